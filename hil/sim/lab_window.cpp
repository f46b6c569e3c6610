#include "sim/lab_window.h"

#include <algorithm>
#include <vector>

#include "sim/lab_bound.h"
#include "sim/lab_hops.h"

namespace mb2co {
namespace sim {
namespace {

uint32_t od_get(canopen::ObjectDictionary& od, uint16_t index, uint8_t sub) {
  return od.get(od.find(index, sub));
}

/// Releases at least `period_ns` apart that fit in a closed window of
/// `span_ns` (the window plus how late one may be received).
uint32_t releases(SimNs span_ns, SimNs period_ns) {
  return static_cast<uint32_t>(span_ns / period_ns + 1);
}

/// Sends of event TPDO `n` of station `s` the operator can cause in one
/// window (its mapped objects changing), or -1 when it maps something the
/// lab does not account for.
int operator_sends(Line& line, int s, uint16_t n, int button_station, const LabOperator& op) {
  canopen::ObjectDictionary& od = line.node(s).gateway().od();
  const uint16_t map = static_cast<uint16_t>(0x1A00 + n);
  const uint32_t count = od_get(od, map, 0);
  const uint32_t first = od_get(od, map, 1) >> 16;
  const int others = op.interference ? 2 : 0;  // STOP2 with the press, STOP before the LED
  if (count == 1 && first == 0x6000) return (s == button_station ? 1 : 0) + others;  // debounced buttons
  if (count == 1 && first == 0x6200) return 1;  // the lab LED: on once per press
  // The line state (RUN state, STOP2 counter): with RUN fixed it changes
  // only when a STOP2 press here is counted.
  if (line_state_tpdo_fixed(line, s, n)) return op.interference ? 1 : 0;
  return -1;
}

/// One message station x receives: how often its sends can come.
struct Sender {
  uint32_t id = 0;      ///< COB-ID
  SimNs period_ns = 0;  ///< what the message set allows between two releases
  int caused = -1;      ///< sends the operator causes in a window; -1: not the operator's
  SimNs event_ns = 0;   ///< its event timer (restarts at every send); 0: none
};

/// Sends of `m` whose reception can fall in a closed interval of `span_ns`
/// (the interval plus how late one may be received).
uint32_t sends_in(const Sender& m, SimNs span_ns) {
  uint32_t n = releases(span_ns, m.period_ns);
  if (m.caused >= 0) {
    // Plus the event timer's: it restarts at every send (CiA 301), so
    // its sends are an event time apart at least.
    const uint32_t timer = m.event_ns != 0 ? releases(span_ns, m.event_ns) : 0;
    const uint32_t operated = static_cast<uint32_t>(m.caused) + timer;
    if (operated < n) n = operated;
  }
  return n;
}

/// Every message station `x` takes in (its filters admit it, another
/// station sends it) with its rate; fails when a message has no known rate.
Status senders_of(Line& line, int x, int button_station, const LabOperator& op, std::vector<Sender>* out) {
  const LineConfig& c = line.config();
  const CanController& rx = line.node(x).can();
  out->clear();
  uint32_t sync_period_us = 0;
  for (int s = 0; s < line.size(); ++s) {
    canopen::ObjectDictionary& od = line.node(s).gateway().od();
    const uint32_t sync_cob = od_get(od, 0x1005, 0);
    if ((sync_cob & 0x40000000u) && od_get(od, 0x1006, 0) != 0) {
      sync_period_us = od_get(od, 0x1006, 0);
      if (s != x && rx.accepts(static_cast<uint16_t>(sync_cob & 0x7FFu)))
        out->push_back(Sender{sync_cob & 0x7FFu, SimNs{sync_period_us} * kNsPerUs});
    }
  }
  for (int s = 0; s < line.size(); ++s) {
    if (s == x) continue;  // a controller does not receive its own frames
    canopen::ObjectDictionary& od = line.node(s).gateway().od();
    for (uint16_t n = 0; n < 4; ++n) {
      const uint16_t comm = static_cast<uint16_t>(0x1800 + n);
      const uint32_t cob = od_get(od, comm, 1);
      if ((cob & 0x80000000u) || od_get(od, static_cast<uint16_t>(0x1A00 + n), 0) == 0) continue;
      if (!rx.accepts(static_cast<uint16_t>(cob & 0x7FFu))) continue;
      const uint32_t type = od_get(od, comm, 2);
      const uint32_t inhibit_us = od_get(od, comm, 3) * 100u;
      uint32_t period_us = 0;  // what the message set allows
      if (type <= 240) {
        period_us = sync_period_us * (type == 0 ? 1u : type);
      } else {
        period_us = inhibit_us != 0
                        ? inhibit_us
                        : application_interarrival_us(c, od_get(od, static_cast<uint16_t>(0x1A00 + n), 1));
      }
      if (period_us == 0) {
        if (type <= 240) continue;  // synchronous without a SYNC producer: never sent
        return Status::failure(
            strf("TPDO%u of node %d has neither an inhibit time nor a known event rate", n + 1, s + 1));
      }
      Sender m{cob & 0x7FFu, SimNs{period_us} * kNsPerUs};
      m.caused = type >= 254 ? operator_sends(line, s, n, button_station, op) : -1;
      m.event_ns = SimNs{od_get(od, comm, 5)} * kNsPerMs;
      out->push_back(m);
    }
    const uint32_t hb_ms = od_get(od, 0x1017, 0);
    if (hb_ms != 0 && rx.accepts(static_cast<uint16_t>(0x700 + s + 1)))
      out->push_back(Sender{0x700u + static_cast<uint32_t>(s + 1), SimNs{hb_ms} * kNsPerMs});
  }
  return Status::ok();
}

/// Maximum flow from the senders (capacity: their sends in the window)
/// through the clusters they can reach (capacity per pair: their sends in
/// the cluster's reception interval) to the path (capacity per cluster: a
/// full receive buffer per pass), by augmenting paths. Small graphs: tens
/// of senders, a handful of clusters.
class FrameFlow {
 public:
  FrameFlow(const std::vector<uint32_t>& sender_cap, const std::vector<std::vector<uint32_t>>& pair_cap,
            const std::vector<uint32_t>& cluster_cap)
      : m_(sender_cap.size()), k_(cluster_cap.size()), n_(m_ + k_ + 2), cap_(n_ * n_, 0) {
    for (size_t i = 0; i < m_; ++i) {
      at(source(), 1 + i) = sender_cap[i];
      for (size_t j = 0; j < k_; ++j) at(1 + i, 1 + m_ + j) = pair_cap[i][j];
    }
    for (size_t j = 0; j < k_; ++j) at(1 + m_ + j, sink()) = cluster_cap[j];
  }

  uint32_t run() {
    uint32_t total = 0;
    for (;;) {
      std::vector<size_t> from(n_, n_);
      std::vector<size_t> queue{source()};
      from[source()] = source();
      for (size_t q = 0; q < queue.size() && from[sink()] == n_; ++q) {
        for (size_t v = 0; v < n_; ++v) {
          if (from[v] == n_ && at(queue[q], v) > 0) {
            from[v] = queue[q];
            queue.push_back(v);
          }
        }
      }
      if (from[sink()] == n_) return total;
      uint32_t push = ~uint32_t{0};
      for (size_t v = sink(); v != source(); v = from[v]) push = std::min(push, at(from[v], v));
      for (size_t v = sink(); v != source(); v = from[v]) {
        at(from[v], v) -= push;
        at(v, from[v]) += push;
      }
      total += push;
    }
  }

 private:
  size_t source() const { return 0; }
  size_t sink() const { return n_ - 1; }
  uint32_t& at(size_t a, size_t b) { return cap_[a * n_ + b]; }

  size_t m_, k_, n_;
  std::vector<uint32_t> cap_;
};

}  // namespace

Status frames_on_path(Line& line, int x, int button_station, SimNs window_ns, SimNs jitter_ns,
                      const std::vector<MessageLateness>& late, const LabOperator& op,
                      const std::vector<PathCluster>& clusters, uint32_t* frames) {
  std::vector<Sender> senders;
  Status listed = senders_of(line, x, button_station, op, &senders);
  if (!listed) return listed;
  const size_t buffers = line.config().node.can_rx_buffers;
  std::vector<uint32_t> sender_cap, cluster_cap;
  std::vector<std::vector<uint32_t>> pair_cap;
  for (const Sender& m : senders) {
    sender_cap.push_back(sends_in(m, window_ns + jitter_ns));
    pair_cap.emplace_back();
    // In a short interval each message's own lateness, not the longest.
    SimNs lateness = jitter_ns;
    for (const MessageLateness& l : late) {
      if (l.id == m.id) lateness = std::min(lateness, l.late_ns);
    }
    for (const PathCluster& k : clusters) pair_cap.back().push_back(sends_in(m, k.span_ns + lateness));
  }
  for (const PathCluster& k : clusters) cluster_cap.push_back(static_cast<uint32_t>(k.passes * buffers));
  *frames = FrameFlow(sender_cap, pair_cap, cluster_cap).run();
  return Status::ok();
}

}  // namespace sim
}  // namespace mb2co
