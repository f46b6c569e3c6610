// Saved parameters (1010h) in a file of 1 KiB, like the Uno's EEPROM: read
// and written in place, fsync'ed around writes of the image's header (offset
// 0), so a saved image survives a restart and a crash never leaves a header
// that declares a payload valid before the payload is on disk.
#pragma once
#include <string>

#include "canopen/param_storage.h"

namespace mb2co {
namespace node {

class EepromFile {
 public:
  static const uint16_t kSize = 1024;
  explicit EepromFile(const std::string& path) : path_(path) {}
  canopen::ParamStorage storage() { return canopen::ParamStorage{&EepromFile::read, &EepromFile::write, this}; }

 private:
  static bool read(void* ctx, uint16_t offset, uint8_t* data, uint16_t len);
  static bool write(void* ctx, uint16_t offset, const uint8_t* data, uint16_t len);
  std::string path_;
};

}  // namespace node
}  // namespace mb2co
