#include "gateway/register_map.h"

namespace mb2co {
namespace gateway {

OdMapEntries::OdMapEntries(const canopen::ObjectDictionary& od, modbus::Table table)
    : od_(&od), row0_(od.find(map_index(table), 0)), count_(0) {
  if (row0_ == canopen::ObjectDictionary::kNoRow) return;
  const uint32_t count = od.get(row0_);
  // The rows of one index are contiguous: sub k is row0 + k up to the capacity.
  const uint8_t capacity = map_capacity(table);
  count_ = static_cast<uint8_t>(count < capacity ? count : capacity);
}

MapItem locate(const canopen::ObjectDictionary& od, modbus::Table table, canopen::OdKey key) {
  return locate_in(OdMapEntries(od, table), is_bit_table(table), key);
}

}  // namespace gateway
}  // namespace mb2co
