// An upload's file, written as the bytes come: under PATH.part, renamed to
// PATH once the transfer completed, removed otherwise (a failed or
// interrupted upload leaves no file, and never a half-written PATH). The
// bytes go through stdio's buffer, so the master's memory stays flat
// however long the object.
#pragma once
#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>

#include "host/status.h"

namespace mb2co {
namespace master {

class PartFile {
 public:
  explicit PartFile(std::string path) : path_(std::move(path)), part_(path_ + ".part") {}
  ~PartFile() { discard(); }
  PartFile(const PartFile&) = delete;
  PartFile& operator=(const PartFile&) = delete;

  /// Creates PATH.part (empty). Fails with "cannot write PATH.part: why".
  Status open();
  /// Appends `n` bytes; false once a write failed (error() says why).
  bool write(const uint8_t* bytes, size_t n);
  /// Closes PATH.part and renames it to PATH. Fails with the first error.
  Status commit();
  /// Closes and removes PATH.part (nothing once committed).
  void discard();
  /// "cannot write PATH.part: No space left on device", "" while none.
  const std::string& error() const { return error_; }
  const std::string& path() const { return path_; }

 private:
  void fail(const std::string& what, int err);

  std::string path_;
  std::string part_;
  std::FILE* file_ = nullptr;
  std::string error_;
};

}  // namespace master
}  // namespace mb2co
