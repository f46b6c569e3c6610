#include "canopen/frame_out.h"

#include <string.h>

namespace mb2co {
namespace canopen {

bool send_frame(const CanSink& sink, uint16_t id, uint8_t dlc, const uint8_t* data) {
  CanFrame f = {};
  f.id = id;
  f.dlc = dlc;
  if (data != nullptr) memcpy(f.data, data, dlc);
  return sink.send(sink.ctx, f);
}

}  // namespace canopen
}  // namespace mb2co
