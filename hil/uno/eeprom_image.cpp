#include "eeprom_image.h"

#include <errno.h>
#include <fcntl.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

namespace mb2co {
namespace uno {

Status EepromImage::load() {
  memset(bytes_, 0xFF, kBytes);
  const int fd = open(path_.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) {
    if (errno == ENOENT) return Status::ok();  // erased, as a new chip
    return Status::failure("eeprom " + path_ + ": " + strerror(errno));
  }
  struct stat st {};
  const bool sized = fstat(fd, &st) == 0 && S_ISREG(st.st_mode) && st.st_size == static_cast<off_t>(kBytes);
  const bool read_ok = sized && read(fd, bytes_, kBytes) == static_cast<ssize_t>(kBytes);
  close(fd);
  if (!sized) {
    return Status::failure("eeprom " + path_ + ": not a file of " + std::to_string(kBytes) + " bytes");
  }
  if (!read_ok) {
    return Status::failure("eeprom " + path_ + ": read failed");
  }
  return Status::ok();
}

Status EepromImage::save() const {
  const std::string tmp = path_ + ".tmp";
  const int fd = open(tmp.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  bool ok = fd >= 0 && write(fd, bytes_, kBytes) == static_cast<ssize_t>(kBytes);
  if (fd >= 0) ok = fsync(fd) == 0 && ok;
  if (fd >= 0) ok = close(fd) == 0 && ok;
  if (ok) ok = rename(tmp.c_str(), path_.c_str()) == 0;
  if (ok) return Status::ok();
  Status failed = Status::failure("eeprom " + path_ + ": cannot write: " + strerror(errno));
  unlink(tmp.c_str());
  return failed;
}

}  // namespace uno
}  // namespace mb2co
