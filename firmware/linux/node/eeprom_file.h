// Saved parameters (1010h) in a file of 1 KiB, like the Uno's EEPROM: read
// and written in place; the core's barriers (ParamStorage::barrier) are
// fsyncs, so a crash never leaves a header that declares a payload valid
// before the payload is on disk (a few per save, not one per entry: ~150
// fsyncs took longer than a Modbus master waits for the answer to "save").
// The file grows with the saves; bytes it does not hold read as FFh, as an
// erased EEPROM cell does, so a cut file is one whose tail is erased.
// A save writes its bytes one per call, ParamSave::kBytesPerPass per pass
// of the loop, like on the Uno. Always ready unless a write time per byte is
// set (--eeprom-write-us): then ParamStorage::ready says no until that long
// after the last byte written, as the Uno's EEPROM (3.3 ms per byte) does,
// so a save takes as long as on the board (a master must poll 1010h/1).
#pragma once
#include <string>

#include "canopen/param_storage.h"
#include "host/status.h"

namespace mb2co {
namespace node {

class EepromFile {
 public:
  static const uint16_t kSize = 1024;
  /// `write_us`: time one byte takes to program (0: none).
  explicit EepromFile(const std::string& path, uint32_t write_us = 0) : path_(path), write_us_(write_us) {}
  canopen::ParamStorage storage() {
    return canopen::ParamStorage{&EepromFile::read, &EepromFile::write, &EepromFile::barrier, this,
                                 write_us_ != 0 ? &EepromFile::ready : nullptr};
  }

 private:
  static bool read(void* ctx, uint16_t offset, uint8_t* data, uint16_t len);
  static bool ready(void* ctx);
  static bool write(void* ctx, uint16_t offset, const uint8_t* data, uint16_t len);
  static bool barrier(void* ctx);

 public:
  /// Fails, with a one-line reason, when the file cannot be read and
  /// written (a directory or another non-regular file, a file without write
  /// permission, a missing directory): a node must not run with parameters
  /// it could never save. Creates an empty file (nothing saved) if none.
  Status usable() const;

 private:
  std::string path_;
  uint32_t write_us_;
  int64_t busy_until_us_ = 0;  ///< steady clock: the last byte is programmed then
};

}  // namespace node
}  // namespace mb2co
