// Non-volatile storage of parameters (1010h save / 1011h restore). The port
// supplies byte-addressed storage (EEPROM on the Uno, a file on Linux, RAM in
// tests); the core decides the layout: two slots, each guarded by a CRC, the
// newer valid one in force. A save interrupted at any point leaves the
// previous set loadable; a damaged slot is detected and reported.
#pragma once
#include <stdint.h>

#include "canopen/od.h"
#include "platform/device_port.h"  // ParamStorage: what the port supplies

namespace mb2co {
namespace canopen {

/// Which rows "save all parameters" keeps: every writable RAM entry except
/// 1010h/1011h themselves, the error history 1003h and commands and process
/// values (kAttrCommand): a saved RUN command would start a station at
/// power-up with nobody watching it.
bool param_is_saved(const ObjectDictionary& od, uint16_t row);
/// Saves the parameters into the slot not holding the newest valid set; false
/// if the storage failed (the previous set stays in force then).
bool params_save(ObjectDictionary& od, const ParamStorage& st);

/// What params_load() found.
enum class ParamLoad : uint8_t {
  kNone,              ///< nothing saved (both slots erased): defaults, nothing to report
  kLoaded,            ///< the newest valid set is loaded
  kLoadedOneDamaged,  ///< a set is loaded; the other slot is damaged (report it)
  kDamaged,           ///< no usable set, damage found (report it): defaults
};
inline bool param_set_loaded(ParamLoad r) {
  return r == ParamLoad::kLoaded || r == ParamLoad::kLoadedOneDamaged;
}
inline bool param_damage_found(ParamLoad r) {
  return r == ParamLoad::kLoadedOneDamaged || r == ParamLoad::kDamaged;
}

/// Loads the newest valid set (CRC right, every value within its entry's
/// limits) into the rows with from <= index <= to. Without a loaded set the
/// rows may hold some loaded bytes (only when the storage fails to read what
/// it has just read): the caller restores defaults then.
ParamLoad params_load(ObjectDictionary& od, const ParamStorage& st, uint16_t from_index, uint16_t to_index);
/// Invalidates both slots: defaults apply from the next reset (1011h).
bool params_erase(const ParamStorage& st);

}  // namespace canopen
}  // namespace mb2co
