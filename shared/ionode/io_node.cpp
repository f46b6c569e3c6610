#include "ionode/io_node.h"

namespace mb2co {
namespace ionode {

using namespace canopen;

IoNode::IoNode(const CanSink& sink, uint32_t device_type)
    : values_(),
      od_(od::IoNodeDefinition, reinterpret_cast<uint8_t*>(&values_)),
      node_(od_, sink),
      device_type_(device_type) {
  row_inputs_ = od_.find(0x6000, 1);
  row_outputs_ = od_.find(0x6200, 1);
  row_local_ = od_.find(0x2100, 0);
  node_.set_app_hook(&IoNode::app_write, this);
  node_.set_reset_callback(&IoNode::on_reset, this);
}

void IoNode::on_reset(void* ctx, NmtReset) {
  IoNode& n = *static_cast<IoNode*>(ctx);
  n.od_.set(n.od_.find(0x1000, 0), n.device_type_);
}

void IoNode::set_input(uint8_t n, uint8_t value) {
  if (n < 2) od_.set(static_cast<uint16_t>(row_inputs_ + n), value);
}

uint8_t IoNode::output(uint8_t n) const {
  return n < 2 ? static_cast<uint8_t>(od_.get(static_cast<uint16_t>(row_outputs_ + n))) : 0;
}

HookResult IoNode::app_write(void* ctx, uint8_t, uint16_t index, uint8_t, const uint8_t*, uint16_t, bool) {
  IoNode& n = *static_cast<IoNode*>(ctx);
  if (index == 0x6200) {
    // A hand switch (2100h) keeps the outputs under local control; and the
    // outputs are process data: they follow the network only when operational.
    if (n.od_.get(n.row_local_) != 0) return kAbortLocalControl;
    if (n.node_.nmt_state() != kNmtOperational) return kAbortDeviceState;
  }
  return kSdoOk;
}

}  // namespace ionode
}  // namespace mb2co
