// SlaveCore's second way in (profile::kModbusTcp, profiles/profile.h): a request PDU from another
// framer (Modbus/TCP), executed by the same function codes as a frame from
// the line and answered through its channel, at once or when done.
#include "modbus/slave.h"

#if MB2CO_CONFIG_MODBUS_TCP  // else the image has no other framer (its profile: shared/profiles)

namespace mb2co {
namespace modbus {

void SlaveCore::serve(PduChannel& channel, uint16_t pdu_length) {
  if (answer_pending_ && answer_channel_ == &channel) {  // its client moved on
    answer_pending_ = false;
    ++counters_.no_responses;
  }
  ++counters_.bus_messages;
  ++counters_.server_messages;
  channel_ = &channel;  // pdu() and send() use it: handle_request serves it like a frame
  handle_request(pdu_length, false);
  channel_ = answer_pending_ ? answer_channel_ : nullptr;
}

void SlaveCore::forget(const PduChannel& channel) {
  if (!answer_pending_ || answer_channel_ != &channel) return;
  answer_pending_ = false;
  ++counters_.no_responses;
  channel_ = answer_channel_ = nullptr;
}

void SlaveCore::send_to_channel(uint16_t pdu_length) {
  if (!channel_->send(channel_->ctx, channel_->pdu, pdu_length)) {
    ++stats_.send_failures;
    ++counters_.no_responses;
  }
}

}  // namespace modbus
}  // namespace mb2co
#endif  // MB2CO_CONFIG_MODBUS_TCP
