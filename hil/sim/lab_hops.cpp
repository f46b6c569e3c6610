#include "sim/lab_hops.h"

#include <algorithm>

#include "sim/lab_bound.h"
#include "timing/time_base.h"

namespace mb2co {
namespace sim {
namespace {

uint32_t od_get(canopen::ObjectDictionary& od, uint16_t index, uint8_t sub) {
  return od.get(od.find(index, sub));
}

/// Assignments enumerated at most; beyond, no split (the bound stays the
/// hops' separate R, sound on its own).
constexpr uint64_t kMaxAssignments = 4096;

/// Line-state TPDOs that interfere alike: same length, rate and jitter.
/// Above both hops in priority, any k of one class cost a hop the same.
struct TpdoClass {
  std::vector<uint32_t> ids;
  uint32_t k = 0;  ///< how many of them the assignment gives the up hop
};

/// `messages` without the ids in `drop`.
std::vector<timing::MessageSpec> without(const std::vector<timing::MessageSpec>& messages,
                                         const std::vector<uint32_t>& drop) {
  std::vector<timing::MessageSpec> out;
  for (const timing::MessageSpec& m : messages) {
    if (std::find(drop.begin(), drop.end(), m.id) == drop.end()) out.push_back(m);
  }
  return out;
}

/// Response time R (ns) of message `id` of `messages` (priority order) as
/// the set gives it, jitter included; false when unbounded.
bool response_ns(const std::vector<timing::MessageSpec>& messages, uint32_t id, uint32_t bitrate_bps,
                 uint64_t* out) {
  std::vector<timing::RtaMessage> rta(messages.size());
  std::vector<timing::RtaResult> res(messages.size());
  size_t bad = 0;
  if (timing::analyse_set(messages.data(), messages.size(), bitrate_bps, timing::WorstCase::kDavis,
                          rta.data(), res.data(), &bad) != timing::RtaStatus::kOk) {
    return false;
  }
  for (size_t i = 0; i < messages.size(); ++i) {
    if (messages[i].id != id) continue;
    if (res[i].revised != timing::Bound::kBounded) return false;
    *out = timing::ticks_to_ns_ceil(res[i].r, bitrate_bps);
    return true;
  }
  return false;
}

}  // namespace

bool line_state_tpdo_fixed(Line& line, int s, uint16_t n) {
  canopen::ObjectDictionary& od = line.node(s).gateway().od();
  const uint16_t map = static_cast<uint16_t>(0x1A00 + n);
  if (od_get(od, map, 0) != 2 || (od_get(od, map, 1) >> 8) != 0x210002u ||
      (od_get(od, map, 2) >> 8) != 0x210003u) {
    return false;
  }
  for (int k = 0; k < line.size(); ++k) {
    if (od_get(line.node(k).gateway().od(), 0x2100, 1) != 0) return false;
  }
  return true;
}

JointHops joint_hops(Line& line, const std::vector<timing::MessageSpec>& messages, uint32_t up_id,
                     uint32_t down_id, uint32_t bitrate_bps, uint64_t span_ns, uint64_t step_ns) {
  JointHops out;
  std::vector<TpdoClass> classes;
  uint64_t inhibit_ns = 0;
  for (int s = 0; s < line.size(); ++s) {
    canopen::ObjectDictionary& od = line.node(s).gateway().od();
    for (uint16_t n = 0; n < 4; ++n) {
      const uint16_t comm = static_cast<uint16_t>(0x1800 + n);
      const uint32_t cob = od_get(od, comm, 1);
      const uint32_t id = cob & 0x7FFu;
      if ((cob & 0x80000000u) || id >= std::min(up_id, down_id) || !line_state_tpdo_fixed(line, s, n))
        continue;
      // One timer send at most: it restarts at every send, so a second
      // one would come a whole event time after the first.
      const uint64_t event_ns = uint64_t{od_get(od, comm, 5)} * kNsPerMs;
      if (event_ns != 0 && event_ns <= span_ns) return out;
      inhibit_ns = std::max<uint64_t>(inhibit_ns, uint64_t{od_get(od, comm, 3)} * 100u * kNsPerUs);
      const auto spec = std::find_if(messages.begin(), messages.end(),
                                     [id](const timing::MessageSpec& m) { return m.id == id; });
      if (spec == messages.end()) return out;
      const auto same = std::find_if(classes.begin(), classes.end(), [&](const TpdoClass& c) {
        const timing::MessageSpec& o =
            *std::find_if(messages.begin(), messages.end(),
                          [&c](const timing::MessageSpec& m) { return m.id == c.ids.front(); });
        return o.dlc == spec->dlc && o.period_us == spec->period_us && o.jitter_us == spec->jitter_us;
      });
      if (same == classes.end()) {
        classes.push_back(TpdoClass{{id}, 0});
      } else {
        same->ids.push_back(id);
      }
    }
  }
  uint64_t assignments = 1;
  for (const TpdoClass& c : classes) {
    assignments *= c.ids.size() + 1;
    out.split_tpdos += static_cast<uint32_t>(c.ids.size());
  }
  if (classes.empty() || assignments > kMaxAssignments) return out;
  uint64_t longest_r_ns = 0;  // of the line-state TPDOs, each with its own jitter
  for (const TpdoClass& c : classes) {
    for (uint32_t id : c.ids) {
      uint64_t r = 0;
      if (!response_ns(messages, id, bitrate_bps, &r)) return out;
      longest_r_ns = std::max(longest_r_ns, r);
    }
  }
  // Δ: the later send of a TPDO meeting both hops leaves at most this long
  // after the up hop's reception (docs/timing.md §9): the STOP2 send is
  // counted ≤ 2 steps after the button PDO is queued, or held back to the
  // inhibit time after the timer send that met the up hop (+ a step), and
  // it is on the bus at most its response time.
  out.close_ns = std::max(2 * step_ns, inhibit_ns + step_ns) + 2 * kNsPerUs + longest_r_ns;
  bool done = false;
  while (!done) {
    std::vector<uint32_t> not_up, not_down;  // the TPDOs each hop does not see
    for (const TpdoClass& c : classes) {
      for (size_t i = 0; i < c.ids.size(); ++i) (i < c.k ? not_down : not_up).push_back(c.ids[i]);
    }
    HopTimes up, down;
    if (!hop_times(without(messages, not_up), up_id, bitrate_bps, &up) ||
        !hop_times(without(messages, not_down), down_id, bitrate_bps, &down)) {
      return JointHops{};
    }
    if (up.worst_ns + down.worst_ns > out.up_ns + out.down_ns) {
      out.up_ns = up.worst_ns;
      out.down_ns = down.worst_ns;
    }
    // Next assignment: count up the classes' k like the digits of a number.
    done = true;
    for (TpdoClass& c : classes) {
      if (c.k < c.ids.size()) {
        ++c.k;
        done = false;
        break;
      }
      c.k = 0;
    }
  }
  out.split = true;
  return out;
}

}  // namespace sim
}  // namespace mb2co
