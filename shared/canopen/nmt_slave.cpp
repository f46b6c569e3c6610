#include "canopen/nmt_slave.h"

namespace mb2co {
namespace canopen {

bool NmtSlave::on_frame(const CanFrame& f) {
  if (f.rtr() || f.dlc != 2) return false;
  if (f.data[1] != 0 && f.data[1] != node_id_) return false;
  const NmtState before = state_;
  switch (f.data[0]) {
    case kNmtStart:
      state_ = kNmtOperational;
      break;
    case kNmtStop:
      state_ = kNmtStopped;
      break;
    case kNmtEnterPreOperational:
      state_ = kNmtPreOperational;
      break;
    case kNmtResetNode:
      reset_ = kResetNode;
      return true;
    case kNmtResetCommunication:
      reset_ = kResetCommunication;
      return true;
    default:
      return false;
  }
  return state_ != before;
}

}  // namespace canopen
}  // namespace mb2co
