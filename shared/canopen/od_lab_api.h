// The lab API of seed 000 §3.3–3.5, offered on top of ObjectDictionary for
// code written against the course's interface. It is the device's own (local)
// access: entries the network may only read (e.g. inputs 6000h) are writable
// here; const entries are not. Writes of network-writable entries go through
// the same checks and write hooks as an SDO download (so writing 1017h here
// restarts the heartbeat, too).
//
// Sizes are in bytes. Results: 0 on success, a negative OdLabError otherwise.
// Buffers: od_read_object's `data` must hold od_getsize_object() bytes, the
// sub-entries back to back from sub-index 0 (the layout od_write_object takes).
// Not re-entrant: one OD is bound at a time (od_bind), as in the lab.
#pragma once
#include <stdint.h>

#include "canopen/od.h"

namespace mb2co {
namespace canopen {

enum OdLabError : int {
  kOdLabNoObject = -1,    ///< no such index
  kOdLabNoSubentry = -2,  ///< no such sub-index
  kOdLabReadOnly = -3,    ///< a const entry cannot be written
  kOdLabRefused = -4,     ///< the value is out of range or refused by the owning service
  kOdLabTooBig = -5,      ///< more than 255 bytes: does not fit the u8 size
  kOdLabNotBound = -6,    ///< od_bind() was not called
};

/// Makes `od` the dictionary the functions below work on (nullptr unbinds).
void od_bind(ObjectDictionary* od);

int od_getsize_object(uint16_t object_index, uint8_t* size);
int od_getsize_subentry(uint16_t object_index, uint8_t subentry_index, uint8_t* size);
int od_read_object(uint16_t object_index, uint8_t* data, uint8_t* size);
int od_read_subentry(uint16_t object_index, uint8_t subentry_index, uint8_t* data, uint8_t* size);
/// All or nothing: when one sub-entry is refused, none changes and no
/// write hook acts (every sub-entry is decided before any is written).
int od_write_object(uint16_t object_index, const uint8_t* data);
int od_write_subentry(uint16_t object_index, uint8_t subentry_index, const uint8_t* data);

}  // namespace canopen
}  // namespace mb2co
