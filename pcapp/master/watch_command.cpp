// watch: the bus as a master sees it. Per node: NMT state and heartbeat age
// (NodeMonitor), last EMCY decoded (EmcyConsumer), PDOs decoded into the
// node's objects (ProcessImage) by the mapping read from the node by SDO
// each time it becomes operational (after a remapping in pre-operational,
// the new one), or as raw bytes with --raw or before the mapping is known.
// Events go out as lines (or JSON lines) the moment they happen; on a
// terminal a table of the nodes is redrawn twice a second as well.
#include <unistd.h>

#include <cstdio>
#include <deque>
#include <iostream>
#include <map>
#include <memory>

#include "canopen/master/emcy_consumer.h"
#include "canopen/master/emcy_names.h"
#include "canopen/master/node_monitor.h"
#include "canopen/master/process_image.h"
#include "canopen/nmt_slave.h"
#include "canopen/od.h"
#include "commands.h"
#include "exit_codes.h"
#include "sdo_network.h"

namespace mb2co {
namespace master {

namespace {

const char* state_name(uint8_t s) {
  switch (s) {
    case canopen::kNmtInitialising:
      return "boot-up";
    case canopen::kNmtStopped:
      return "stopped";
    case canopen::kNmtOperational:
      return "operational";
    case canopen::kNmtPreOperational:
      return "pre-operational";
    case canopen::kNodeStateUnknown:
      return "unknown";
    default:
      return "invalid";
  }
}

std::string hex(const uint8_t* p, int n) {
  std::string s;
  char b[4];
  for (int i = 0; i < n; ++i) {
    std::snprintf(b, sizeof b, i ? " %02X" : "%02X", p[i]);
    s += b;
  }
  return s;
}

class WatchService : public BusService {
 public:
  /// `sdo`: where the TPDO mappings are read from (null: raw PDOs only).
  WatchService(std::ostream* out, bool json, bool table, SdoNetwork* sdo)
      : out_(out), json_(json), table_(table), sdo_(sdo) {
    monitors_.set_listener(canopen::MonitorListener{&WatchService::on_monitor, this});
    emcy_.set_listener(canopen::EmcyListener{&WatchService::on_emcy, this});
  }
  /// Node guarding instead of heartbeat (a node with 1017h = 0): an RTR every
  /// `guard_ms`, lost after guard_ms × `life_factor` without an answer.
  bool guard(uint8_t node, uint16_t guard_ms, uint8_t life_factor) {
    canopen::NodeMonitor* m = monitors_.monitor(node);
    return m && m->watch_guarding(node, guard_ms, life_factor);
  }
  /// Only these nodes' EMCYs and PDOs are shown (all when never called).
  void show_only(const std::vector<uint8_t>& nodes) {
    shown_.assign(128, false);
    for (uint8_t id : nodes) shown_[id] = true;
  }
  bool shown(uint8_t node) const { return shown_.empty() || (node < shown_.size() && shown_[node]); }
  bool watch(uint8_t node, uint16_t consumer_ms) {
    canopen::NodeMonitor* m = monitors_.monitor(node);
    // The producer time is not known to a passive watcher; any below the
    // consumer time is allowed, and only the consumer time matters here.
    return m && m->watch_heartbeat(node, 1, consumer_ms);
  }
  void on_frame(const CanFrame& f, uint32_t now_us, const CanSink&) override {
    if (f.extended()) return;
    if (f.id >= 0x701 && f.id <= 0x77F && !f.rtr() && f.dlc >= 1)
      last_heard_us_[static_cast<uint8_t>(f.id - 0x700)] = now_us;
    if (monitors_.on_frame(f, now_us)) return;
    if (emcy_.on_frame(f, now_us)) return;
    if (f.id >= 0x180 && f.id <= 0x57F && !f.rtr()) {
      if (image_.on_frame(f, now_us))
        decoded(f);
      else
        pdo(f, now_us);
    }
  }
  void process(uint32_t now_us, const CanSink& sink) override {
    now_us_ = now_us;
    monitors_.process(now_us, sink);
    if (table_ && time_reached(now_us, redraw_at_us_)) {
      draw(now_us);
      redraw_at_us_ = now_us + 500000u;
    }
  }
  void next_deadline(NextDeadline& d) const override {
    monitors_.next_deadline(d);
    if (table_) d.at(redraw_at_us_);
  }

 private:
  static void on_monitor(void* ctx, uint8_t node, canopen::MonitorEvent e, uint8_t from, uint8_t to) {
    auto* self = static_cast<WatchService*>(ctx);
    if (e == canopen::kMonitorStateChanged && to == canopen::kNmtOperational) self->read_mapping(node);
    const char* what = e == canopen::kMonitorNodeLost      ? "lost"
                       : e == canopen::kMonitorNodeBack    ? "back"
                       : e == canopen::kMonitorBootUp      ? "boot-up"
                       : e == canopen::kMonitorToggleError ? "toggle-error"
                                                           : "state";
    char line[160];
    if (self->json_)
      std::snprintf(line, sizeof line, "{\"node\":%u,\"event\":\"%s\",\"from\":\"%s\",\"to\":\"%s\"}", node,
                    what, state_name(from), state_name(to));
    else if (e == canopen::kMonitorStateChanged)
      std::snprintf(line, sizeof line, "node %u state %s -> %s", node, state_name(from), state_name(to));
    else
      std::snprintf(line, sizeof line, "node %u %s", node, what);
    self->event(line);
  }
  static void on_emcy(void* ctx, uint8_t node, const canopen::EmcyMessage& m, uint32_t) {
    auto* self = static_cast<WatchService*>(ctx);
    if (!self->shown(node)) return;
    std::string bits;
    for (uint8_t b = 1; b != 0; b = static_cast<uint8_t>(b << 1)) {
      if (!(m.error_register & b)) continue;
      if (!bits.empty()) bits += ", ";
      bits += canopen::error_register_bit_name(b);
    }
    char line[320];
    if (self->json_)
      std::snprintf(line, sizeof line,
                    "{\"node\":%u,\"event\":\"emcy\",\"code\":\"%04X\",\"name\":\"%s\",\"register\":\"%02X\","
                    "\"register_bits\":\"%s\",\"manufacturer\":\"%s\"}",
                    node, m.code, canopen::emcy_code_name(m.code), m.error_register, bits.c_str(),
                    hex(m.manufacturer, 5).c_str());
    else
      std::snprintf(line, sizeof line, "node %u emcy %04Xh %s, register %02Xh%s%s%s, manufacturer %s", node,
                    m.code, canopen::emcy_code_name(m.code), m.error_register, bits.empty() ? "" : " (",
                    bits.c_str(), bits.empty() ? "" : ")", hex(m.manufacturer, 5).c_str());
    self->event(line);
  }
  /// Reads TPDO1..4's COB-ID (1800h+n/1) and mapping (1A00h+n/0..8) of
  /// `node`, one transfer after the other, then configures the image.
  void read_mapping(uint8_t node) {
    if (!sdo_) return;
    for (uint8_t n = 0; n < 4; ++n) {
      Transfer& cob = add(node, static_cast<uint16_t>(0x1800 + n), 1);
      cob.on_done = [this, node, n](Transfer& c) {
        if (!c.ok() || c.data.size() != 4) return;
        const uint32_t cob_id = canopen::le32(c.data.data());
        if (cob_id & 0x80000000u) return;  // not valid: nothing to decode
        Transfer& count = add(node, static_cast<uint16_t>(0x1A00 + n), 0);
        count.on_done = [this, node, n, cob_id](Transfer& k) {
          if (!k.ok() || k.data.size() != 1 || k.data[0] == 0 || k.data[0] > 8) return;
          auto mapping = std::make_shared<std::vector<uint32_t>>();
          const uint8_t entries = k.data[0];
          for (uint8_t sub = 1; sub <= entries; ++sub) {
            Transfer& e = add(node, static_cast<uint16_t>(0x1A00 + n), sub);
            e.on_done = [this, node, n, cob_id, mapping, entries](Transfer& m) {
              if (!m.ok() || m.data.size() != 4) return;
              mapping->push_back(canopen::le32(m.data.data()));
              if (mapping->size() != entries) return;
              if (image_.configure_tpdo(node, n, static_cast<uint16_t>(cob_id & 0x7FF), mapping->data(),
                                        entries)) {
                mappings_[static_cast<uint32_t>(node) << 8 | n] = *mapping;
                pdo_of_cob_[static_cast<uint16_t>(cob_id & 0x7FF)] = std::make_pair(node, n);
              }
            };
          }
        };
      };
    }
  }
  /// A transfer kept alive until the watch ends (deque: stable addresses).
  Transfer& add(uint8_t node, uint16_t index, uint8_t sub) {
    transfers_.emplace_back();
    Transfer& t = transfers_.back();
    t.node = node;
    t.index = index;
    t.sub = sub;
    sdo_->queue(&t);
    return t;
  }
  /// "node 3 TPDO1 2100h/2=0x1 2100h/3=0x0 2120h/1=0x0"
  void decoded(const CanFrame& f) {
    const auto which = pdo_of_cob_.find(static_cast<uint16_t>(f.id));
    if (which == pdo_of_cob_.end()) return;
    const uint8_t node = which->second.first, n = which->second.second;
    const canopen::ImagePdo* p = image_.pdo(node, n, false);
    if (!p) return;
    std::string text;
    char item[64];
    for (uint8_t k = 0; k < p->count; ++k) {
      if (p->entry[k] == canopen::ImagePdo::kDummy) continue;
      const canopen::ImageEntry* e = entry_of(node, p, k);
      if (!e) continue;
      if (json_)
        std::snprintf(item, sizeof item, "%s\"%04X/%u\":\"0x%X\"", text.empty() ? "" : ",", e->index, e->sub,
                      e->u32());
      else
        std::snprintf(item, sizeof item, " %04Xh/%u=0x%X", e->index, e->sub, e->u32());
      text += item;
    }
    // Only changes: a cyclic PDO would flood the log.
    std::string& last = decoded_[static_cast<uint16_t>(f.id)];
    if (text == last) return;
    last = text;
    char head[64];
    if (json_) {
      std::snprintf(head, sizeof head, "{\"node\":%u,\"event\":\"tpdo\",\"n\":%u,\"values\":{", node, n + 1);
      event((std::string(head) + text + "}}").c_str());
    } else {
      std::snprintf(head, sizeof head, "node %u TPDO%u", node, n + 1);
      event((std::string(head) + text).c_str());
    }
  }
  /// The image entry the k-th mapping entry of `p` decodes into.
  const canopen::ImageEntry* entry_of(uint8_t node, const canopen::ImagePdo* p, uint8_t k) const {
    // The mapping as configured is kept beside the image: look it up there.
    const auto m = mappings_.find(static_cast<uint32_t>(node) << 8 | p->n);
    if (m == mappings_.end() || k >= m->second.size()) return nullptr;
    const uint32_t e = m->second[k];
    return image_.find(node, static_cast<uint16_t>(e >> 16), static_cast<uint8_t>(e >> 8));
  }
  void pdo(const CanFrame& f, uint32_t) {
    // A PDO of the default connection set names its node in the low 7 bits.
    if (!shown(static_cast<uint8_t>(f.id & 0x7F))) return;
    std::string& last = pdos_[static_cast<uint16_t>(f.id)];
    const std::string data = hex(f.data, f.dlc);
    if (data == last && !last.empty()) return;  // only changes: a cyclic PDO would flood the log
    last = data;
    char line[160];
    if (json_)
      std::snprintf(line, sizeof line, "{\"event\":\"pdo\",\"cob_id\":\"%03X\",\"data\":\"%s\"}", f.id,
                    data.c_str());
    else
      std::snprintf(line, sizeof line, "pdo %03Xh %s", f.id, data.c_str());
    event(line);
  }
  void event(const char* line) {
    if (table_) return;  // the table shows it; lines would scroll it away
    *out_ << line << "\n" << std::flush;
  }
  void draw(uint32_t now_us) {
    std::string s = "\x1b[H\x1b[2Jnode  state             heartbeat age  last EMCY\n";
    char row[200];
    for (uint8_t id = 1; id <= 127; ++id) {
      const canopen::NodeMonitor* m = monitors_.find(id);
      if (!m) continue;
      const auto heard = last_heard_us_.find(id);
      const canopen::EmcyRecord* e = emcy_.record(id);
      char age[32] = "-";
      if (heard != last_heard_us_.end())
        std::snprintf(age, sizeof age, "%.1f s", static_cast<double>(now_us - heard->second) / 1e6);
      char last_emcy[96] = "-";
      if (e)
        std::snprintf(last_emcy, sizeof last_emcy, "%04Xh %s", e->last.code,
                      canopen::emcy_code_name(e->last.code));
      std::snprintf(row, sizeof row, "%4u  %-16s  %13s  %s%s\n", id, state_name(m->state()), age, last_emcy,
                    m->link() == canopen::kLinkLost ? "  LOST" : "");
      s += row;
    }
    for (const auto& p : pdos_) {
      std::snprintf(row, sizeof row, "pdo %03Xh  %s\n", p.first, p.second.c_str());
      s += row;
    }
    *out_ << s << std::flush;
  }

  std::ostream* out_;
  bool json_;
  bool table_;
  uint32_t now_us_ = 0;
  uint32_t redraw_at_us_ = 0;
  SdoNetwork* sdo_;
  std::deque<Transfer> transfers_;
  canopen::ProcessImage<64, 200> image_;
  std::map<uint16_t, std::string> decoded_;
  std::vector<bool> shown_;
  std::map<uint16_t, std::pair<uint8_t, uint8_t>> pdo_of_cob_;  ///< TPDO COB-ID → (node, n) ///< by node id;
                                                                ///< empty: every node
  std::map<uint32_t, std::vector<uint32_t>> mappings_;  ///< node << 8 | n → 1A0xh entries
  canopen::NodeMonitorTable<127> monitors_;
  canopen::EmcyConsumer<127> emcy_;
  std::map<uint8_t, uint32_t> last_heard_us_;
  std::map<uint16_t, std::string> pdos_;
};

}  // namespace

int watch_command(const Options& o, Transport& transport, std::ostream& out, std::ostream& err) {
  if (!transport.bus()) return fail(err, kExitUsage, "watch: " + needs_can_frames("watch"));
  BusLoop& bus = *transport.bus();
  std::vector<uint8_t> nodes;
  if (o.args.has("--nodes")) {
    const Status s = parse_node_list(o.args.get("--nodes"), &nodes);
    if (!s) return fail(err, kExitUsage, "watch: " + s.message());
  } else {
    for (int id = 1; id <= 127; ++id) nodes.push_back(static_cast<uint8_t>(id));
  }
  // Ranges checked by the parser (the table in cli_options.cpp).
  const uint64_t consumer_ms = o.args.uint("--heartbeat", 1000);
  const uint64_t for_ms = o.args.duration_ms("--for", 0);
  const uint64_t guard_ms = o.args.uint("--guard", 0);
  const uint64_t life_factor = o.args.uint("--life", 3);
  if (o.args.has("--guard") && o.args.has("--heartbeat"))
    return fail(err, kExitUsage, "watch: --heartbeat or --guard, not both");
  if (o.args.has("--life") && !o.args.has("--guard"))
    return fail(err, kExitUsage, "watch: --life is the guarding's life time factor: only with --guard");
  const bool raw = o.args.has("--raw");
  const bool table = !o.json && isatty(STDOUT_FILENO) && &out == &std::cout;
  if (const int code = open_transport(o, transport, err)) return code;
  // Mappings are read by SDO unless --raw (a watch that only listens).
  static SdoNetwork sdo(o.timeout_ms * 1000u, 0);
  if (!raw) bus.add(&sdo);
  static WatchService service(&out, o.json, table, raw ? nullptr : &sdo);  // large: not on the stack
  service.show_only(nodes);
  for (uint8_t id : nodes) {
    if (guard_ms)
      service.guard(id, static_cast<uint16_t>(guard_ms), static_cast<uint8_t>(life_factor));
    else
      service.watch(id, static_cast<uint16_t>(consumer_ms));
  }
  bus.add(&service);
  // Said once the socket is bound: from here on nothing on the bus is missed
  // (a script or test may start the nodes after this line).
  if (o.json)
    out << "{\"event\":\"watching\",\"interface\":\"" << o.iface << "\",\"nodes\":" << nodes.size()
        << ",\"heartbeat_ms\":" << consumer_ms << "}\n";
  else if (!table)
    out << "watching " << o.iface << ": " << nodes.size() << " node ids, "
        << (guard_ms ? "guarding every " + std::to_string(guard_ms) + " ms, life time factor " +
                           std::to_string(life_factor)
                     : "heartbeat consumer " + std::to_string(consumer_ms) + " ms")
        << "\n";
  out << std::flush;
  if (for_ms) {
    bus.run_until([] { return false; }, static_cast<uint32_t>(for_ms * 1000u));
  } else {
    while (!bus.interrupted()) bus.run_until([] { return false; }, BusLoop::kLongestRunUs);
  }
  return kExitOk;
}

}  // namespace master
}  // namespace mb2co
