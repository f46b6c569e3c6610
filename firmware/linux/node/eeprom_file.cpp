#include "eeprom_file.h"

#include <fcntl.h>
#include <unistd.h>

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
  // The image's header is at offset 0 and is written twice by a save
  // (params_save): first invalidated, last made valid. Syncing around those
  // writes only keeps the order that matters (invalid before the payload
  // changes, payload durable before the header says it is valid) with ~3
  // fsyncs per save instead of one per entry (~150: over a second on a busy
  // machine, longer than a Modbus master waits for the answer to "save").
  const bool barrier = offset == 0;
  bool ok = (!barrier || fsync(fd) == 0) && pwrite(fd, data, len, offset) == len && (!barrier || fsync(fd) == 0);
  ok = close(fd) == 0 && ok;
  return ok;
}

}  // namespace node
}  // namespace mb2co
