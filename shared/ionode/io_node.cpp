#include "ionode/io_node.h"

namespace mb2co {
namespace ionode {

using namespace canopen;

constexpr uint16_t IoNode::kWidestRange;

IoNode::IoNode(const CanSink& sink, uint32_t device_type)
    : values_(),
      od_(od::IoNodeDefinition, reinterpret_cast<uint8_t*>(&values_)),
      node_(od_, sink),
      device_type_(device_type) {
  row_inputs_ = od_.find(0x6000, 1);
  row_outputs_ = od_.find(0x6200, 1);
  row_local_ = od_.find(0x2100, 0);
  row_polarity_ = od_.find(0x6002, 1);
  pins_[0] = pins_[1] = 0;
  node_.tpdos().set_profile_events(0x0F);  // type 255: CiA 401's interrupt masks
  od_.set_owner(kOwnerIoNode, this);
  node_.set_reset_callback(&IoNode::on_reset, this);
}

void IoNode::start(uint8_t default_node_id, uint32_t now_us) {
  // The saved id (2001h/1) is loaded by the start's reset node and named
  // the reset's id by on_reset, before the boot-up.
  node_.start(default_node_id, now_us);
}

void IoNode::on_reset(void* ctx, NmtReset kind) {
  IoNode& n = *static_cast<IoNode*>(ctx);
  n.od_.set(n.od_.find(0x1000, 0), n.device_type_);
  // 2001h/1-2 as every device keeps its id and bit rate (Node::take_node_id_and_bitrate);
  // the rest once, in the reset that boots up with this id.
  if (!n.node_.take_node_id_and_bitrate(kind, &n.values_.x2001_1_nodeId, n.values_.x2001_2_bitrateKbit))
    return;
  // A reset node put 6000h and 6002h back to their defaults (or the saved
  // polarity): 6000h reads the pins again.
  for (uint8_t i = 0; i < 2; ++i) n.update_input(i, static_cast<uint8_t>(n.od_.get(n.row_polarity_ + i)));
}

void IoNode::set_input(uint8_t n, uint8_t value) {
  if (n >= 2) return;
  pins_[n] = value;
  update_input(n, static_cast<uint8_t>(od_.get(row_polarity_ + n)));
}

// Rows from 6002h/1 on: 6002h/1-2, 6005h/0, 6006h/0-2, 6007h/0-2, 6008h/0-2.
enum : uint8_t { kGlobalEnable = 2, kAnyChange = 4, kLowToHigh = 7, kHighToLow = 10 };

void IoNode::update_input(uint8_t n, uint8_t polarity) {
  const uint16_t row = static_cast<uint16_t>(row_inputs_ + n);
  const uint16_t param = static_cast<uint16_t>(row_polarity_ + n);
  const uint8_t before = static_cast<uint8_t>(od_.get(row));
  const uint8_t now = static_cast<uint8_t>(pins_[n] ^ polarity);
  const uint8_t changed = before ^ now;
  if (changed == 0) return;
  od_.set(row, now);
  const bool event =
      ((changed & od_.get(param + kAnyChange)) | (changed & now & od_.get(param + kLowToHigh)) |
       (changed & before & od_.get(param + kHighToLow))) != 0;
  if (event && od_.get(static_cast<uint16_t>(row_polarity_ + kGlobalEnable)) != 0) request_input_pdos();
}

void IoNode::request_input_pdos() {
  for (uint8_t n = 0; n < 4; ++n) {
    const uint16_t map = od_.find(static_cast<uint16_t>(0x1A00 + n), 0);
    const uint8_t count = static_cast<uint8_t>(od_.get(map));
    for (uint8_t k = 1; k <= count; ++k)
      if ((od_.get(static_cast<uint16_t>(map + k)) >> 16) == 0x6000u) {
        node_.tpdos().request(n);
        break;
      }
  }
}

uint8_t IoNode::output(uint8_t n) const {
  return n < 2 ? static_cast<uint8_t>(od_.get(static_cast<uint16_t>(row_outputs_ + n))) : 0;
}

// Before it is stored: 6000h reads the pins with the new polarity.
HookResult IoNodeHandlers::polarity(void* io, uint16_t, uint8_t sub, const uint8_t* data, bool apply) {
  if (apply) static_cast<IoNode*>(io)->update_input(static_cast<uint8_t>(sub - 1), data[0]);
  return kSdoOk;
}

// A hand switch (2100h) keeps the outputs under local control; and the
// outputs are process data: they follow the network only when operational.
HookResult IoNodeHandlers::outputs(void* io, uint16_t, uint8_t, const uint8_t*, bool) {
  IoNode& n = *static_cast<IoNode*>(io);
  if (n.od_.get(n.row_local_) != 0) return kAbortLocalControl;
  if (n.node_.nmt_state() != kNmtOperational) return kAbortDeviceState;
  return kSdoOk;
}

}  // namespace ionode
}  // namespace mb2co
