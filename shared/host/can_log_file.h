// A CAN trace written while a program runs: `candump -L` lines (canplayer,
// Wireshark, SavvyCAN), or pcap with LINKTYPE_CAN_SOCKETCAN when the path
// ends in ".pcap" (host/pcap_can.h). Host-only (stdio, std::string).
// Write failures after open are counted, not reported per frame: a trace
// must never stop the program it watches.
#pragma once
#include <errno.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>

#include <string>

#include "canopen/can_frame.h"
#include "host/candump_text.h"
#include "host/pcap_can.h"
#include "host/status.h"

namespace mb2co {

class CanLogFile {
 public:
  CanLogFile() = default;
  ~CanLogFile() { close(); }
  CanLogFile(const CanLogFile&) = delete;
  CanLogFile& operator=(const CanLogFile&) = delete;

  /// Creates (or empties) `path`; pcap when it ends in ".pcap" (the file
  /// header is written at once), else text with `iface` on every line.
  /// Fails with one line naming the path.
  Status open(const std::string& path, const std::string& iface) {
    close();
    pcap_ = is_pcap_path(path);
    iface_ = iface;
    file_ = fopen(path.c_str(), pcap_ ? "wbe" : "we");
    if (file_ == nullptr) return Status::failure(path + ": " + strerror(errno));
    if (pcap_) put(pcap_can_file_header());
    return Status::ok();
  }
  bool is_open() const { return file_ != nullptr; }
  bool pcap() const { return pcap_; }

  /// One frame seen at t_us (µs since the epoch, as candump stamps).
  void write(uint64_t t_us, const CanFrame& frame) {
    if (file_ == nullptr) return;
    put(pcap_ ? pcap_can_record(t_us, frame) : candump_log_line(t_us, iface_, frame));
    ++frames_;
  }
  /// Hands what is buffered to the kernel (a reader sees whole lines).
  void flush() {
    if (file_ != nullptr && fflush(file_) != 0) ++write_errors_;
  }
  void close() {
    if (file_ == nullptr) return;
    if (fclose(file_) != 0) ++write_errors_;
    file_ = nullptr;
  }
  uint64_t frames() const { return frames_; }
  uint64_t write_errors() const { return write_errors_; }

 private:
  void put(const std::string& bytes) {
    if (fwrite(bytes.data(), 1, bytes.size(), file_) != bytes.size()) ++write_errors_;
  }

  FILE* file_ = nullptr;
  bool pcap_ = false;
  std::string iface_;
  uint64_t frames_ = 0;
  uint64_t write_errors_ = 0;
};

}  // namespace mb2co
