// `mb2co-timing load` and `mb2co-timing rta`: a message set from CSV or from
// the line configuration, its bus load, and its response-time analysis.
#include <fstream>

#include "command_parts.h"
#include "svg.h"
#include "timing/time_base.h"

namespace mb2co {
namespace timing_cli {
namespace {

double to_double(const timing::Fixed64& v) {
  return static_cast<double>(v.whole) + static_cast<double>(v.frac) * 0x1p-64;
}

struct Analysed {
  std::vector<timing::MessageSpec> set;
  uint32_t bitrate = 0;
  timing::WorstCase convention = timing::WorstCase::kDavis;
  Format format = Format::kTable;
};

Status prepare(const Options& o, Analysed& a, bool* runtime_failure) {
  Status s = frame_bits_option(o, &a.convention);
  if (s) s = format_option(o, &a.format);
  if (s) s = message_set_option(o, a.set, &a.bitrate, runtime_failure);
  return s;
}

Cell time_cell(bool valid, uint64_t ticks, uint32_t bitrate) {
  return valid ? Cell::us(timing::ticks_to_ns_ceil(ticks, bitrate)) : Cell::null();
}

Cell reason_cell(timing::Bound b) {
  switch (b) {
    case timing::Bound::kBounded:
      return Cell::null();
    case timing::Bound::kUtilisation:
      return Cell::str("utilisation");
    case timing::Bound::kHorizon:
      return Cell::str("horizon");
  }
  return Cell::null();
}

}  // namespace

Status load_command(const Options& o, std::ostream& out, bool* runtime_failure) {
  Analysed a;
  Status s = prepare(o, a, runtime_failure);
  if (!s) return s;
  Report r;
  r.rows_key = "messages";
  r.columns = {"name", "id", "bits", "period_us", "load_bps"};
  for (const timing::MessageSpec& m : a.set) {
    const timing::Utilisation bps = timing::bus_load_bps(&m, 1, a.bitrate, a.convention);
    r.rows.push_back({Cell::str(m.name), Cell::id(m.id, m.extended),
                      Cell::integer(timing::message_bits(m, a.bitrate, a.convention)),
                      Cell::integer(m.period_us), Cell::real(to_double(bps.lower()), 3)});
  }
  const timing::Utilisation load = timing::bus_load_bps(a.set.data(), a.set.size(), a.bitrate, a.convention);
  const timing::Utilisation u = timing::set_utilisation(a.set.data(), a.set.size(), a.bitrate, a.convention);
  r.totals = {{"bitrate", Cell::integer(a.bitrate)},
              {"frame_bits", Cell::str(frame_bits_name(a.convention))},
              {"message_count", Cell::integer(a.set.size())},
              {"load_bps", Cell::real(to_double(load.lower()), 3)},
              {"utilisation", Cell::real(to_double(u.upper()), 6)},
              {"fits", Cell::boolean(u.below_one())}};
  if (o.has("--window-us")) {
    uint64_t window = 0;
    if (!(s = uint_option(o, "--window-us", 1, UINT32_MAX, 0, &window))) return s;
    const uint32_t w = static_cast<uint32_t>(window);
    const uint64_t bits = timing::window_bits(a.set.data(), a.set.size(), w, a.bitrate, a.convention);
    const uint64_t capacity = timing::window_capacity_bits(w, a.bitrate);
    r.totals.push_back({"window_us", Cell::integer(w)});
    r.totals.push_back({"window_bits", Cell::integer(bits)});
    r.totals.push_back({"window_capacity_bits", Cell::integer(capacity)});
    r.totals.push_back({"window_fits", Cell::boolean(bits <= capacity)});
  }
  print_report(r, a.format, out);
  return Status::ok();
}

Status rta_command(const Options& o, std::ostream& out, bool* deadline_missed, bool* runtime_failure) {
  Analysed a;
  Status s = prepare(o, a, runtime_failure);
  if (!s) return s;
  if (o.has("--svg") != o.has("--message")) {
    return Status::failure("options --svg FILE and --message NAME go together");
  }
  const size_t n = a.set.size();
  std::vector<timing::RtaMessage> rta(n);
  std::vector<timing::RtaResult> results(n);
  size_t bad = 0;
  if (timing::analyse_set(a.set.data(), n, a.bitrate, a.convention, rta.data(), results.data(), &bad) !=
      timing::RtaStatus::kOk) {
    return Status::failure(std::string("message \"") + a.set[bad].name +
                           "\" is out of range for the analysis");
  }

  Report r;
  r.rows_key = "messages";
  r.columns = {"name",       "id",          "ext",         "dlc",
               "bits",       "c_us",        "period_us",   "deadline_us",
               "jitter_us",  "blocking_us", "busy_us",     "instances",
               "r_first_us", "r_us",        "schedulable", "first_optimistic",
               "unbounded"};
  bool all_ok = true;
  size_t optimistic = 0;
  std::string optimistic_names;
  for (size_t i = 0; i < n; ++i) {
    const timing::MessageSpec& m = a.set[i];
    const timing::RtaResult& res = results[i];
    const bool bounded = res.revised == timing::Bound::kBounded;
    all_ok = all_ok && res.schedulable;
    if (res.first_optimistic) {
      ++optimistic;
      optimistic_names += (optimistic_names.empty() ? "" : ", ") + std::string(m.name);
    }
    r.rows.push_back({Cell::str(m.name), Cell::id(m.id, m.extended), Cell::integer(m.extended),
                      Cell::integer(m.dlc), Cell::integer(timing::ticks_to_bits_ceil(rta[i].c)),
                      time_cell(true, rta[i].c, a.bitrate), Cell::integer(m.period_us),
                      Cell::integer(m.deadline_us), Cell::integer(m.jitter_us),
                      time_cell(true, res.blocking, a.bitrate), time_cell(bounded, res.busy, a.bitrate),
                      bounded ? Cell::integer(res.instances) : Cell::null(),
                      time_cell(res.first == timing::Bound::kBounded, res.r_first, a.bitrate),
                      time_cell(bounded, res.r, a.bitrate), Cell::boolean(res.schedulable),
                      Cell::boolean(res.first_optimistic), reason_cell(res.revised)});
  }
  const timing::Utilisation u = timing::set_utilisation(a.set.data(), n, a.bitrate, a.convention);
  r.totals = {{"bitrate", Cell::integer(a.bitrate)},
              {"frame_bits", Cell::str(frame_bits_name(a.convention))},
              {"tau_bit_us", Cell::us(timing::bits_to_ns_ceil(1, a.bitrate))},
              {"message_count", Cell::integer(n)},
              {"utilisation", Cell::real(to_double(u.upper()), 6)},
              {"schedulable", Cell::boolean(all_ok)},
              {"first_optimistic", Cell::integer(optimistic)}};
  if (optimistic != 0) {
    r.notes.push_back("first attempt (§2.12) optimistic for: " + optimistic_names);
  }

  if (o.has("--svg")) {
    size_t target = n;
    for (size_t i = 0; i < n; ++i) {
      if (o.get("--message") == a.set[i].name) target = i;
    }
    if (target == n) {
      return Status::failure("--message: no message named \"" + o.get("--message") + "\"");
    }
    if (results[target].revised != timing::Bound::kBounded) {
      return Status::failure("message \"" + o.get("--message") + "\" has no bounded busy period to draw");
    }
    std::ofstream svg(o.get("--svg"), std::ios::binary | std::ios::trunc);
    svg << busy_period_svg(a.set, rta, target, results[target], a.bitrate);
    if (!svg.flush()) {
      *runtime_failure = true;
      return Status::failure(o.get("--svg") + ": cannot write");
    }
  }
  print_report(r, a.format, out);
  *deadline_missed = o.has("--check") && !all_ok;
  return Status::ok();
}

}  // namespace timing_cli
}  // namespace mb2co
