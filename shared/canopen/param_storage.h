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
/// A save of all parameters into the slot not holding the newest valid set,
/// run over many passes of the loop: an EEPROM byte takes 3.3 ms, a whole
/// slot ~1.5 s, which the line must not see as a station gone silent. Each
/// step() writes at most kBytesPerPass bytes, one per ParamStorage::write,
/// and only while ParamStorage::ready allows, then returns.
///
/// Order of the writes into the target slot: its magic made invalid, a
/// barrier, sequence number, length, payload and CRC, a barrier, the magic
/// last, a barrier. Until the last magic byte is written the slot is
/// no set, and the other slot is never touched: power failing at any moment
/// leaves the old set or the new one in force.
///
/// Each entry is copied when its first byte is written, so an entry of up
/// to 4 bytes written by the network during the save is saved whole, old or
/// new (the save keeps each entry as it was when the save reached it).
/// Value-initialised (all zero) = idle. Owned by the Node (NodeState).
class ParamSave {
 public:
  static const uint8_t kBytesPerPass = 16;
  enum Result : uint8_t { kRunning, kDone, kFailed };

  /// Begins a save (nothing is written before the first step()).
  void start(const ObjectDictionary& od, const ParamStorage& st);
  bool running() const { return next_ != 0; }
  /// One pass. kRunning: call again (when the storage is ready); kDone: the
  /// new set is in force; kFailed: the storage failed or the payload does
  /// not fit (the previous set stays in force). Then idle.
  Result step(const ObjectDictionary& od, const ParamStorage& st);

 private:
  /// row_ := the first saved row from `from` on, its bytes into entry_.
  void next_row(const ObjectDictionary& od, uint16_t from);

  uint16_t next_;      ///< 1 + the next byte's place in the write sequence (.cpp); 0 idle
  uint16_t length_;    ///< payload bytes
  uint16_t sequence_;  ///< of the new set
  uint16_t crc_;       ///< over the payload written so far, then over the header too
  uint16_t row_;       ///< the row whose bytes the payload writes now
  uint8_t in_row_;     ///< next byte of row_
  uint8_t slot_;       ///< the target slot (0 or 1)
  uint8_t entry_[4];   ///< row_'s first 4 bytes as the save reached it
};

/// What params_load() found.
enum class ParamLoad : uint8_t {
  kNone,              ///< nothing saved (both slots erased): defaults, nothing to report
  kLoaded,            ///< the newest valid set is loaded
  kLoadedOneDamaged,  ///< the newest valid set is loaded; the other slot is damaged (report it:
                      ///< it may have been the newer one, its sequence number cannot be trusted)
  kDamaged,           ///< no usable set, damage found (report it): defaults
};
inline bool param_set_loaded(ParamLoad r) {
  return r == ParamLoad::kLoaded || r == ParamLoad::kLoadedOneDamaged;
}
inline bool param_damage_found(ParamLoad r) {
  return r == ParamLoad::kLoadedOneDamaged || r == ParamLoad::kDamaged;
}

/// Loads the newest valid set (CRC right, every value within its entry's
/// limits; both slots' CRCs are checked, so a damaged newer slot is reported
/// even where its header claims to be the older) into the rows with from <= index <= to. Without a loaded set
/// the rows may hold some loaded bytes (only when the storage fails to read what it has just read): the
/// caller restores defaults then.
ParamLoad params_load(ObjectDictionary& od, const ParamStorage& st, uint16_t from_index, uint16_t to_index);
/// Invalidates both slots: defaults apply from the next reset (1011h).
bool params_erase(const ParamStorage& st);

}  // namespace canopen
}  // namespace mb2co
