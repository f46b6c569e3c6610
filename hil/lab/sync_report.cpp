#include "sync_report.h"

#include "report.h"

namespace mb2co {
namespace lab {

using sim::strf;

namespace {

// Milliseconds (§5.3, §11) or microseconds (§5.2) with two decimals.
std::string in_unit(uint64_t ns, double unit_ns) {
  return strf("%.2f", static_cast<double>(ns) / unit_ns);
}

std::string ratio(uint64_t max_ns, uint64_t worst_ns) {
  return strf("%.1f%%",
              worst_ns == 0 ? 0.0 : 100.0 * static_cast<double>(max_ns) / static_cast<double>(worst_ns));
}

// The row of one case: n, min, mean, max | best, worst | inside, max/worst.
std::string row(const char* label, size_t n, uint64_t min_ns, double mean_ns, uint64_t max_ns,
                const timing::LatencyBound& b, uint32_t outside, double unit_ns) {
  return strf("  %-24s %5zu %9s %9s %9s  | %9s %9s | %6s  %9s\n", label, n, in_unit(min_ns, unit_ns).c_str(),
              strf("%.2f", mean_ns / unit_ns).c_str(), in_unit(max_ns, unit_ns).c_str(),
              in_unit(b.best_ns, unit_ns).c_str(), in_unit(b.worst_ns, unit_ns).c_str(),
              outside == 0 ? "all" : strf("%u out", outside).c_str(), ratio(max_ns, b.worst_ns).c_str());
}

std::string header(const char* first) {
  return strf("  %-24s %5s %9s %9s %9s  | %9s %9s | %6s  %9s\n", first, "n", "min", "mean", "max", "best",
              "worst", "inside", "max/worst");
}

std::string terms(const timing::LatencyBound& b, double unit_ns, const char* unit) {
  std::string s;
  for (size_t i = 0; i < b.count; ++i) {
    s += strf("%s%s %s..%s", i == 0 ? "" : ", ", b.terms[i].name,
              in_unit(b.terms[i].best_ns, unit_ns).c_str(), in_unit(b.terms[i].worst_ns, unit_ns).c_str());
  }
  return s + " " + unit;
}

// Table, bound terms and verdict of one SYNC lab.
std::string sync_section(const std::vector<sim::SyncResult>& results, const char* name, const char* what,
                         double unit_ns, const char* unit) {
  std::string s;
  bool all = true;
  size_t total = 0;
  std::string failures;
  for (const sim::SyncResult& r : results) {
    const std::string label = strf("%uk", r.lab.bitrate_kbit);
    total += r.samples_ns.size();
    all = all && r.ok;
    if (!r.bound_ok) {
      s += strf("  %-24s no bound: %s\n", label.c_str(), r.error.c_str());
      failures += strf("; %s: no bound", label.c_str());
      continue;
    }
    if (!r.error.empty()) {
      s += strf("  %-24s %s\n", label.c_str(), r.error.c_str());
      failures += strf("; %s: not measured", label.c_str());
      continue;
    }
    s += row(label.c_str(), r.samples_ns.size(), r.stats.min_ns, r.stats.mean_ns, r.stats.max_ns, r.bound,
             r.outside, unit_ns);
    if (r.outside != 0) failures += strf("; %s: %u outside", label.c_str(), r.outside);
    if (r.samples_ns.size() != r.wanted)
      failures += strf("; %s: %zu of %u measured", label.c_str(), r.samples_ns.size(), r.wanted);
    if (r.lost != 0) failures += strf("; %s: %u presses without LED", label.c_str(), r.lost);
  }
  s += "  bound terms (best..worst):\n";
  for (const sim::SyncResult& r : results) {
    if (r.bound_ok) s += strf("  %4uk: %s\n", r.lab.bitrate_kbit, terms(r.bound, unit_ns, unit).c_str());
  }
  if (all) {
    s += strf("verdict %s: PASS (criterion: every one of %zu %s inside its analytical bounds)\n", name, total,
              what);
  } else {
    s += strf("verdict %s: FAIL (criterion: all %s measured, each inside its analytical bounds%s)\n", name,
              what, failures.c_str());
  }
  return s;
}

std::string sync_setup(const sim::SyncResult& r) {
  const timing::SyncParams& p = r.params;
  return strf(
      "  station 1 sends SYNC (80h) every %u us (1006h), station 2 answers with TPDO2 (282h, transmission "
      "type n = %u: at every n-th SYNC)\n"
      "  firmware: a frame handled %u..%u us after its reception, SYNC queued up to %u us late\n",
      r.lab.sync_period_us, r.lab.transmission_type, p.pass_min_us, p.fw_loop_us, p.sync_jitter_us);
}

}  // namespace

std::string sync_roundtrip_section(const std::vector<sim::SyncResult>& results) {
  std::string s = "\n== sync-roundtrip: SYNC's first bit -> synchronous PDO received (seed 000 §5.2), us\n";
  if (!results.empty()) s += sync_setup(results.front());
  s += header("bitrate");
  return s + sync_section(results, "sync-roundtrip", "round trips", 1e3, "us");
}

std::string sync_latency_section(const std::vector<sim::SyncResult>& results) {
  std::string s =
      "\n== sync-latency: joystick (START) on station 2 -> LED on station 1 under SYNC (seed 000 §5.3), ms\n";
  if (!results.empty()) {
    s += sync_setup(results.front());
    if (results.front().lab.bound_sync_period_us != 0)
      s += strf("  the bound assumes a SYNC period of %u us (--bound-sync-period-us)\n",
                results.front().lab.bound_sync_period_us);
  }
  s += header("bitrate");
  return s + sync_section(results, "sync-latency", "presses", 1e6, "ms");
}

std::string sync_csv(const std::vector<sim::SyncResult>& results) {
  std::string s = "bitrate_kbit,n,value_ns,best_ns,worst_ns,inside\n";
  for (const sim::SyncResult& r : results) {
    for (size_t i = 0; i < r.samples_ns.size(); ++i) {
      const uint64_t v = r.samples_ns[i];
      const bool in = r.bound_ok && v >= r.bound.best_ns && v <= r.bound.worst_ns;
      s += strf("%u,%zu,%llu,%llu,%llu,%d\n", r.lab.bitrate_kbit, i + 1, static_cast<unsigned long long>(v),
                static_cast<unsigned long long>(r.bound.best_ns),
                static_cast<unsigned long long>(r.bound.worst_ns), in ? 1 : 0);
    }
  }
  return s;
}

std::string alternative_section(const std::vector<sim::AlternativeResult>& results) {
  std::string s =
      "\n== alternative: button -> LED with the control process on the PC or on an Arduino (seed 000 §11), "
      "ms\n"
      "  pc modbus:         the PC reads the button and writes the LED on its own Arduino (Modbus/RTU only)\n"
      "  pc modbus+canopen: the same PC, button and LED on another Arduino (Modbus/RTU and CANopen)\n"
      "  arduino canopen:   simpler alternative: the 'process control' software on one Arduino (station 1,\n"
      "                     LED := button in the pass that receives it), button and LED on another\n"
      "                     (station 2); only the CANopen network carries the data\n";
  s += header("bitrate  path");
  bool all = true;
  size_t total = 0;
  std::string failures;
  for (const sim::AlternativeResult& r : results) {
    const sim::LatencyResult* cases[] = {&r.modbus, &r.canopen, &r.arduino};
    const char* names[] = {"pc modbus", "pc modbus+canopen", "arduino canopen"};
    for (int i = 0; i < 3; ++i) {
      const sim::LatencyResult& c = *cases[i];
      const std::string label = strf("%4uk  %s", r.bitrate_kbit, names[i]);
      total += c.samples_ns.size();
      if (!c.bound.ok) {
        s += strf("  %-24s no bound: %s\n", label.c_str(), c.bound.error.c_str());
      } else {
        s += row(label.c_str(), c.samples_ns.size(), c.min_ns, c.mean_ns, c.max_ns, c.bound.bound, c.outside,
                 1e6);
      }
      if (!c.ok) failures += strf("; %uk %s", r.bitrate_kbit, names[i]);
    }
    all = all && r.ok;
  }
  s += "  bound terms of the Arduino-controlled path (best..worst):\n";
  for (const sim::AlternativeResult& r : results) {
    if (r.arduino.bound.ok)
      s += strf("  %4uk: %s\n", r.bitrate_kbit, terms(r.arduino.bound.bound, 1e6, "ms").c_str());
  }
  if (all) {
    s += strf(
        "verdict alternative: PASS (criterion: every one of %zu measurements of the three paths inside its "
        "analytical bounds)\n",
        total);
  } else {
    s += strf(
        "verdict alternative: FAIL (criterion: every measurement inside its analytical bounds; failed%s)\n",
        failures.c_str());
  }
  return s;
}

std::string sync_svg(const sim::SyncResult& r, bool roundtrip) {
  HistogramPanel p;
  p.name = strf("transmission type %u", r.lab.transmission_type);
  p.samples = &r.samples_ns;
  p.min = r.stats.min_ns;
  p.max = r.stats.max_ns;
  p.bounded = r.bound_ok;
  p.best = r.bound.best_ns;
  p.worst = r.bound.worst_ns;
  const uint32_t kbit = r.lab.bitrate_kbit;
  return roundtrip
             ? histogram_svg(strf("SYNC's first bit to the synchronous PDO received at %u kbit/s:", kbit),
                             "round trips", kUs, {p})
             : histogram_svg(strf("Button to LED latency under SYNC at %u kbit/s:", kbit), "presses", kMs,
                             {p});
}

std::string alternative_svg(const sim::AlternativeResult& r) {
  std::vector<HistogramPanel> panels = {latency_panel(r.modbus, "pc modbus"),
                                        latency_panel(r.canopen, "pc modbus+canopen"),
                                        latency_panel(r.arduino, "arduino canopen")};
  panels[2].fill = "#40a040";
  return histogram_svg(
      strf("Button to LED latency, control process on the PC or an Arduino, at %u kbit/s:", r.bitrate_kbit),
      "presses", kMs, panels);
}

}  // namespace lab
}  // namespace mb2co
