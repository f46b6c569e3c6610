// latency --remote on the common clock (CiA 301 TIME, issue 25): a press is
// measured from the remote station's own stamp of its button edge (its
// 2300h/1) to this station's stamp of the lab LED change (2300h/2). Both are
// on the network clock once TIME frames have set each station's clock
// (1013h's scale: µs since 1984-01-01 mod 2^32), so the debounce, the TPDO
// and the CAN hop are inside the delay. The remote stamp comes through this
// station's gateway by FC 2Bh/MEI 0Dh (SDO upload, CiA 309-2).
//
// What the difference of two stamps on two clocks can be off by (the clock
// offset's uncertainty), derived in docs/mb2co-plant.md "Latency mode":
//   spread: every station takes the same TIME frame, so the producer's send
//     delay and the 1 ms resolution cancel; what differs is when each station
//     stamps its reception: in the firmware pass that reads it, up to one
//     loop pass (timing::LatencyParams::fw_loop_us) after the frame's end;
//   drift: each clock runs on its own since its last TIME frame, off by at
//     most drift_ppm of that age (the two ages add up).
#pragma once
#include <stdint.h>

#include <string>

#include "host/status.h"

namespace mb2co {
namespace pcapp {

class ModbusLink;

struct ClockBound {
  uint32_t spread_us = 1000;  ///< TIME reception spread: one firmware loop pass (timing::LatencyParams)
  uint32_t drift_ppm = 100;   ///< most two station clocks run apart (--drift-ppm)
};

/// The uncertainty of (stamp here - stamp there) in µs, rounded up: the
/// spread plus the drift over both clocks' ages since their last TIME frame.
inline uint32_t clock_uncertainty_us(const ClockBound& b, uint32_t age_here_us, uint32_t age_remote_us) {
  const uint64_t drift = (uint64_t{age_here_us} + age_remote_us) * b.drift_ppm;
  return b.spread_us + static_cast<uint32_t>((drift + 999999u) / 1000000u);
}

/// How long a clock had run on its own when it took `stamp_us`: since its
/// last set before the stamp. `set_us` is the set read after the stamp (a
/// TIME frame may have come in between: then the one before, `prev_set_us`,
/// is the stamp's). All on the common clock, wrap-safe.
inline uint32_t clock_age_us(uint32_t stamp_us, uint32_t set_us, uint32_t prev_set_us) {
  const uint32_t age = stamp_us - set_us;
  return age < 0x80000000u ? age : stamp_us - prev_set_us;
}

/// The remote press edge of one press and both clocks' last set, all on the
/// common clock; the sets as read after the press and the ones known before.
struct RemoteEdge {
  uint32_t edge_us = 0;             ///< remote 2300h/1: its last button edge
  uint32_t set_here_us = 0;         ///< this station's 2300h/4
  uint32_t set_remote_us = 0;       ///< the remote station's 2300h/4
  uint32_t prev_set_here_us = 0;    ///< this station's 2300h/4 read before (probe or last press)
  uint32_t prev_set_remote_us = 0;  ///< the remote station's, read before
};

/// Which station to ask and whether there is a common clock. Not copyable
/// state beyond the ids; every call blocks on the link (a few Modbus
/// exchanges; a remote node that does not answer: the gateway's SDO timeout).
class RemoteClock {
 public:
  /// Once before measuring: this station's node id (2000h/1, holding
  /// register of the default map), the watched station (2130h/2, else the
  /// previous one 2110h/4) and that both clocks are common (2300h/4 != 0).
  /// A failure is the one-line reason nothing can be measured.
  Status probe(ModbusLink& link);
  /// The remote station's last edge and both clocks' last set.
  Status read_edge(ModbusLink& link, RemoteEdge& e);

  uint8_t here_id() const { return here_id_; }
  uint8_t remote_id() const { return remote_id_; }

 private:
  /// 2300h/4 of `node_id` (common µs of its clock's last set; 0 never).
  Status clock_set(ModbusLink& link, uint8_t node_id, uint32_t& set_us);

  uint8_t here_id_ = 0;
  uint8_t remote_id_ = 0;
  uint32_t set_here_us_ = 0;  ///< 2300h/4 as last read
  uint32_t set_remote_us_ = 0;
};

}  // namespace pcapp
}  // namespace mb2co
