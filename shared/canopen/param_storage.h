// Non-volatile storage of parameters (1010h save / 1011h restore). The port
// supplies byte-addressed storage (EEPROM on the Uno, a file on Linux, RAM in
// tests); the core decides the layout and guards it with a checksum, so a save
// interrupted half-way is detected and ignored: defaults apply instead.
#pragma once
#include <stdint.h>

#include "canopen/od.h"

namespace mb2co {
namespace canopen {

struct ParamStorage {
  bool (*read)(void* ctx, uint16_t offset, uint8_t* data, uint16_t len);
  bool (*write)(void* ctx, uint16_t offset, const uint8_t* data, uint16_t len);
  void* ctx;
};

/// Which rows "save all parameters" keeps: every writable RAM entry except
/// 1010h/1011h themselves and the error history 1003h.
bool param_is_saved(const OdEntry& e);
/// Saves the parameters; false if the storage failed (nothing valid stored then).
bool params_save(const ObjectDictionary& od, const ParamStorage& st);
/// Loads saved parameters of rows with from <= index <= to over the current
/// values; false (and nothing changed) when there is no valid image.
bool params_load(ObjectDictionary& od, const ParamStorage& st, uint16_t from_index,
                 uint16_t to_index);
/// Invalidates the saved image: defaults apply from the next reset (1011h).
bool params_erase(const ParamStorage& st);

}  // namespace canopen
}  // namespace mb2co
