// The Uno's 1 KiB EEPROM kept in a file between runs of mb2co-uno (a saved
// node id survives a restart, as on the board). A missing file is an erased
// EEPROM (all 0xFF); a file of any other size than 1 KiB is refused. Saving
// writes a temporary file and renames it over the old one: a crash leaves
// the old image or the new one, never half of each.
#pragma once
#include <stddef.h>
#include <stdint.h>

#include <string>

#include "host/status.h"

namespace mb2co {
namespace uno {

class EepromImage {
 public:
  static constexpr size_t kBytes = 1024;

  explicit EepromImage(std::string path) : path_(std::move(path)) {}

  /// Reads the file (or starts erased when it does not exist). Fails for a
  /// file of the wrong size or one that cannot be read.
  Status load();
  /// Writes the bytes back.
  Status save() const;

  uint8_t* bytes() { return bytes_; }
  size_t size() const { return kBytes; }

 private:
  std::string path_;
  uint8_t bytes_[kBytes];
};

}  // namespace uno
}  // namespace mb2co
