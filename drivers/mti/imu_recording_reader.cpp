#include "drivers/mti/imu_recording_reader.hpp"

#include <stdexcept>

namespace tumble::mti {
namespace {

bool starts_like_pcap(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  std::array<unsigned char, 4> m{};
  if (!f.read(reinterpret_cast<char*>(m.data()), m.size())) return false;
  const std::uint32_t le = m[0] | (m[1] << 8) | (m[2] << 16) | (std::uint32_t{m[3]} << 24);
  // Classic pcap (µs and ns, either byte order) and pcapng's section header.
  return le == 0xA1B2C3D4 || le == 0xD4C3B2A1 || le == 0xA1B23C4D || le == 0x4D3CB2A1 || le == 0x0A0D0D0A;
}

}  // namespace

ImuRecordingReader::ImuRecordingReader(const std::string& path, MtiStreamOptions options)
    : path_(path), stream_(options) {
  if (starts_like_pcap(path)) {
    format_ = RecordingFormat::Pcap;
    try {
      pcap_ = std::make_unique<pcap::Reader>(path);
    } catch (const pcap::Error& e) {
      throw std::runtime_error(e.what());
    }
    if (pcap_->link_type() != pcap::kLinkUser0)
      throw std::runtime_error(path + ": link type " + std::to_string(pcap_->link_type()) +
                               " is not LINKTYPE_USER0 (147): not an IMU serial recording");
    return;
  }
  raw_.open(path, std::ios::binary);
  if (!raw_) throw std::runtime_error("cannot read IMU recording " + path);
}

bool ImuRecordingReader::end(std::vector<ImuSample>& out) {
  ended_ = true;
  const std::size_t before = out.size();
  stream_.finish(out);
  return out.size() > before;
}

bool ImuRecordingReader::next(std::vector<ImuSample>& out) {
  if (ended_) return false;
  if (pcap_) {
    const auto record = pcap_->next();
    if (!record) return end(out);
    ++reads_;
    if (record->bytes.size() < record->original_length) ++short_records_;
    stream_.feed(record->bytes, static_cast<double>(record->t_ns) * 1e-9, out);
    return true;
  }
  raw_.read(reinterpret_cast<char*>(chunk_.data()), static_cast<std::streamsize>(chunk_.size()));
  const auto n = static_cast<std::size_t>(raw_.gcount());
  if (n == 0) return end(out);
  ++reads_;
  stream_.feed_untimed(std::span<const std::uint8_t>(chunk_.data(), n), out);
  return true;
}

std::string ImuRecordingReader::problem() const {
  std::string problems;
  const auto add = [&problems](const std::string& p) { problems += (problems.empty() ? "" : "; ") + p; };
  if (pcap_ && pcap_->truncated()) add("truncated: " + pcap_->error());
  if (short_records_ > 0) add(std::to_string(short_records_) + " records cut short by the snap length");
  const MtiStats& s = stream_.stats();
  if (s.frames.frames == 0 && s.frames.bytes > 0) {
    add("no Xbus frame in " + std::to_string(s.frames.bytes) + " bytes: not an MTi stream");
  } else {
    // A pcap holds whole serial reads, and a recording stops between two of
    // them wherever that falls (tumbled --record and Ctrl-C): its last frame
    // cut off is where it stopped, as its first is where it started. A pcap
    // cut inside a record is reported above; a raw stream cut inside a frame
    // is a truncated file.
    if (s.frames.cut_off > 0 && !pcap_) add("truncated: the stream ends inside a frame");
    // Stray bytes and preambles are normal (recordings start mid-frame);
    // failed checksums and impossible lengths are corruption.
    const std::uint64_t corrupt = s.frames.bad_checksum + s.frames.bad_length;
    if (corrupt > 0)
      add(std::to_string(corrupt) + " corrupt frames skipped (checksum " + std::to_string(s.frames.bad_checksum) +
          ", length " + std::to_string(s.frames.bad_length) + "), " + std::to_string(s.frames.bytes_discarded) +
          " bytes discarded");
  }
  if (s.mtdata2.truncated_messages > 0)
    add(std::to_string(s.mtdata2.truncated_messages) + " MTData2 messages with a cut packet chain");
  return problems.empty() ? std::string{} : path_ + ": " + problems;
}

}  // namespace tumble::mti
