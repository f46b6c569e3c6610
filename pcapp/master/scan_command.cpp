// scan: which node ids answer SDO, all asked at once. A node counts as
// present when it answers the upload of 1000h (device type, mandatory in
// every CiA 301 device) with data or with an abort; then 1018h/1-4 and
// 1008h are read from it. Silence within the SDO timeout: no node there
// (no abort is sent to it: a probe). The probes are one burst on the bus; a
// node whose filters let others' requests in may lose a frame in it (the
// Uno's MCP2515 holds two), so a read from a node that answered its probe
// and then stays silent is asked once more, after its timeout, when the
// burst is long gone.
#include <cstdio>
#include <functional>
#include <map>
#include <memory>
#include <vector>

#include "canopen/od.h"
#include "commands.h"
#include "exit_codes.h"
#include "transfer_run.h"

namespace mb2co {
namespace master {

namespace {

/// What a node that answered its probe is asked. The transfers live in
/// `asked` (never freed while the scan runs: a retry is queued from the
/// on_done of the transfer it replaces); the other members point into it.
struct Found {
  const Transfer* identity[4] = {};  ///< 1018h/1..4, the last try
  const Transfer* name = nullptr;    ///< 1008h, the last try
  std::vector<std::unique_ptr<Transfer>> asked;
};

/// The SDO timeout without an answer: a lost frame when the node is there.
bool silent(const Transfer& t) {
  return !t.ok() && !t.by_server && t.result == canopen::kAbortTimeout && t.gateway_error.empty();
}

std::string u32_text(const Transfer* t) {
  if (!t || !t->ok() || t->data.size() != 4) return "-";
  const uint32_t v = canopen::le32(t->data.data());
  char b[16];
  std::snprintf(b, sizeof b, "0x%08X", v);
  return b;
}

std::string text_of(const Transfer* t) {
  if (!t || !t->ok()) return "";
  std::string s;
  for (uint8_t c : t->data)
    s += (c >= 0x20 && c < 0x7F && c != '"' && c != '\\') ? static_cast<char>(c) : '?';
  return s;
}

}  // namespace

int scan_command(const Options& o, Transport& transport, std::ostream& out, std::ostream& err) {
  const std::vector<std::string>& w = o.args.operands;  // at most 2 (the table)
  uint8_t first = 1, last = 127;
  if (!w.empty()) {
    Status s = parse_node_id(w[0], false, &first);
    if (s) last = w.size() == 2 ? 0 : 127;
    if (s && w.size() == 2) s = parse_node_id(w[1], false, &last);
    if (!s) return fail(err, kExitUsage, "scan: " + s.message());
    if (last < first) return fail(err, kExitUsage, "scan: LAST below FIRST");
  }
  if (const int code = open_transport(o, transport, err)) return code;
  TransferRun run(o, transport);
  std::map<uint8_t, Found> found;
  auto make = [](uint8_t node, uint16_t index, uint8_t sub) {
    std::unique_ptr<Transfer> t(new Transfer);
    t->node = node;
    t->index = index;
    t->sub = sub;
    return t;
  };
  // Queues a read of (index, sub) from `node`, noted in *slot; once more if
  // the first try gets no answer (`tries` left after this one).
  std::function<void(uint8_t, uint16_t, uint8_t, const Transfer**, int)> ask;
  ask = [&](uint8_t node, uint16_t index, uint8_t sub, const Transfer** slot, int tries) {
    Found& f = found[node];
    f.asked.push_back(make(node, index, sub));
    Transfer* t = f.asked.back().get();
    *slot = t;
    if (tries > 0)
      t->on_done = [&ask, node, index, sub, slot, tries](Transfer& done) {
        if (silent(done)) ask(node, index, sub, slot, tries - 1);
      };
    run.network().queue(t);
  };
  std::map<uint8_t, std::unique_ptr<Transfer>> probes;
  for (int id = first; id <= last; ++id) {
    const uint8_t node = static_cast<uint8_t>(id);
    probes[node] = make(node, 0x1000, 0);
    probes[node]->probe = true;
    probes[node]->on_done = [&, node](Transfer& t) {
      if (!t.ok() && !t.by_server) return;  // silence: nobody there
      Found& f = found[node];
      for (uint8_t sub = 1; sub <= 4; ++sub) ask(node, 0x1018, sub, &f.identity[sub - 1], 1);
      ask(node, 0x1008, 0, &f.name, 1);
    };
    run.network().queue(probes[node].get());
  }
  if (!run.run()) return fail(err, kExitInterrupted, "scan: interrupted");
  const Status link = run.network().link_status();
  if (!link) return fail(err, kExitBus, "scan: " + link.message());
  for (auto& p : found) {
    const uint8_t node = p.first;
    Found& f = p.second;
    const Transfer* dt = probes[node].get();
    if (o.json) {
      out << "{\"node\":" << unsigned(node) << ",\"device_type\":\"" << u32_text(dt) << "\",\"vendor\":\""
          << u32_text(f.identity[0]) << "\",\"product\":\"" << u32_text(f.identity[1]) << "\",\"revision\":\""
          << u32_text(f.identity[2]) << "\",\"serial\":\"" << u32_text(f.identity[3]) << "\",\"name\":\""
          << text_of(f.name) << "\"}\n";
    } else {
      out << "node " << unsigned(node) << ": device type " << u32_text(dt) << ", vendor "
          << u32_text(f.identity[0]) << ", product " << u32_text(f.identity[1]) << ", revision "
          << u32_text(f.identity[2]) << ", serial " << u32_text(f.identity[3]) << ", name \""
          << text_of(f.name) << "\"\n";
    }
  }
  if (!o.json) out << "scan: " << found.size() << " of " << (last - first + 1) << " node ids answered\n";
  return found.empty() ? fail(err, kExitNoAnswer, "scan: no node answered") : kExitOk;
}

}  // namespace master
}  // namespace mb2co
