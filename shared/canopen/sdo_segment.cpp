#include "canopen/sdo_segment.h"

#include <string.h>

#include "canopen/frame_out.h"
#include "canopen/od.h"

namespace mb2co {
namespace canopen {

void send_sdo(const CanSink& sink, uint8_t cmd, const uint8_t* bytes, uint8_t n, uint16_t cob_id) {
  uint8_t d[8] = {cmd, 0, 0, 0, 0, 0, 0, 0};
  if (n != 0) memcpy(&d[1], bytes, n);
  send_frame(sink, cob_id, 8, d);
}

void sdo_mux_bytes(uint8_t* out, uint16_t index, uint8_t sub, uint32_t value) {
  put_le16(out, index);
  out[2] = sub;
  put_le32(&out[3], value);
}

}  // namespace canopen
}  // namespace mb2co
