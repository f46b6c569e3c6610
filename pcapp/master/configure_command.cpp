// configure: CiA 302-2 style configuration of the nodes of a network file
// from their DCFs, all nodes at once (or --one-at-a-time). Per node, one
// chain of SDO transfers on its queue, each step queued by the previous
// one's on_done:
//   1. identity: 1018h/1..3 read and compared with the DCF's values
//      (ParameterValue, else DefaultValue) where it gives them; silence at
//      1018h/1 means the node is missing;
//   2. every sub with a ParameterValue (resolved with the node id) that is
//      not ro/const is read; the ones that differ are written, the first
//      abort stops the node and undoes it (all or nothing per node): what
//      was written is written back with the value read in this step, in
//      the reverse order (a PDO's entries again in the CiA 301 order), one
//      line per entry restored;
//      (1003h error history, 1010h and 1011h store/restore commands and
//      1013h, the node's clock (TIME), are never written from a DCF: what a
//      dump reads there is a record, a capability or an instant, not a
//      setting);
//   3. --save: 1010h/1 = "save", then 1010h/1 polled every 100 ms until it
//      reads 1 again (the save is done; at most 10 s); then, unless
//      --no-start, NMT start.
// PDO parameters are written in the CiA 301 order whatever order the DCF
// lists them in: for a PDO with something to change, its COB-ID is written
// with bit 31 (not valid) first, its mapping count set to 0 before mapping
// entries are written, then the count, then the COB-ID the DCF gives (or the
// one it had).
#include <cstdio>
#include <deque>
#include <functional>
#include <map>
#include <memory>

#include "abort_text.h"
#include "commands.h"
#include "eds_reader.h"
#include "eds_value.h"
#include "exit_codes.h"
#include "network_file.h"
#include "transfer_run.h"

namespace mb2co {
namespace master {

namespace {

std::string where(uint16_t index, uint8_t sub) {
  char b[24];
  std::snprintf(b, sizeof b, "%04Xh/%u", index, sub);
  return b;
}

std::string hex8(uint32_t v) {
  char b[16];
  std::snprintf(b, sizeof b, "%08Xh", v);
  return b;
}

std::string hex32(uint32_t v) {
  char b[16];
  std::snprintf(b, sizeof b, "0x%08X", v);
  return b;
}

uint32_t u32_of(const std::vector<uint8_t>& b) {
  uint32_t v = 0;
  for (size_t i = 0; i < b.size() && i < 4; ++i) v |= static_cast<uint32_t>(b[i]) << (8 * i);
  return v;
}

std::vector<uint8_t> bytes_of(uint32_t v, size_t n) {
  std::vector<uint8_t> b(n);
  for (size_t i = 0; i < n; ++i) b[i] = static_cast<uint8_t>(v >> (8 * i));
  return b;
}

bool is_pdo_comm(uint16_t i) {
  return (i >= 0x1400 && i <= 0x15FF) || (i >= 0x1800 && i <= 0x19FF);
}
bool is_pdo_map(uint16_t i) {
  return (i >= 0x1600 && i <= 0x17FF) || (i >= 0x1A00 && i <= 0x1BFF);
}

/// One node's configuration, run as a chain of transfers. Owns its
/// transfers (a deque: queued Transfers must not move).
class NodeJob {
 public:
  enum Outcome { kRunning, kConfigured, kRefused, kMissing };

  NodeJob(const NetworkNode& node, eds::DeviceDescription dcf, TransferNetwork* net, bool save)
      : node_(node), dcf_(std::move(dcf)), net_(net), save_(save) {}

  /// Called once when the job ended, whatever the outcome.
  std::function<void()> on_finished;

  void start() { read_identity(1); }

  uint8_t id() const { return node_.id; }
  Outcome outcome() const { return outcome_; }
  const std::string& why() const { return why_; }
  unsigned written() const { return written_; }
  unsigned equal() const { return equal_; }
  unsigned read_only() const { return read_only_; }
  bool saved() const { return saved_; }
  /// After a refused write: one line per entry written back ("restored
  /// 1017h/0 = 0x64") or that could not be ("not restored 2001h/0: ...").
  const std::vector<std::string>& restore_lines() const { return restore_lines_; }

 private:
  /// A sub the DCF configures (or, `counted` false, one read for the PDO
  /// order only).
  struct Entry {
    uint16_t index = 0;
    uint8_t sub = 0;
    std::vector<uint8_t> want;
    bool counted = true;
    Transfer* read = nullptr;
    bool known() const { return read && read->ok(); }
    bool differs() const { return !known() || read->data != want; }
  };
  struct Write {
    uint16_t index;
    uint8_t sub;
    std::vector<uint8_t> bytes;
    bool reported = false;  ///< a restore step with a line (not the PDO order's own steps)
  };

  /// A transfer of this node's, not queued yet.
  Transfer& make(uint16_t index, uint8_t sub, bool upload, std::vector<uint8_t> bytes,
                 std::function<void(Transfer&)> done) {
    transfers_.emplace_back();
    Transfer& t = transfers_.back();
    t.node = node_.id;
    t.index = index;
    t.sub = sub;
    t.upload = upload;
    t.data = std::move(bytes);
    t.on_done = std::move(done);
    return t;
  }
  /// make() and queue it (its on_done may run before this returns).
  void queue(uint16_t index, uint8_t sub, bool upload, std::vector<uint8_t> bytes,
             std::function<void(Transfer&)> done) {
    net_->queue(&make(index, sub, upload, std::move(bytes), std::move(done)));
  }

  void finish(Outcome o, const std::string& why = std::string()) {
    if (outcome_ != kRunning) return;
    outcome_ = o;
    why_ = why;
    if (on_finished) on_finished();
  }

  /// A failed transfer ends the job: silence is "missing", an abort "refused".
  /// What is still queued for the node is dropped: after silence it would
  /// only wait out one SDO timeout each.
  void failed(const Transfer& t, const char* what) {
    net_->drop_queued(node_.id, canopen::kAbortTimeout);
    if (!t.by_server)
      finish(kMissing, "no answer to " + where(t.index, t.sub));
    else
      finish(kRefused, std::string(what) + " " + where(t.index, t.sub) + ": SDO abort " + hex8(t.result) +
                           " (" + abort_text(t.result) + ")");
  }

  void read_identity(uint8_t sub) {
    queue(0x1018, sub, true, {}, [this, sub](Transfer& t) {
      if (!t.ok()) return failed(t, "reading");
      static const char* const kWhat[] = {"", "vendor", "product", "revision"};
      const eds::SubObject* s = dcf_.find(0x1018, sub);
      std::optional<eds::Value> want;
      if (s && s->parameter_value) want = eds::resolve(s->type, *s->parameter_value, node_.id);
      if (s && !s->parameter_value && s->default_value)
        want = eds::resolve(s->type, *s->default_value, node_.id);
      if (want && u32_of(want->bytes) != u32_of(t.data))
        return finish(kRefused, std::string("wrong identity: ") + kWhat[sub] + " " + hex32(u32_of(t.data)) +
                                    " want " + hex32(u32_of(want->bytes)));
      if (sub < 3) return read_identity(static_cast<uint8_t>(sub + 1));
      read_current();
    });
  }

  void add_entry(uint16_t index, uint8_t sub, std::vector<uint8_t> want, bool counted) {
    for (Entry& e : entries_)
      if (e.index == index && e.sub == sub) return;
    Entry e;
    e.index = index;
    e.sub = sub;
    e.want = std::move(want);
    e.counted = counted;
    entries_.push_back(std::move(e));
  }

  Entry* entry(uint16_t index, uint8_t sub) {
    for (Entry& e : entries_)
      if (e.index == index && e.sub == sub) return &e;
    return nullptr;
  }

  /// Step 2: the current value of everything the DCF configures.
  void read_current() {
    for (const auto& p : dcf_.objects) {
      for (const eds::SubObject& s : p.second.subs) {
        // 1010h/1011h are commands (a signature starts them), not values:
        // a DCF's ParameterValue there is what the node said it can do.
        // 1003h is the error history: a record of the node's, which only
        // takes 0 (clear); a dumped count is no setting either. 1013h is the
        // node's clock: a dumped value is the instant of the dump, and
        // writing it would set the clock back.
        if (!s.parameter_value || p.first == 0x1003 || p.first == 0x1010 || p.first == 0x1011 ||
            p.first == 0x1013)
          continue;
        if (s.access == eds::AccessType::kRo || s.access == eds::AccessType::kConst) {
          ++read_only_;
          continue;
        }
        const auto want = eds::resolve(s.type, *s.parameter_value, node_.id);
        if (!want)
          return finish(kRefused, "ParameterValue of " + where(p.first, s.sub) + " does not fit its type");
        add_entry(p.first, s.sub, want->bytes, true);
      }
    }
    // What the PDO order needs to know even when the DCF does not set it:
    // the COB-ID (to disable and re-enable) and the mapping count.
    std::vector<Entry> aux;
    for (const Entry& e : entries_) {
      const uint16_t comm = is_pdo_map(e.index) ? static_cast<uint16_t>(e.index - 0x200) : e.index;
      if (!is_pdo_comm(comm)) continue;
      aux.push_back(Entry{comm, 1, {}, false, nullptr});
      aux.push_back(Entry{static_cast<uint16_t>(comm + 0x200), 0, {}, false, nullptr});
    }
    for (Entry& e : aux) add_entry(e.index, e.sub, e.want, false);
    reads_left_ = entries_.size();
    if (reads_left_ == 0) return write_next();
    for (Entry& e : entries_) {
      e.read = &make(e.index, e.sub, true, {}, [this](Transfer& t) {
        // Silence ends the node; an abort (e.g. write-only) just means
        // "unknown, write it".
        if (!t.ok() && !t.by_server) return failed(t, "reading");
        if (--reads_left_ == 0 && outcome_ == kRunning) plan();
      });
    }
    for (Entry& e : entries_) net_->queue(e.read);
  }

  /// Turns what differs into writes, PDOs in the CiA 301 order.
  void plan() {
    for (const Entry& e : entries_) {
      if (!e.counted) continue;
      if (e.differs())
        ++written_;
      else
        ++equal_;
    }
    for (const Entry& e : entries_)
      if (e.counted && e.differs() && !is_pdo_comm(e.index) && !is_pdo_map(e.index))
        writes_.push_back(Write{e.index, e.sub, e.want});
    for (const Entry& cob : entries_)  // one COB-ID entry per PDO the DCF touches
      if (is_pdo_comm(cob.index) && cob.sub == 1) plan_pdo(cob.index);
    write_next();
  }

  void plan_pdo(uint16_t comm) {
    const uint16_t map = static_cast<uint16_t>(comm + 0x200);
    bool comm_differs = false, map_differs = false;
    for (const Entry& e : entries_) {
      if (!e.counted || !e.differs()) continue;
      if (e.index == comm) comm_differs = true;
      if (e.index == map) map_differs = true;
    }
    if (!comm_differs && !map_differs) return;
    const Entry* cob = entry(comm, 1);
    const Entry* count = entry(map, 0);
    const std::vector<uint8_t> cob_now = cob->known() ? cob->read->data : std::vector<uint8_t>();
    const std::vector<uint8_t> cob_want = cob->counted ? cob->want : cob_now;
    if (cob_now.size() == 4 && !(u32_of(cob_now) & 0x80000000u))
      writes_.push_back(Write{comm, 1, bytes_of(u32_of(cob_now) | 0x80000000u, 4)});
    for (const Entry& e : entries_)
      if (e.index == comm && e.sub != 1 && e.counted && e.differs())
        writes_.push_back(Write{comm, e.sub, e.want});
    if (map_differs) {
      writes_.push_back(Write{map, 0, {0}});
      for (const Entry& e : entries_)
        if (e.index == map && e.sub != 0 && e.counted) writes_.push_back(Write{map, e.sub, e.want});
      const std::vector<uint8_t> n =
          count->counted ? count->want : (count->known() ? count->read->data : std::vector<uint8_t>());
      if (!n.empty()) writes_.push_back(Write{map, 0, n});
    }
    if (!cob_want.empty()) writes_.push_back(Write{comm, 1, cob_want});
  }

  void write_next() {
    if (next_write_ < writes_.size()) {
      const Write& w = writes_[next_write_++];
      queue(w.index, w.sub, false, w.bytes, [this](Transfer& t) {
        if (!t.ok()) return refused_write(t);
        write_next();
      });
      return;
    }
    if (save_ && !saved_) {
      queue(0x1010, 1, false, bytes_of(0x65766173u, 4), [this](Transfer& t) {  // "save"
        if (!t.ok()) return failed(t, "saving");
        save_started_us_ = t.ended_us;
        poll_save(t.ended_us);
      });
      return;
    }
    finish(kConfigured);
  }

  /// writes_[0, next_write_ - 1) were applied when `t` failed: the outcome
  /// is decided now, the restore runs before on_finished.
  void refused_write(const Transfer& t) {
    net_->drop_queued(node_.id, canopen::kAbortTimeout);
    const std::string what = "writing " + where(t.index, t.sub);
    pending_why_ = t.by_server ? what + ": SDO abort " + hex8(t.result) + " (" + abort_text(t.result) + ")"
                               : "no answer to " + where(t.index, t.sub);
    pending_outcome_ = t.by_server ? kRefused : kMissing;
    plan_restore(next_write_ - 1);
    next_restore_ = 0;
    restore_next();
  }

  /// The value read before (step 2), or nullptr when the read failed.
  const std::vector<uint8_t>* before(uint16_t index, uint8_t sub) {
    const Entry* e = entry(index, sub);
    return e && e->known() ? &e->read->data : nullptr;
  }

  void add_restore(uint16_t index, uint8_t sub) {
    const std::vector<uint8_t>* old = before(index, sub);
    if (!old) {
      restore_lines_.push_back("not restored " + where(index, sub) + ": it could not be read before");
      return;
    }
    restores_.push_back(Write{index, sub, *old, true});
  }

  /// The entries of writes_[0, applied) in reverse order of their last
  /// write, each back to its value before; a PDO as one block in the CiA
  /// 301 order (invalid, count 0, mapping entries, count, parameters, COB-ID).
  void plan_restore(size_t applied) {
    std::vector<std::pair<uint16_t, uint8_t>> seen;
    auto first_time = [&seen](uint16_t index, uint8_t sub) {
      for (const auto& s : seen)
        if (s.first == index && s.second == sub) return false;
      seen.emplace_back(index, sub);
      return true;
    };
    for (size_t i = applied; i-- > 0;) {
      const Write& w = writes_[i];
      if (!is_pdo_comm(w.index) && !is_pdo_map(w.index)) {
        if (first_time(w.index, w.sub)) add_restore(w.index, w.sub);
        continue;
      }
      const uint16_t comm = is_pdo_map(w.index) ? static_cast<uint16_t>(w.index - 0x200) : w.index;
      if (first_time(comm, 0xFF)) plan_pdo_restore(comm, applied);  // 0xFF: the PDO as a whole
    }
  }

  void plan_pdo_restore(uint16_t comm, size_t applied) {
    const uint16_t map = static_cast<uint16_t>(comm + 0x200);
    std::vector<uint8_t> cob_now;
    std::vector<uint8_t> map_subs, comm_subs;  // written, latest write first
    auto note = [](std::vector<uint8_t>* subs, uint8_t sub) {
      for (uint8_t s : *subs)
        if (s == sub) return;
      subs->push_back(sub);
    };
    bool count_written = false;
    for (size_t i = applied; i-- > 0;) {
      const Write& w = writes_[i];
      if (w.index == comm && w.sub == 1 && cob_now.empty()) cob_now = w.bytes;
      if (w.index == comm && w.sub != 1) note(&comm_subs, w.sub);
      if (w.index == map && w.sub != 0) note(&map_subs, w.sub);
      if (w.index == map && w.sub == 0) count_written = true;
    }
    if (cob_now.empty()) {
      const std::vector<uint8_t>* old = before(comm, 1);
      if (old) cob_now = *old;
    }
    if (cob_now.size() == 4 && !(u32_of(cob_now) & 0x80000000u))
      restores_.push_back(Write{comm, 1, bytes_of(u32_of(cob_now) | 0x80000000u, 4)});
    if (count_written || !map_subs.empty()) {
      restores_.push_back(Write{map, 0, {0}});
      for (uint8_t s : map_subs) add_restore(map, s);
      add_restore(map, 0);
    }
    for (uint8_t s : comm_subs) add_restore(comm, s);
    bool cob_written = false;
    for (size_t i = 0; i < applied; ++i) cob_written |= writes_[i].index == comm && writes_[i].sub == 1;
    if (cob_written) add_restore(comm, 1);
  }

  std::string value_text(uint16_t index, uint8_t sub, const std::vector<uint8_t>& bytes) const {
    const eds::SubObject* s = dcf_.find(index, sub);
    eds::Value v;
    v.bytes = bytes;
    if (s) return eds::format_value(s->type, v);
    return eds::format_value(eds::DataType::kOctetString, v);
  }

  /// One restore step after the other; an abort is said and the rest still
  /// tried, silence ends the restore (the rest are said not restored).
  void restore_next() {
    if (next_restore_ >= restores_.size()) return finish(pending_outcome_, pending_why_);
    const Write& w = restores_[next_restore_++];
    queue(w.index, w.sub, false, w.bytes, [this](Transfer& t) {
      const Write& done = restores_[next_restore_ - 1];
      if (t.ok()) {
        if (done.reported)
          restore_lines_.push_back("restored " + where(done.index, done.sub) + " = " +
                                   value_text(done.index, done.sub, done.bytes));
        return restore_next();
      }
      const std::string step = where(done.index, done.sub) + (done.reported ? "" : " (PDO invalid first)");
      if (t.by_server) {
        restore_lines_.push_back("not restored " + step + ": SDO abort " + hex8(t.result) + " (" +
                                 abort_text(t.result) + ")");
        return restore_next();
      }
      restore_lines_.push_back("not restored " + step + ": no answer");
      for (size_t i = next_restore_; i < restores_.size(); ++i)
        if (restores_[i].reported)
          restore_lines_.push_back("not restored " + where(restores_[i].index, restores_[i].sub) +
                                   ": no answer");
      net_->drop_queued(node_.id, canopen::kAbortTimeout);
      finish(kMissing, pending_why_);
    });
  }

  /// A node may answer "save" at once and write over its next passes (the
  /// Uno: ~1.5 s): 1010h/1 reads 0 until the set is stored (CiA 301
  /// §7.5.2.13: bit 0, the node saves on command). Polled every
  /// kSavePollUs; "saved" only once it reads 1 again.
  void poll_save(uint32_t after_us) {
    Transfer& t = make(0x1010, 1, true, {}, [this](Transfer& r) {
      if (!r.ok()) return failed(r, "polling the save");
      if (!r.data.empty() && (r.data[0] & 1u)) {
        saved_ = true;
        return finish(kConfigured);
      }
      if (r.ended_us - save_started_us_ >= kSaveTimeoutUs)
        return finish(kRefused, "saving: 1010h/1 still reads 0 after " +
                                    std::to_string(kSaveTimeoutUs / 1000000u) + " s");
      poll_save(r.ended_us);
    });
    t.not_before_us = (after_us + kSavePollUs) | 1u;
    net_->queue(&t);
  }

  NetworkNode node_;
  eds::DeviceDescription dcf_;
  TransferNetwork* net_;
  bool save_;
  std::deque<Transfer> transfers_;
  std::deque<Entry> entries_;
  std::vector<Write> writes_;
  size_t next_write_ = 0;
  size_t reads_left_ = 0;
  Outcome outcome_ = kRunning;
  std::string why_;
  unsigned written_ = 0, equal_ = 0, read_only_ = 0;
  bool saved_ = false;
  std::vector<Write> restores_;
  size_t next_restore_ = 0;
  Outcome pending_outcome_ = kRefused;
  std::string pending_why_;
  std::vector<std::string> restore_lines_;
  uint32_t save_started_us_ = 0;  ///< when the node accepted "save"
  static const uint32_t kSavePollUs = 100000;
  static const uint32_t kSaveTimeoutUs = 10000000;
};

std::string json_text(const std::string& s) {
  std::string o;
  for (char c : s) {
    if (c == '"' || c == '\\') o += '\\';
    o += c;
  }
  return o;
}

}  // namespace

int configure_command(const Options& o, Transport& transport, std::ostream& out, std::ostream& err) {
  const std::vector<std::string>& w = o.args.operands;  // exactly 1 (the table)
  const bool save = o.args.has("--save");
  const bool no_start = o.args.has("--no-start");
  const bool one_at_a_time = o.args.has("--one-at-a-time");
  NetworkFile net;
  Status s = read_network_file(w[0], &net);
  if (!s) return fail(err, kExitUsage, "configure: " + s.message());
  if (net.nodes.empty()) return fail(err, kExitUsage, "configure: " + w[0] + ": no node is present");

  if (const int code = open_transport(o, transport, err)) return code;
  TransferRun run(o, transport);
  std::vector<std::unique_ptr<NodeJob>> jobs;
  for (const NetworkNode& n : net.nodes) {
    const eds::ParseResult dcf = eds::parse_file(n.dcf_path);
    if (!dcf) {
      const std::string why = dcf.error.line == 0
                                  ? "DCF of node " + std::to_string(n.id) + " " + n.dcf_path + ": cannot read"
                                  : dcf.error.text();
      return fail(err, kExitUsage, "configure: " + why);
    }
    jobs.emplace_back(new NodeJob(n, *dcf.model, &run.network(), save));
  }
  if (one_at_a_time) {
    for (size_t i = 0; i + 1 < jobs.size(); ++i) {
      NodeJob* next = jobs[i + 1].get();
      jobs[i]->on_finished = [next] { next->start(); };
    }
    jobs.front()->start();
  } else {
    for (auto& j : jobs) j->start();
  }
  if (!run.run())
    return fail(err, kExitInterrupted, "configure: interrupted: transfers aborted (08000000h sent)");
  const Status link = run.network().link_status();
  if (!link) return fail(err, kExitBus, "configure: " + link.message());

  bool refused = false, missing = false;
  for (auto& j : jobs) {
    bool started = false;
    if (j->outcome() == NodeJob::kConfigured && !no_start) {
      const Status sent = transport.nmt(canopen::kNmtStart, j->id());
      if (!sent) return fail(err, kExitBus, "configure: NMT start: " + sent.message());
      started = true;
    }
    refused |= j->outcome() == NodeJob::kRefused;
    missing |= j->outcome() == NodeJob::kMissing || j->outcome() == NodeJob::kRunning;
    static const char* const kResult[] = {"missing", "configured", "refused", "missing"};
    if (o.json) {
      out << "{\"node\":" << unsigned(j->id()) << ",\"result\":\"" << kResult[j->outcome()] << "\"";
      if (j->outcome() == NodeJob::kConfigured)
        out << ",\"written\":" << j->written() << ",\"equal\":" << j->equal()
            << ",\"read_only\":" << j->read_only() << ",\"saved\":" << (j->saved() ? "true" : "false")
            << ",\"started\":" << (started ? "true" : "false");
      else
        out << ",\"why\":\"" << json_text(j->why()) << "\"";
      if (!j->restore_lines().empty()) {
        out << ",\"restore\":[";
        for (size_t i = 0; i < j->restore_lines().size(); ++i)
          out << (i ? "," : "") << "\"" << json_text(j->restore_lines()[i]) << "\"";
        out << "]";
      }
      out << "}\n";
      continue;
    }
    out << "node " << unsigned(j->id()) << ": ";
    switch (j->outcome()) {
      case NodeJob::kConfigured:
        out << "configured: " << j->written() << " written, " << j->equal() << " equal, " << j->read_only()
            << " read-only skipped" << (j->saved() ? ", saved" : "") << (started ? ", started" : "") << "\n";
        break;
      case NodeJob::kRefused:
        out << "refused: " << j->why() << "\n";
        break;
      default:
        out << "missing (" << j->why() << ")\n";
        break;
    }
    for (const std::string& line : j->restore_lines())
      out << "node " << unsigned(j->id()) << ": " << line << "\n";
  }
  // Silence is the worse news: a missing node was not even identified.
  return missing ? kExitNoAnswer : refused ? kExitRefused : kExitOk;
}

}  // namespace master
}  // namespace mb2co
