#include "canopen/node.h"

#include "canopen/frame_out.h"

namespace mb2co {
namespace canopen {

Node::Node(ObjectDictionary& od, const CanSink& sink) : NodeState(), od_(od), sink_(sink) {
  od_.set_owner(kOdOwnerNode, this);
}

static const uint16_t kIndices[] MB2CO_FLASH = {0x1016, 0x1017, 0x100C, 0x100D};

constexpr uint16_t Node::kWidestRange;

namespace {

/// Writes the range of exactly `id` at `r`; returns the next place.
CanIdRange* exact(CanIdRange* r, uint32_t id) {
  r->id = static_cast<uint16_t>(id);
  r->mask = kCanRangeExact;
  return r + 1;
}

}  // namespace

uint8_t Node::acceptance(CanIdRange* ranges) const {
  CanIdRange* r = exact(ranges, 0x000);                     // NMT
  r = exact(r, sync_.cob_id());                             // SYNC (1005h)
  r = exact(r, 0x600u + node_id_);                          // SDO request
  if (profile::kGuarding) r = exact(r, 0x700u + node_id_);  // node guarding (RTR)
  for (uint8_t n = 0; n < kPdoCount; ++n) {
    const uint32_t cob = rpdos_.cob_id(n);
    // Valid (bit 31 clear) and a standard id (bit 29 clear).
    if ((cob & 0xA0000000u) == 0) r = exact(r, cob & 0x7FFu);
  }
  for (uint8_t sub = 1; sub <= kHbConsumers; ++sub) {
    const uint32_t entry = od_.get(static_cast<uint16_t>(row_[k1016] + sub));
    const uint8_t remote = static_cast<uint8_t>(entry >> 16);
    // Node id 1..127 and a consumer time: a heartbeat to watch.
    if (remote >= 1 && remote <= 127 && (entry & 0xFFFFu) != 0) r = exact(r, 0x700u + remote);
  }
  if (profile::kTime && TimeStamp::consuming()) r = exact(r, TimeStamp::can_id());  // TIME (1012h)
  if (profile::kTpdoRtr) *r++ = kTpdoRemoteRange;
  const uint8_t services = service_range_count_;
  if (services != 0) flash_copy(r, service_ranges_, services * sizeof *r);  // none: no table (null)
  return static_cast<uint8_t>(r - ranges + services);
}

void Node::start(uint8_t node_id, uint32_t now_us) {
  next_node_id_ = node_id;
  power_on_node_id_ = node_id;
  reset(kResetNode, now_us);
}

void Node::reset(NmtReset kind, uint32_t now_us) {
  node_id_ = next_node_id_;
  od_.set_node_id(node_id_);
  // Reset node restores every area, reset communication only 1000h–1FFFh;
  // saved parameters (1010h) then replace the defaults.
  const uint16_t from = kind == kResetNode ? 0x0000 : 0x1000;
  const uint16_t to = kind == kResetNode ? 0xFFFF : 0x1FFF;
  od_.restore_defaults(from, to);
  // A damaged set is refused whole (params_load restores what it began).
  const ParamLoad loaded = storage_ != nullptr ? params_load(od_, *storage_, from, to) : ParamLoad::kNone;
  params_loaded_ = param_set_loaded(loaded);
  // The application adjusts what it derives from the configuration (e.g. its
  // device type, the line's PDO COB-IDs) before the services read the OD.
  if (reset_cb_ != nullptr) reset_cb_(reset_ctx_, kind);
  // The application's id entry, restored with its area at a reset node,
  // names another id than the one pending (written, not saved): the saved or
  // power-on id is in force (CiA 301: a pending id takes effect at reset
  // communication; a reset node restores what was saved). The communication
  // area once more for that id, so that every node-id-relative entry is its
  // own and the one boot-up leaves on it. Only after a reset node, so at
  // most once (a bounded stack on the AVR, whatever the callback does).
  if (kind == kResetNode && next_node_id_ != node_id_) return reset(kResetCommunication, now_us);
  od_.find_rows(kIndices, kRows, row_);
  row_1010_ = od_.find(0x1010, 1);
  // 1010h sub 1 reads the storage capability: 1 = saves on command.
  od_.set(row_1010_, storage_ != nullptr ? 1u : 0u);
  nmt_.init(node_id_);
  error_control_.init(node_id_);
  emcy_.init(&od_);
  if (param_damage_found(loaded)) {
    // Sent after the boot-up (EMCY waits for pre-operational): the operator
    // learns that a saved set was lost or that an older one is in force.
    emcy_.raise(kEmcyStorage, kErrGeneric);
    if (storage_damage_count_ != 0xFF) ++storage_damage_count_;
  }
  sync_.init(&od_);
  tpdos_.init(&od_);
  rpdos_.init(&od_, &emcy_);
  sdo_.init(&od_, node_id_);
  if (profile::kTime) TimeStamp::init(&od_, now_us);
  hb_consumer_.reset_all();
  for (uint8_t s = 1; s <= kHbConsumers; ++s) {
    hb_consumer_.configure(s, od_.get(static_cast<uint16_t>(row_[k1016] + s)));
  }
  hb_lost_ = false;
  life_lost_ = false;
  // The port opens its filters for what the reset configured, before the
  // boot-up message (a reply to it must not be filtered out).
  update_filters();
  // Boot-up, then pre-operational autonomously (CiA 301 §7.3.2.2).
  send_frame(sink_, static_cast<uint16_t>(0x700u + node_id_), 1, nullptr);
  enter(kNmtPreOperational);
  error_control_.restart();
  (void)now_us;
}

void Node::enter(NmtState state) {
  const NmtState before = nmt_.state();
  nmt_.set_state(state);
  on_transition(before);
}

void Node::on_transition(NmtState before) {
  const NmtState state = nmt_.state();
  if (state == before) return;
  if (state == kNmtOperational) tpdos_.on_operational();
  if (before == kNmtOperational) rpdos_.stop();
  if (state == kNmtStopped) {
    sdo_.cancel();
    hb_consumer_.reset_all();
  }
  if (before == kNmtStopped) sync_.restart();
}

void Node::receive(const CanFrame& f, uint32_t now_us) {
  if (f.extended() || nmt_.state() == kNmtInitialising) return;
  if (f.id == 0) {
    const NmtState before = nmt_.state();
    if (!nmt_.on_frame(f)) return;
    const NmtReset r = nmt_.take_reset();
    if (r == kResetNone) return on_transition(before);
    if (save_.running()) return request_reset(r);  // after the save (process())
    return reset(r, now_us);
  }
  // 1013h reads the time of this frame, and a write of it in this frame
  // (SDO, RPDO) sets the clock at its arrival.
  if (profile::kTime) {
    TimeStamp::refresh(now_us);
    if (TimeStamp::on_frame(f, now_us, nmt_.sdo_allowed())) return;
  }
  if (nmt_.sync_allowed()) {
    uint8_t counter = 0;
    const Sync::Result r = sync_.on_frame(f, &counter);
    if (r == Sync::kSyncEvent) {
      emcy_.clear(kEmcySyncLength);
      return on_sync_event(counter, now_us);
    }
    if (r == Sync::kSyncLengthError) return emcy_.raise(kEmcySyncLength, kErrCommunication);
  }
  if (f.id == 0x600u + node_id_) {
    if (nmt_.sdo_allowed()) sdo_.on_frame(f, now_us, sink_);
    return;
  }
  if (f.id == 0x700u + node_id_) {
    if (profile::kGuarding && f.rtr()) {
      error_control_.on_guard_request(now_us, nmt_.state(), sink_,
                                      static_cast<uint16_t>(od_.get(row_[k1017])), guard_time_ms(),
                                      life_time_factor());
    }
    return;
  }
  if (nmt_.pdo_allowed()) {
    // Answered where the profile has it (profile::kTpdoRtr).
    if (profile::kTpdoRtr && f.rtr() && tpdos_.on_rtr(f, sink_, now_us)) return;
    if (rpdos_.on_frame(f, now_us)) return;
  }
  if (f.id > 0x700u && f.id <= 0x77Fu && nmt_.sdo_allowed()) hb_consumer_.on_frame(f, now_us);
}

void Node::local_nmt(NmtCommand command, uint32_t now_us) {
  CanFrame f = {};
  f.dlc = 2;
  f.data[0] = command;
  f.data[1] = node_id_;
  receive(f, now_us);
}

void Node::on_sync_event(uint8_t counter, uint32_t now_us) {
  if (!nmt_.pdo_allowed()) return;
  rpdos_.on_sync();
  tpdos_.on_sync(counter, sink_, now_us);
}

// 100Ch and 100Dh, or 0 (no guarding) where the profile leaves guarding out
// (the rows are then absent from the OD).
uint16_t Node::guard_time_ms() const {
  return profile::kGuarding ? static_cast<uint16_t>(od_.get(row_[k100C])) : 0u;
}

uint8_t Node::life_time_factor() const {
  return profile::kGuarding ? static_cast<uint8_t>(od_.get(row_[k100D])) : 0u;
}

void Node::update_guard_emcy() {
  emcy_.report(kEmcyLifeGuard, hb_lost_ || life_lost_, kErrCommunication);
}

void Node::update_filters() {
  filters_stale_ = false;
  // An image without filters receives everything: no ranges to compute.
  if (!profile::kAcceptanceFilters || can_control_ == nullptr) return;
  const CanControl control = flash_read(can_control_);
  if (control.set_filters == nullptr) return;
  CanIdRange ranges[kMaxAcceptanceRanges];
  const uint8_t count = acceptance(ranges);
  control.set_filters(sink_.ctx, ranges, count);
}

void Node::on_controller_state(uint8_t events, bool passive, uint32_t now_us) {
  if (events & kControllerRxOverflow) {
    overflow_us_ = now_us;
    emcy_.raise(kEmcyCanOverrun, kErrCommunication);
  }
  if (events & kControllerBusOffRecovered) {
    recovered_us_ = now_us;
    emcy_.raise(kEmcyBusOffRecovered, kErrCommunication);
  }
  if (events & kControllerStateChanged) emcy_.report(kEmcyCanPassive, passive, kErrCommunication);
}

void Node::expire_controller_emcy(uint32_t now_us) {
  if (emcy_.active(kEmcyCanOverrun) && now_us - overflow_us_ >= kControllerEventHoldUs) {
    emcy_.clear(kEmcyCanOverrun);
  }
  if (emcy_.active(kEmcyBusOffRecovered) && now_us - recovered_us_ >= kControllerEventHoldUs) {
    emcy_.clear(kEmcyBusOffRecovered);
  }
}

bool Node::next_deadline(uint32_t now_us, uint32_t* at_us) const {
  NextDeadline d(now_us);
  next_deadline(d);
  return d.result(at_us);
}

// Mirrors process(): the same services under the same NMT conditions.
void Node::next_deadline(NextDeadline& d) const {
  if (save_.running()) {
    // The storage tells no time: a busy EEPROM byte is polled.
    if (storage_->ready == nullptr || storage_->ready(storage_->ctx)) return d.now();
    d.in(kSavePollUs);
  } else if (pending_reset_ != kResetNone) {
    return d.now();
  }
  if (nmt_.state() == kNmtInitialising) return;
  if (filters_stale_) return d.now();
  if (emcy_.active(kEmcyCanOverrun)) d.at(overflow_us_ + kControllerEventHoldUs);
  if (emcy_.active(kEmcyBusOffRecovered)) d.at(recovered_us_ + kControllerEventHoldUs);
  error_control_.next_deadline(d, static_cast<uint16_t>(od_.get(row_[k1017])), guard_time_ms(),
                               life_time_factor());
  if (nmt_.sdo_allowed()) {
    hb_consumer_.next_deadline(d);
    sync_.next_deadline(d);
    sdo_.next_deadline(d);
  }
  if (profile::kTime) TimeStamp::next_deadline(d, nmt_.sdo_allowed());
  if (nmt_.pdo_allowed()) {
    rpdos_.next_deadline(d);
    tpdos_.next_deadline(d);
  }
  emcy_.next_deadline(d, nmt_.emcy_allowed());
}

void Node::process(uint32_t now_us) {
  if (save_.running()) step_save();
  if (pending_reset_ != kResetNone && !save_.running()) {
    const NmtReset kind = pending_reset_;
    pending_reset_ = kResetNone;
    reset(kind, now_us);
  }
  if (nmt_.state() == kNmtInitialising) return;
  if (filters_stale_) update_filters();
  expire_controller_emcy(now_us);
  const ErrorControl::Event ev =
      error_control_.process(now_us, nmt_.state(), sink_, static_cast<uint16_t>(od_.get(row_[k1017])),
                             guard_time_ms(), life_time_factor());
  if (ev != ErrorControl::kNoEvent) {
    life_lost_ = ev == ErrorControl::kLifeGuardLost;
    update_guard_emcy();
  }
  if (nmt_.sdo_allowed()) {
    const bool lost = hb_consumer_.process(now_us) != 0;
    if (lost != hb_lost_) {
      hb_lost_ = lost;
      update_guard_emcy();
    }
    uint8_t counter = 0;
    if (sync_.process(now_us, true, sink_, &counter)) on_sync_event(counter, now_us);
    sdo_.process(now_us, sink_);
  }
  if (profile::kTime) TimeStamp::process(now_us, nmt_.sdo_allowed(), sink_);
  if (nmt_.pdo_allowed()) {
    rpdos_.process(now_us);
    tpdos_.process(now_us, sink_);
  }
  emcy_.process(now_us, nmt_.emcy_allowed(), sink_);
}

SdoAbort Node::on_hb_consumer_write(uint8_t sub, uint32_t value, bool apply) {
  const uint8_t id = static_cast<uint8_t>(value >> 16);
  const uint16_t time_ms = static_cast<uint16_t>(value);
  if (value >> 24) return kAbortInvalidValue;  // reserved bits
  if (id > 127) return kAbortInvalidValue;
  if (id != 0 && time_ms != 0) {
    // CiA 301 §7.5.2.34: one consumer time per node id.
    for (uint8_t s = 1; s <= kHbConsumers; ++s) {
      if (s == sub) continue;
      const uint32_t other = od_.get(static_cast<uint16_t>(row_[k1016] + s));
      if (static_cast<uint8_t>(other >> 16) == id && static_cast<uint16_t>(other) != 0) {
        return kAbortIncompatible;
      }
    }
  }
  if (apply) hb_consumer_.configure(sub, value);
  return kSdoOk;
}

HookResult Node::on_store_write(uint16_t index, uint32_t value, bool apply) {
  // 1011h is absent where the profile leaves it out: every write here saves.
  const bool save = !profile::kRestoreDefaults || index == 0x1010;
  // CiA 301 §7.5.2.13/14: the signature "save" or "load", and a storage.
  if (value != (save ? kSaveSignature : kLoadSignature) || storage_ == nullptr) return kAbortStore;
  if (save_.running()) return kAbortDeviceState;  // busy: poll 1010h/1 until it reads 1
  if (!apply) return HookResult::handled();
  if (!save) return params_erase(*storage_) ? HookResult::handled() : HookResult(kAbortGeneral);
  // Answered now, done over the next passes (step_save): a whole slot takes
  // ~1.5 s on the Uno, longer than masters wait for an answer.
  save_.start(od_, *storage_);
  od_.set(row_1010_, 0u);
  return HookResult::handled();
}

void Node::step_save() {
  const ParamSave::Result r = save_.step(od_, *storage_);
  if (r == ParamSave::kRunning) return;
  od_.set(row_1010_, 1u);
  // Failed: the previous set stays in force; reported until a save succeeds.
  emcy_.report(kEmcyStorage, r == ParamSave::kFailed, kErrGeneric);
}

bool Node::take_node_id_and_bitrate(NmtReset kind, uint8_t* node_id_entry,
                                    const uint16_t& bitrate_kbit_entry) {
  if (kind == kResetCommunication) {
    *node_id_entry = node_id_;
  } else if (!params_loaded_) {
    *node_id_entry = power_on_node_id_;
  }
  next_node_id_ = *node_id_entry;
  if (next_node_id_ != node_id_) return false;
  // The one place the bit rate reaches the controller (platform/device_port.h):
  // at every reset, before the boot-up message leaves.
  if (can_control_ != nullptr) {
    const CanControl control = flash_read(can_control_);
    if (control.set_bitrate != nullptr) control.set_bitrate(sink_.ctx, bitrate_kbit_entry);
  }
  return true;
}

// ---- the communication area's write handlers (od_comm.h) -------------------
// Each is the one place a write of its entries reaches the service that owns
// them; `apply` false decides only (OdWriteFunction). A write that may
// change what the node consumes (1005h, 1012h, 1016h, 1400h-1403h) makes
// the filters stale: the next process() hands acceptance() to the port.

HookResult NodeHandlers::error_control(void* node, uint16_t, uint8_t, const uint8_t*, bool apply) {
  if (apply) static_cast<Node*>(node)->error_control_.restart();
  return kSdoOk;
}

HookResult NodeHandlers::heartbeat_consumer(void* node, uint16_t, uint8_t sub, const uint8_t* data,
                                            bool apply) {
  Node& n = *static_cast<Node*>(node);
  if (apply) n.filters_stale_ = true;
  return n.on_hb_consumer_write(sub, le32(data), apply);
}

HookResult NodeHandlers::emcy(void* node, uint16_t index, uint8_t sub, const uint8_t* data, bool apply) {
  return static_cast<Node*>(node)->emcy_.on_write(index, sub, data, apply);
}

HookResult NodeHandlers::sync(void* node, uint16_t index, uint8_t, const uint8_t* data, bool apply) {
  Node& n = *static_cast<Node*>(node);
  if (apply) n.filters_stale_ = true;
  return n.sync_.on_write(index, data, apply);
}

// A mapping write hands the port the ranges in force once more (a port
// finds them set: nothing changes on the bus).
HookResult NodeHandlers::rpdo(void* node, uint16_t index, uint8_t sub, const uint8_t* data, bool apply) {
  Node& n = *static_cast<Node*>(node);
  if (apply) n.filters_stale_ = true;
  return n.rpdos_.on_write(index, sub, data, apply);
}

HookResult NodeHandlers::tpdo(void* node, uint16_t index, uint8_t sub, const uint8_t* data, bool apply) {
  return static_cast<Node*>(node)->tpdos_.on_write(index, sub, data, apply);
}

HookResult NodeHandlers::store(void* node, uint16_t index, uint8_t, const uint8_t* data, bool apply) {
  return static_cast<Node*>(node)->on_store_write(index, le32(data), apply);
}

// Only where the profile has TIME (od_comm.h lists them then).
HookResult NodeHandlers::time_cob_id(void* node, uint16_t index, uint8_t, const uint8_t* data, bool apply) {
  Node& n = *static_cast<Node*>(node);
  if (apply) n.filters_stale_ = true;
  return n.TimeStamp::on_write(index, data, apply);
}

HookResult NodeHandlers::time_stamp(void* node, uint16_t index, uint8_t, const uint8_t* data, bool apply) {
  return static_cast<Node*>(node)->TimeStamp::on_write(index, data, apply);
}

// The id's range (1..127) is the entry's limit.
HookResult NodeHandlers::node_id(void* node, uint16_t, uint8_t, const uint8_t* data, bool apply) {
  if (apply) static_cast<Node*>(node)->next_node_id_ = data[0];  // at reset communication
  return kSdoOk;
}

// The MCP2515's rates (platform/device_port.h, CanControl::set_bitrate);
// in force from the next reset (Node::take_node_id_and_bitrate).
HookResult NodeHandlers::bitrate(void*, uint16_t, uint8_t, const uint8_t* data, bool) {
  const uint16_t kbit = le16(data);
  if (kbit != 125 && kbit != 250 && kbit != 500 && kbit != 1000) return kAbortInvalidValue;
  return kSdoOk;
}

// A request, not a setting: it reads back 0. Its range (0..2) is the
// entry's limit.
HookResult NodeHandlers::restart_request(void* node, uint16_t, uint8_t, const uint8_t* data, bool apply) {
  if (apply && data[0] != 0) {
    static_cast<Node*>(node)->request_reset(data[0] == 1 ? kResetCommunication : kResetNode);
  }
  return HookResult::handled();
}

}  // namespace canopen
}  // namespace mb2co
