// A CAN frame to hand to UnoRig::can_in in the in-process tests of the images.
#pragma once
#include <stddef.h>
#include <stdint.h>

#include <vector>

#include "uno_rig.h"

namespace mb2co {
namespace uno {

/// A data frame with 11-bit `id` and `data` (at most 8 bytes).
inline CanFrame rig_frame(uint32_t id, const std::vector<uint8_t>& data) {
  CanFrame f{};
  f.id = id;
  f.dlc = static_cast<uint8_t>(data.size());
  for (size_t i = 0; i < data.size(); ++i) f.data[i] = data[i];
  return f;
}

}  // namespace uno
}  // namespace mb2co
