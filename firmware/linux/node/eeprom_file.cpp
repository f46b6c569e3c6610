#include "eeprom_file.h"

#include <errno.h>
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <chrono>
#include <cstring>

namespace mb2co {
namespace node {
namespace {

int64_t steady_us() {
  return std::chrono::duration_cast<std::chrono::microseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

}  // namespace

bool EepromFile::ready(void* ctx) {
  return steady_us() >= static_cast<EepromFile*>(ctx)->busy_until_us_;
}

bool EepromFile::read(void* ctx, uint16_t offset, uint8_t* data, uint16_t len) {
  const EepromFile& e = *static_cast<EepromFile*>(ctx);
  if (offset + len > kSize) return false;
  // What the file does not hold (never written: it grows with the saves, or
  // it was cut) reads as an erased EEPROM cell does: FFh. So a file cut
  // inside a set fails that set's CRC, like damaged EEPROM bytes would.
  std::memset(data, 0xFF, len);
  const int fd = open(e.path_.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return errno == ENOENT;  // never saved: all erased
  const ssize_t n = pread(fd, data, len, offset);
  close(fd);
  if (n > 0 && n < len) std::memset(data + n, 0xFF, static_cast<size_t>(len - n));
  return n >= 0;
}

bool EepromFile::write(void* ctx, uint16_t offset, const uint8_t* data, uint16_t len) {
  EepromFile& e = *static_cast<EepromFile*>(ctx);
  if (offset + len > kSize) return false;
  if (e.write_us_ != 0) e.busy_until_us_ = steady_us() + static_cast<int64_t>(e.write_us_) * len;
  const int fd = open(e.path_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd < 0) return false;
  bool ok = pwrite(fd, data, len, offset) == len;
  ok = close(fd) == 0 && ok;
  return ok;
}

Status EepromFile::usable() const {
  struct stat st;
  if (stat(path_.c_str(), &st) == 0) {
    // Checked by its mode, not by access(): as root a read-only file would
    // pass access(W_OK), and a node must not overwrite what was set read-only.
    if (!S_ISREG(st.st_mode)) return Status::failure(path_ + ": not a regular file");
    if ((st.st_mode & (S_IWUSR | S_IWGRP | S_IWOTH)) == 0)
      return Status::failure(path_ + ": read-only file, saves would fail");
  }
  const int fd = open(path_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd < 0)
    return Status::failure(path_ + ": cannot open for reading and writing: " + std::strerror(errno));
  close(fd);
  return Status::ok();
}

bool EepromFile::barrier(void* ctx) {
  const EepromFile& e = *static_cast<EepromFile*>(ctx);
  const int fd = open(e.path_.c_str(), O_RDWR | O_CLOEXEC);
  if (fd < 0) return false;
  bool ok = fsync(fd) == 0;
  ok = close(fd) == 0 && ok;
  return ok;
}

}  // namespace node
}  // namespace mb2co
