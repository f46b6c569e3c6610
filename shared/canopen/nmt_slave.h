// NMT slave (CiA 301 §7.3.2): the node's communication state and the commands
// that change it. What each state allows is answered here, so every service
// asks the same place.
#pragma once
#include <stdint.h>

#include "canopen/can_frame.h"

namespace mb2co {
namespace canopen {

enum NmtState : uint8_t {
  kNmtInitialising = 0x00,  ///< also the boot-up message's data byte
  kNmtStopped = 0x04,
  kNmtOperational = 0x05,
  kNmtPreOperational = 0x7F,
};

enum NmtCommand : uint8_t {
  kNmtStart = 0x01,
  kNmtStop = 0x02,
  kNmtEnterPreOperational = 0x80,
  kNmtResetNode = 0x81,
  kNmtResetCommunication = 0x82,
};

enum NmtReset : uint8_t { kResetNone = 0, kResetCommunication, kResetNode };

/// Members that start at zero have no initialisers: the owner (NodeState)
/// is value-initialised, which zero-fills it in one go.
class NmtSlave {
 public:
  void init(uint8_t node_id) {
    node_id_ = node_id;
    state_ = kNmtInitialising;
    reset_ = kResetNone;
  }
  /// Handles a frame on COB-ID 000h. Frames that are not exactly 2 bytes, RTR
  /// frames, unknown commands and other nodes' commands are ignored (CiA 301:
  /// NMT is unconfirmed, there is nothing to answer). Returns true if the state
  /// changed or a reset was requested.
  bool on_frame(const CanFrame& f);
  /// Reset requested by the last command, cleared by the call.
  NmtReset take_reset() {
    const NmtReset r = reset_;
    reset_ = kResetNone;
    return r;
  }
  NmtState state() const { return state_; }
  void set_state(NmtState s) { state_ = s; }

  bool sdo_allowed() const { return state_ == kNmtPreOperational || state_ == kNmtOperational; }
  bool pdo_allowed() const { return state_ == kNmtOperational; }
  /// EMCY, SYNC and heartbeat consumption: pre-operational and operational.
  bool emcy_allowed() const { return sdo_allowed(); }
  bool sync_allowed() const { return sdo_allowed(); }

 private:
  uint8_t node_id_;
  NmtState state_;
  NmtReset reset_;
};

}  // namespace canopen
}  // namespace mb2co
