// Latency of a remote read through the gateway (FC 2Bh / MEI 0Dh SDO upload,
// docs/gateway-network.md): the Modbus request, the slave's end of frame
// (t3.5), the SDO transfer on CAN with the remote node's answers, the
// response. Times in ns; best and worst bound as in rtu_timing.h.
#pragma once
#include <stdint.h>

#include "timing/can_bits.h"
#include "timing/rtu_timing.h"

namespace mb2co {
namespace timing {

/// Bytes of a 2Bh/0Dh upload request and of its response carrying
/// `window_bytes` object bytes (address, PDU, CRC).
RtuExchange net_upload_exchange(uint16_t window_bytes);

/// The CAN side of an SDO upload of `object_bytes`: expedited up to 4 bytes
/// (request + answer), else segmented (initiate, then one request and one
/// answer per 7 bytes). `answers`: frames the remote node sends, each after
/// its own reaction time.
struct SdoUploadSteps {
  uint32_t frames;   ///< 8-byte frames on the bus
  uint32_t answers;  ///< of those, the remote node's
};
SdoUploadSteps sdo_upload_steps(uint32_t object_bytes);

struct RemoteReadTiming {
  uint64_t serial_ns;     ///< request + t3.5 + response (frames rounded up)
  uint64_t can_best_ns;   ///< the CAN frames without stuff bits
  uint64_t can_worst_ns;  ///< with worst-case stuffing (`convention`)
  uint64_t best_ns;       ///< everything, frames unstuffed, node time 0
  uint64_t worst_ns;      ///< everything, worst stuffing, `node_answer_ns` per answer
};

/// A read of `window_bytes` of an object of `object_bytes` at `bitrate_bps`
/// (> 0). `node_answer_ns`: the remote node's worst time to answer one SDO
/// frame; `gateway_turnaround_ns`: the gateway's worst time to react, once per
/// frame it receives (the request's end and each answer). The bus is assumed
/// free for the transfer's frames (no other traffic: add the analysis of
/// rta.h for a loaded bus).
RemoteReadTiming remote_read_timing(const SerialFormat& serial, uint32_t bitrate_bps, uint32_t object_bytes,
                                    uint16_t window_bytes, uint64_t node_answer_ns,
                                    uint64_t gateway_turnaround_ns, WorstCase convention);

}  // namespace timing
}  // namespace mb2co
