#include "timing/remote_read.h"

namespace mb2co {
namespace timing {

namespace {
// Address 1, CRC 2; the PDU: 12-byte header, + 4-byte object size and the
// data in an upload response (modbus/network_pdu.h).
constexpr uint16_t kAduOverhead = 3;
constexpr uint16_t kHeader = 12;
constexpr uint16_t kSizedHeader = 16;

uint64_t frames_ns(uint32_t frames, uint16_t bits, uint32_t bitrate_bps) {
  return (static_cast<uint64_t>(frames) * bits * 1000000000u + bitrate_bps - 1u) / bitrate_bps;
}
}  // namespace

RtuExchange net_upload_exchange(uint16_t window_bytes) {
  return RtuExchange{kAduOverhead + kHeader,
                     static_cast<uint16_t>(kAduOverhead + kSizedHeader + window_bytes)};
}

SdoUploadSteps sdo_upload_steps(uint32_t object_bytes) {
  if (object_bytes <= 4u) return SdoUploadSteps{2, 1};
  const uint32_t segments = (object_bytes + 6u) / 7u;
  return SdoUploadSteps{2u + 2u * segments, 1u + segments};
}

RemoteReadTiming remote_read_timing(const SerialFormat& serial, uint32_t bitrate_bps, uint32_t object_bytes,
                                    uint16_t window_bytes, uint64_t node_answer_ns,
                                    uint64_t gateway_turnaround_ns, WorstCase convention) {
  RemoteReadTiming t;
  const TransactionTiming rtu =
      transaction_timing(serial, net_upload_exchange(window_bytes), t35_ns(serial), 0, 0);
  t.serial_ns = rtu.worst_ns;
  const SdoUploadSteps steps = sdo_upload_steps(object_bytes);
  t.can_best_ns = frames_ns(steps.frames, frame_bits_unstuffed(false, 8), bitrate_bps);
  t.can_worst_ns = frames_ns(steps.frames, frame_bits_worst(false, 8, convention), bitrate_bps);
  t.best_ns = rtu.best_ns + t.can_best_ns;
  // The gateway reacts to the request's end and to every answer.
  t.worst_ns = t.serial_ns + t.can_worst_ns + steps.answers * node_answer_ns +
               (1u + steps.answers) * gateway_turnaround_ns;
  return t;
}

}  // namespace timing
}  // namespace mb2co
