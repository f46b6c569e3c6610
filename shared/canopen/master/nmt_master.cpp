#include "canopen/master/nmt_master.h"

#include "canopen/frame_out.h"

namespace mb2co {
namespace canopen {

static bool known_command(uint8_t c) {
  return c == kNmtStart || c == kNmtStop || c == kNmtEnterPreOperational || c == kNmtResetNode ||
         c == kNmtResetCommunication;
}

bool NmtMaster::command(NmtCommand command, uint8_t node_id) {
  if (!known_command(command) || node_id > 127) return false;
  const uint8_t data[2] = {static_cast<uint8_t>(command), node_id};
  if (send_frame(sink_, 0x000, 2, data)) return true;
  if (send_failures_ != 0xFFFF) ++send_failures_;
  return false;
}

}  // namespace canopen
}  // namespace mb2co
