// FC 08 (diagnostics, serial line spec §6.1) and FC 2B/0E (read device
// identification, application protocol §6.21).
#include "modbus/slave.h"

namespace mb2co {
namespace modbus {
namespace {

constexpr uint8_t kConformityBasicStreamAndIndividual = 0x81;
constexpr uint8_t kMoreFollows = 0xFF;

// Read Device ID codes.
enum : uint8_t { kStreamBasic = 1, kStreamRegular = 2, kStreamExtended = 3, kIndividual = 4 };

}  // namespace

bool SlaveCore::is_restart_request(uint16_t pdu_length) const {
  if (!profile::kDiagnostics) return false;
  const uint8_t* p = framer_.buffer() + 1;
  if (pdu_length != 5u || p[0] != fc::kDiagnostics) return false;
  if (get_be16(p + 1) != diag::kRestartCommunications) return false;
  const uint16_t data = get_be16(p + 3);
  return data == 0x0000u || data == 0xFF00u;
}

SlaveCore::Reply SlaveCore::diagnostics(uint16_t pdu_length) {
#if MB2CO_CONFIG_MODBUS_TCP
  // Serial line only (application protocol §6.8): its counters and modes
  // are the line's, not a Modbus/TCP client's.
  if (channel_ != nullptr) return Reply{0, Exception::kIllegalFunction};
#endif
  uint8_t* p = pdu();
  if (pdu_length < 3u) return Reply{0, Exception::kIllegalDataValue};
  const uint16_t sub = get_be16(p + 1);
  if (sub == diag::kReturnQueryData) return Reply{pdu_length, Exception::kNone};  // loop-back

  uint16_t value = 0;  // the response's data field
  bool data_ok = pdu_length == 5u && get_be16(p + 3) == 0x0000u;
  switch (sub) {
    case diag::kRestartCommunications:
      // FF00 would also clear the event log: we keep none, so both are alike.
      data_ok = pdu_length == 5u && (get_be16(p + 3) == 0x0000u || get_be16(p + 3) == 0xFF00u);
      if (!data_ok) return Reply{0, Exception::kIllegalDataValue};
      restart_pending_ = true;
      return Reply{5, Exception::kNone};
    case diag::kForceListenOnly:
      if (!data_ok) return Reply{0, Exception::kIllegalDataValue};
      listen_only_ = true;
      return Reply{0, Exception::kNone};  // never answered
    case diag::kClearCounters:
      if (!data_ok) return Reply{0, Exception::kIllegalDataValue};
      clear_counters();
      return Reply{5, Exception::kNone};
    case diag::kClearOverrun:
      if (!data_ok) return Reply{0, Exception::kIllegalDataValue};
      counters_.char_overruns = 0;
      return Reply{5, Exception::kNone};
    case diag::kReturnDiagnosticRegister:
    case diag::kServerNakCount:   // we never answer NAK
    case diag::kServerBusyCount:  // nor busy
      break;
    case diag::kBusMessageCount:
      value = counters_.bus_messages;
      break;
    case diag::kBusCommErrorCount:
      value = counters_.bus_comm_errors;
      break;
    case diag::kBusExceptionCount:
      value = counters_.exceptions;
      break;
    case diag::kServerMessageCount:
      value = counters_.server_messages;
      break;
    case diag::kServerNoResponseCount:
      value = counters_.no_responses;
      break;
    case diag::kBusCharOverrunCount:
      value = counters_.char_overruns;
      break;
    default:
      return Reply{0, Exception::kIllegalFunction};  // sub-function not supported
  }
  if (!data_ok) return Reply{0, Exception::kIllegalDataValue};
  put_be16(p + 3, value);
  return Reply{5, Exception::kNone};
}

// FC 2B / MEI 0D: the handler answers now (an exception PDU is answered by
// the usual path, so that it is counted once) or later (send_deferred).
SlaveCore::Reply SlaveCore::network_request(uint16_t pdu_length) {
  if (net_handler_ == nullptr) return Reply{0, Exception::kIllegalFunction};
  const uint16_t length = net_handler_->handle(net_handler_->ctx, pdu(), pdu_length, response_capacity());
  if (length == 0u) {
    answer_pending_ = true;
#if MB2CO_CONFIG_MODBUS_TCP
    answer_channel_ = channel_;
#endif
    return Reply{0, Exception::kNone};
  }
  if (length == 2u && (pdu()[0] & fc::kExceptionFlag) != 0u) {
    return Reply{0, static_cast<Exception>(pdu()[1])};
  }
  return Reply{length, Exception::kNone};
}

SlaveCore::Reply SlaveCore::device_identification(uint16_t pdu_length) {
  uint8_t* p = pdu();
  if (profile::kNetwork && pdu_length >= 2u && p[1] == kMeiCanopenReference)
    return network_request(pdu_length);
  if (identity_ == nullptr) return Reply{0, Exception::kIllegalFunction};
  if (pdu_length < 2u) return Reply{0, Exception::kIllegalDataValue};
  if (p[1] != kMeiReadDeviceId) return Reply{0, Exception::kIllegalFunction};
  if (pdu_length != 4u) return Reply{0, Exception::kIllegalDataValue};
  const uint8_t code = p[2];
  uint8_t first = p[3];
  if (code < kStreamBasic || code > kIndividual) return Reply{0, Exception::kIllegalDataValue};
  if (code == kIndividual) {
    if (first > DeviceIdentity::kLastBasicObject) return Reply{0, Exception::kIllegalDataAddress};
  } else if (first > DeviceIdentity::kLastBasicObject) {
    first = 0;  // stream access from an unknown object restarts at object 0
  }
  // Regular and extended requests are answered at our conformity level
  // (basic): the same objects as a basic request.
  const uint8_t last = code == kIndividual ? first : static_cast<uint8_t>(DeviceIdentity::kLastBasicObject);

  p[3] = kConformityBasicStreamAndIndividual;
  p[4] = 0;  // more follows
  p[5] = 0;  // next object id
  // At most 253 with a 256-byte frame; >= 13 (kMinSlaveFrameBytes).
  const uint16_t max_pdu = static_cast<uint16_t>(framer_.capacity() - 1u - kCrcBytes);
  uint8_t count = 0;
  uint16_t pos = 7;
  for (uint16_t id = first; id <= last; ++id) {
    // Invariant: pos ≤ max_pdu; the first object always has room ≥ max_pdu - 9.
    const bool header_fits = pos + 2u <= max_pdu;
    const uint8_t room = header_fits ? static_cast<uint8_t>(max_pdu - pos - 2u) : 0u;
    const uint8_t length =
        header_fits ? identity_->copy_object(static_cast<uint8_t>(id), p + pos + 2, room) : 0u;
    if (count != 0u && (!header_fits || length > room)) {  // next transaction
      p[4] = kMoreFollows;
      p[5] = static_cast<uint8_t>(id);
      break;
    }
    p[pos] = static_cast<uint8_t>(id);
    p[pos + 1u] = length > room ? room : length;  // a first object too long is cut
    pos = static_cast<uint16_t>(pos + 2u + p[pos + 1u]);
    ++count;
  }
  p[6] = count;
  return Reply{pos, Exception::kNone};
}

}  // namespace modbus
}  // namespace mb2co
