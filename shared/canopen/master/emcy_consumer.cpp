#include "canopen/master/emcy_consumer.h"

#include <string.h>

namespace mb2co {
namespace canopen {

bool emcy_decode(const CanFrame& f, uint8_t* node_id, EmcyMessage* out) {
  if (f.rtr() || f.extended() || f.id <= 0x080u || f.id > 0x0FFu || f.dlc != 8) return false;
  *node_id = static_cast<uint8_t>(f.id - 0x080u);
  out->code = static_cast<uint16_t>(f.data[0] | (f.data[1] << 8));
  out->error_register = f.data[2];
  memcpy(out->manufacturer, &f.data[3], sizeof out->manufacturer);
  return true;
}

}  // namespace canopen
}  // namespace mb2co
