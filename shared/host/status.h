// The one result type of host code outside the core: the Linux ports
// (serial, SocketCAN, mb2co-node's options), pcapp/ and hil/: done, or failed
// with one line saying why. Host-only (std::string): the portable core reports
// with canopen::SdoAbort instead. A value, not a member
// holding the last error, so a caller cannot read a reason that belongs to an
// earlier call, and a free function reports the same way an object does.
// Failures of the hot path (each frame sent or received) are not Statuses but
// counters (SocketCanCounters), as in the core.
#pragma once
#include <string>
#include <utility>

namespace mb2co {

class Status {
 public:
  /// Done.
  Status() = default;
  static Status ok() { return Status(); }
  /// Failed; `why` is one line without a newline, meant for a human (stderr).
  static Status failure(std::string why) {
    Status s;
    s.failed_ = true;
    s.message_ = std::move(why);
    return s;
  }

  bool is_ok() const { return !failed_; }
  explicit operator bool() const { return !failed_; }
  /// Why it failed ("" when done).
  const std::string& message() const { return message_; }

 private:
  bool failed_ = false;
  std::string message_;
};

}  // namespace mb2co
