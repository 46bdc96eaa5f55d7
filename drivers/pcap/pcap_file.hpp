// Reading and writing pcap/pcapng recordings through libpcap. Record times are
// host arrival times, kept at nanosecond precision.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

struct pcap;
struct pcap_dumper;

namespace tumble::pcap {

// Link types we read or write (tcpdump's LINKTYPE_ numbers).
inline constexpr int kLinkEthernet = 1;
inline constexpr int kLinkRawIpv4 = 228;
inline constexpr int kLinkRaw = 101;
inline constexpr int kLinkLinuxSll = 113;
inline constexpr int kLinkLinuxSll2 = 276;
inline constexpr int kLinkUser0 = 147;

struct Record {
  std::int64_t t_ns = 0;            // arrival time, CLOCK_REALTIME
  std::uint32_t original_length = 0;  // length on the wire (may exceed bytes when truncated)
  std::span<const std::uint8_t> bytes;  // valid until the next call to next()
};

class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class Reader {
 public:
  // Throws Error naming the file and libpcap's reason when it cannot be opened.
  explicit Reader(const std::string& path);
  ~Reader();
  Reader(const Reader&) = delete;
  Reader& operator=(const Reader&) = delete;

  int link_type() const { return link_type_; }
  const std::string& path() const { return path_; }
  // The next record, or nullopt at the end. A truncated or corrupt file ends
  // the stream; truncated() then says so.
  std::optional<Record> next();
  bool truncated() const { return !error_.empty(); }
  const std::string& error() const { return error_; }

 private:
  std::string path_;
  ::pcap* handle_ = nullptr;
  int link_type_ = 0;
  std::string error_;
};

class Writer {
 public:
  // Creates (truncates) path; throws Error when it cannot.
  Writer(const std::string& path, int link_type, std::uint32_t snap_length = 65535);
  ~Writer();
  Writer(const Writer&) = delete;
  Writer& operator=(const Writer&) = delete;

  void write(std::int64_t t_ns, std::span<const std::uint8_t> bytes);
  // Pushes buffered records to the file so a crash loses at most what came after.
  void flush();
  // Flushes and syncs to the disk (fdatasync): 0, or the errno that failed
  // (ENOSPC: the disk is full; a write() that failed before is reported here).
  int sync();
  // True once a write or flush failed (the records after it may be missing).
  bool failed() const;
  // The file's size so far, buffered records included.
  std::int64_t bytes() const;
  void close();

 private:
  std::string path_;
  ::pcap* dead_ = nullptr;
  ::pcap_dumper* dumper_ = nullptr;
};

}  // namespace tumble::pcap
