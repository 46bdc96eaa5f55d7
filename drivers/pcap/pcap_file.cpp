#include "drivers/pcap/pcap_file.hpp"

#include <pcap/pcap.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>

namespace tumble::pcap {

Reader::Reader(const std::string& path) : path_(path) {
  char errbuf[PCAP_ERRBUF_SIZE] = {0};
  handle_ = pcap_open_offline_with_tstamp_precision(path.c_str(), PCAP_TSTAMP_PRECISION_NANO, errbuf);
  if (handle_ == nullptr) throw Error("cannot read recording " + path + ": " + errbuf);
  link_type_ = pcap_datalink(handle_);
}

Reader::~Reader() {
  if (handle_ != nullptr) pcap_close(handle_);
}

std::optional<Record> Reader::next() {
  if (handle_ == nullptr) return std::nullopt;
  pcap_pkthdr* header = nullptr;
  const u_char* data = nullptr;
  const int rc = pcap_next_ex(handle_, &header, &data);
  if (rc == 1) {
    Record r;
    r.t_ns = static_cast<std::int64_t>(header->ts.tv_sec) * 1'000'000'000 + header->ts.tv_usec;
    r.original_length = header->len;
    r.bytes = {data, header->caplen};
    return r;
  }
  if (rc == PCAP_ERROR) error_ = path_ + ": " + pcap_geterr(handle_);
  pcap_close(handle_);
  handle_ = nullptr;
  return std::nullopt;
}

Writer::Writer(const std::string& path, int link_type, std::uint32_t snap_length) : path_(path) {
  dead_ = pcap_open_dead_with_tstamp_precision(link_type, static_cast<int>(snap_length),
                                               PCAP_TSTAMP_PRECISION_NANO);
  if (dead_ == nullptr) throw Error("cannot create a pcap writer for " + path);
  dumper_ = pcap_dump_open(dead_, path.c_str());
  if (dumper_ == nullptr) {
    const std::string reason = pcap_geterr(dead_);
    pcap_close(dead_);
    dead_ = nullptr;
    throw Error("cannot write recording " + path + ": " + reason);
  }
}

Writer::~Writer() { close(); }

void Writer::write(std::int64_t t_ns, std::span<const std::uint8_t> bytes) {
  if (dumper_ == nullptr) throw Error("write to closed recording " + path_);
  pcap_pkthdr header{};
  header.ts.tv_sec = static_cast<time_t>(t_ns / 1'000'000'000);
  // With nanosecond precision libpcap stores tv_usec as nanoseconds.
  header.ts.tv_usec = static_cast<suseconds_t>(t_ns % 1'000'000'000);
  header.caplen = static_cast<bpf_u_int32>(bytes.size());
  header.len = static_cast<bpf_u_int32>(bytes.size());
  pcap_dump(reinterpret_cast<u_char*>(dumper_), &header, bytes.data());
}

void Writer::flush() {
  if (dumper_ != nullptr && pcap_dump_flush(dumper_) != 0) throw Error("cannot flush recording " + path_);
}

int Writer::sync() {
  if (dumper_ == nullptr) return EBADF;
  std::FILE* file = pcap_dump_file(dumper_);
  if (std::fflush(file) != 0 || std::ferror(file) != 0) return errno != 0 ? errno : EIO;
  return ::fdatasync(::fileno(file)) == 0 ? 0 : errno;
}

bool Writer::failed() const { return dumper_ == nullptr || std::ferror(pcap_dump_file(dumper_)) != 0; }

std::int64_t Writer::bytes() const { return dumper_ == nullptr ? 0 : pcap_dump_ftell64(dumper_); }

void Writer::close() {
  if (dumper_ != nullptr) {
    pcap_dump_close(dumper_);
    dumper_ = nullptr;
  }
  if (dead_ != nullptr) {
    pcap_close(dead_);
    dead_ = nullptr;
  }
}

}  // namespace tumble::pcap
