// libFuzzer target for the MTi driver: frame reader, MTData2 decoder, the
// whole stream (sequence checks and time mapping) and the configurator on
// arbitrary bytes. Any out-of-bounds read or UB is a crash under ASan+UBSan.
#include <cstddef>
#include <cstdint>
#include <span>
#include <stdexcept>
#include <vector>

#include "drivers/mti/commands.hpp"
#include "drivers/mti/configurator.hpp"
#include "drivers/mti/frame_reader.hpp"
#include "drivers/mti/imu_sample.hpp"
#include "drivers/mti/message_ids.hpp"
#include "drivers/mti/mtdata2_decode.hpp"
#include "drivers/mti/mti_stream.hpp"
#include "drivers/mti/output_configuration.hpp"

using namespace tumble;
using namespace tumble::mti;

namespace {

void decode_payload(std::span<const std::uint8_t> payload) {
  MtData2 m;
  MtData2DecodeStats stats;
  if (!decode_mtdata2(payload, m, stats)) return;
  ImuSample s;
  fill_imu_sample(m, 0.01, s);
}

void parse_reply(const XbusFrame& f, Configurator& configurator, double t_s) {
  switch (f.mid) {
    case mid::kMtData2: decode_payload(f.payload); break;
    case mid::kOutputConfiguration:
      try {
        parse_output_configuration(f.payload);
      } catch (const std::invalid_argument&) {
      }
      break;
    case mid::kDeviceId: parse_device_id(f.payload); break;
    case mid::kFirmwareRev: parse_firmware_revision(f.payload); break;
    case mid::kProductCode: ranges_from_product_code(parse_product_code(f.payload)); break;
    default: break;
  }
  configurator.on_frame(f, t_s);
  configurator.on_tick(t_s);
  configurator.take_output();
  configurator.take_baud_switch();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::span<const std::uint8_t> bytes(data, size);
  decode_payload(bytes);  // the decoder without needing a checksum first
  if (size == 0) return 0;

  // Serial reads of a size the input chooses.
  const std::size_t chunk = 1 + data[0] % 97;
  FrameReader reader;
  Configurator configurator(ConfiguratorOptions{});
  configurator.start(0);
  MtiStream stream;
  std::vector<ImuSample> samples;
  double t_s = 1.7e9;
  for (std::size_t pos = 1; pos < size; pos += chunk) {
    const auto read = bytes.subspan(pos, std::min(chunk, size - pos));
    t_s += 0.001 * (read[0] % 16);
    stream.feed(read, t_s, samples);
    reader.push(read);
    while (const auto f = reader.next()) parse_reply(*f, configurator, t_s - 1.7e9);
  }
  reader.finish();
  while (const auto f = reader.next()) parse_reply(*f, configurator, t_s - 1.7e9);
  stream.finish(samples);
  return 0;
}
