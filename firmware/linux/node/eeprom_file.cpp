#include "eeprom_file.h"

#include <errno.h>
#include <fcntl.h>
#include <unistd.h>

#include <cstring>

namespace mb2co {
namespace node {

bool EepromFile::read(void* ctx, uint16_t offset, uint8_t* data, uint16_t len) {
  const EepromFile& e = *static_cast<EepromFile*>(ctx);
  if (offset + len > kSize) return false;
  const int fd = open(e.path_.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return false;  // never saved: no image
  const ssize_t n = pread(fd, data, len, offset);
  close(fd);
  return n == len;
}

bool EepromFile::write(void* ctx, uint16_t offset, const uint8_t* data, uint16_t len) {
  const EepromFile& e = *static_cast<EepromFile*>(ctx);
  if (offset + len > kSize) return false;
  const int fd = open(e.path_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd < 0) return false;
  bool ok = pwrite(fd, data, len, offset) == len;
  ok = close(fd) == 0 && ok;
  return ok;
}

bool EepromFile::usable(std::string* reason) const {
  const int fd = open(path_.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (fd < 0) {
    *reason = path_ + ": cannot open for reading and writing: " + std::strerror(errno);
    return false;
  }
  close(fd);
  return true;
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
