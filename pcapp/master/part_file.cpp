#include "part_file.h"

#include <cerrno>
#include <cstring>

namespace mb2co {
namespace master {

void PartFile::fail(const std::string& what, int err) {
  if (error_.empty()) error_ = "cannot write " + what + ": " + std::strerror(err);
}

Status PartFile::open() {
  file_ = std::fopen(part_.c_str(), "wb");
  if (!file_) {
    fail(part_, errno);
    return Status::failure(error_);
  }
  return Status::ok();
}

bool PartFile::write(const uint8_t* bytes, size_t n) {
  if (!file_ || !error_.empty()) return false;
  if (std::fwrite(bytes, 1, n, file_) != n) {
    fail(part_, errno);
    return false;
  }
  return true;
}

Status PartFile::commit() {
  if (!file_) return Status::failure(error_.empty() ? "cannot write " + part_ + ": not open" : error_);
  const int closed = std::fclose(file_);
  file_ = nullptr;
  if (closed != 0) fail(part_, errno);
  if (error_.empty() && std::rename(part_.c_str(), path_.c_str()) != 0) fail(path_, errno);
  if (error_.empty()) return Status::ok();
  std::remove(part_.c_str());
  return Status::failure(error_);
}

void PartFile::discard() {
  if (!file_) return;
  std::fclose(file_);
  file_ = nullptr;
  std::remove(part_.c_str());
}

}  // namespace master
}  // namespace mb2co
