// Where the gateway's Modbus registers are: the addresses of the OD entries
// the app reads and writes, located by the register map (gateway/register_map.h)
// in the maps 2400h (holding registers) and 2401h (input registers) of the
// gateway OD this app is linked with. So the app follows the firmware's
// default map by construction; tests check the result against
// docs/register-map.md.
#pragma once
#include <stdint.h>

#include <string>
#include <vector>

#include "plant/station_fields.h"

namespace mb2co {
namespace canopen {
class ObjectDictionary;
}

namespace pcapp {

/// The OD entries the app uses: the station's fields (shared/plant).
using plant::Field;
using plant::field_spec;
using plant::FieldSpec;
using plant::kFieldCount;

enum class RegTable : uint8_t { kNone = 0, kHolding = 1, kInput = 2 };

/// Where one field is: none when neither register map holds it.
struct Location {
  RegTable table = RegTable::kNone;
  uint16_t address = 0;
  uint8_t width = 0;  ///< registers: 1, or 2 for a 32-bit entry
};

struct RegisterLayout {
  Location at[kFieldCount];
  /// Per table (index holding / input): true for every mapped address, in
  /// address order. Reading across a mapped address we do not need is fine;
  /// an unmapped one would be exception 02.
  std::vector<bool> mapped[2];
  /// Writable (rw OD entry) per holding address.
  std::vector<bool> writable;

  const Location& operator[](Field f) const { return at[static_cast<int>(f)]; }
};

/// Reads the maps 2400h and 2401h of a gateway OD. Holding registers win
/// when an entry is mapped in both tables (FC 17h can then reach it).
RegisterLayout layout_from_od(const canopen::ObjectDictionary& od);
/// The layout of the gateway OD's defaults (the firmware's default map).
RegisterLayout default_layout();

}  // namespace pcapp
}  // namespace mb2co
