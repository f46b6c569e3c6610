// Human-readable CANopen: a frame as in the seeds' traces ("<583> 42 00 10
// 00 91 01 03 00") and what it means under the predefined connection set
// ("SDO response node 3: upload 1000h/00 = 00030191h"). Host-only.
#pragma once
#include <string>

#include "canopen/can_frame.h"

namespace mb2co {
namespace hil {

std::string frame_bytes(const CanFrame& f);
std::string describe(const CanFrame& f);

}  // namespace hil
}  // namespace mb2co
