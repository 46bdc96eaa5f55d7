// Replays a recorded IMU serial stream: our pcap (LINKTYPE_USER0, one record
// per serial read, arrival times) or a plain Xsens byte stream (.mtb-like raw
// frames, no arrival times: sample times come from SampleTimeFine + epoch).
// Bad input never aborts: it is counted, and problem() says what was wrong.
#pragma once

#include <array>
#include <cstdint>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "core/types.hpp"
#include "drivers/mti/mti_stream.hpp"
#include "drivers/pcap/pcap_file.hpp"

namespace tumble::mti {

enum class RecordingFormat : std::uint8_t { Pcap, RawBytes };

class ImuRecordingReader {
 public:
  // Tells the formats apart by the pcap/pcapng magic. Throws std::runtime_error
  // naming the file when it cannot be opened or is a pcap of another link type.
  ImuRecordingReader(const std::string& path, MtiStreamOptions options);

  // Decodes the next serial read (pcap record or raw chunk) and appends its
  // samples to out. False at the end of the file.
  bool next(std::vector<ImuSample>& out);
  // See MtiStream::SampleObserver; called for each sample as next() appends it.
  void set_sample_observer(MtiStream::SampleObserver observer) { stream_.set_sample_observer(std::move(observer)); }

  RecordingFormat format() const { return format_; }
  const MtiStats& stats() const { return stream_.stats(); }
  std::uint64_t reads() const { return reads_; }
  std::uint64_t short_records() const { return short_records_; }  // pcap records cut by the snap length
  // Empty for a clean file, else what was wrong (truncation, bytes that are
  // not an MTi stream, bad frames): meaningful once next() returned false.
  std::string problem() const;

 private:
  bool end(std::vector<ImuSample>& out);

  std::string path_;
  RecordingFormat format_ = RecordingFormat::RawBytes;
  MtiStream stream_;
  std::unique_ptr<pcap::Reader> pcap_;
  std::ifstream raw_;
  std::array<std::uint8_t, 4096> chunk_{};
  std::uint64_t reads_ = 0;
  std::uint64_t short_records_ = 0;
  bool ended_ = false;
};

}  // namespace tumble::mti
