// NMT master (CiA 301 §7.2.8.3.1): the five node control commands, to one
// node or to all (node id 0), as a 2-byte frame on COB-ID 000h. NMT is
// unconfirmed: whether a node obeyed is seen by the NodeMonitor (heartbeat
// or guarding state), not here.
#pragma once
#include <stdint.h>

#include "canopen/can_frame.h"
#include "canopen/nmt_slave.h"

namespace mb2co {
namespace canopen {

class NmtMaster {
 public:
  /// Node id 0 addresses every node (CiA 301 broadcast).
  static const uint8_t kAllNodes = 0;

  /// `sink` is copied; its ctx must outlive the NmtMaster.
  explicit NmtMaster(const CanSink& sink) : sink_(sink) {}

  /// Sends `command` to `node_id` (0: all, 1..127: one). False, with nothing
  /// sent, for another command byte or a node id above 127; false when the
  /// port refused the frame (counted in send_failures()).
  bool command(NmtCommand command, uint8_t node_id);
  bool start(uint8_t node_id) { return command(kNmtStart, node_id); }
  bool stop(uint8_t node_id) { return command(kNmtStop, node_id); }
  bool enter_pre_operational(uint8_t node_id) { return command(kNmtEnterPreOperational, node_id); }
  bool reset_node(uint8_t node_id) { return command(kNmtResetNode, node_id); }
  bool reset_communication(uint8_t node_id) { return command(kNmtResetCommunication, node_id); }

  /// Commands the port refused (never decrements, saturates).
  uint16_t send_failures() const { return send_failures_; }

 private:
  CanSink sink_;
  uint16_t send_failures_ = 0;
};

}  // namespace canopen
}  // namespace mb2co
