#include "scenario_runs.h"

#include <chrono>

#include "report.h"
#include "sim/scenarios.h"
#include "sync_processing.h"
#include "sync_report.h"

namespace mb2co {
namespace lab {

namespace {

uint64_t monotonic_ns() {
  return static_cast<uint64_t>(std::chrono::duration_cast<std::chrono::nanoseconds>(
                                   std::chrono::steady_clock::now().time_since_epoch())
                                   .count());
}

/// A scenario that is one run of the line: its section, its timeline, its
/// simulated time and its verdict.
void add_line_run(const Options& o, const char* name, const sim::LineSummary& line,
                  const std::string& section, bool ok, LabRun* run) {
  run->bar.clear();
  run->report += section;
  run->files.push_back({sim::strf("timeline-%s.svg", name), timeline_svg(line, o.line.stations, name)});
  run->simulated_s += static_cast<double>(line.duration_ns) / 1e9;
  run->pass = run->pass && ok;
}

/// The run scenario: --duration s of the line in production.
void run_production(const Options& o, LabRun* run) {
  const sim::RunResult r = sim::run_scenario(o.line, o.duration_s * sim::kNsPerS, &run->log,
                                             [&](double f) { run->bar.show("run", f, monotonic_ns()); });
  add_line_run(o, "run", r.line, run_section(r), r.ok, run);
}

void run_stop2(const Options& o, LabRun* run) {
  const sim::Stop2Result r =
      sim::stop2_scenario(o.line, &run->log, [&](double f) { run->bar.show("stop2", f, monotonic_ns()); });
  add_line_run(o, "stop2", r.line, stop2_section(r), r.ok, run);
}

/// Button to LED at every bit rate, over Modbus and over Modbus + CANopen.
void run_latency(const Options& o, LabRun* run) {
  std::vector<sim::LatencyResult> results;
  const size_t cases = o.bitrates.size() * 2;
  for (size_t i = 0; i < cases; ++i) {
    const sim::LatencyCase lc{o.bitrates[i / 2], i % 2 == 1, o.worst};
    const std::string stage = sim::strf("latency %uk %s", lc.bitrate_kbit, lc.remote ? "canopen" : "modbus");
    results.push_back(sim::latency_scenario(o.line, lc, o.presses, &run->log, [&](double f) {
      run->bar.show(stage, (static_cast<double>(i) + f) / static_cast<double>(cases), monotonic_ns());
    }));
    run->simulated_s += static_cast<double>(results.back().duration_ns) / 1e9;
  }
  run->bar.clear();
  run->report += latency_section(results);
  for (const sim::LatencyResult& r : results) run->pass = run->pass && r.ok;
  run->files.push_back({"latency.csv", latency_csv(results)});
  run->files.push_back({"latency-bounds.csv", bound_terms_csv(results)});
  for (uint32_t b : o.bitrates)
    run->files.push_back({sim::strf("latency-%uk.svg", b), latency_svg(results, b)});
}

void run_faults(const Options& o, LabRun* run) {
  const sim::FaultsResult r =
      sim::faults_scenario(o.line, &run->log, [&](double f) { run->bar.show("faults", f, monotonic_ns()); });
  add_line_run(o, "faults", r.line, faults_section(r), r.ok, run);
}

/// sync-roundtrip or sync-latency (seed 000 §5) at every bit rate.
void run_sync_lab(const Options& o, LabRun* run) {
  const bool roundtrip = o.scenario == Scenario::kSyncRoundtrip;
  std::vector<sim::SyncResult> results;
  for (size_t i = 0; i < o.bitrates.size(); ++i) {
    sim::SyncLabConfig lc;
    lc.bitrate_kbit = o.bitrates[i];
    lc.sync_period_us = o.sync_period_us;
    lc.transmission_type = static_cast<uint8_t>(o.transmission_type);
    lc.bound_sync_period_us = o.bound_sync_period_us;
    const std::string stage = sim::strf("%s %uk", scenario_name(o.scenario), lc.bitrate_kbit);
    const auto shown = [&](double f) {
      run->bar.show(stage, (static_cast<double>(i) + f) / static_cast<double>(o.bitrates.size()),
                    monotonic_ns());
    };
    results.push_back(roundtrip ? sim::sync_roundtrip_scenario(o.line, lc, o.syncs, &run->log, shown)
                                : sim::sync_latency_scenario(o.line, lc, o.presses, &run->log, shown));
    run->simulated_s += static_cast<double>(results.back().duration_ns) / 1e9;
    run->pass = run->pass && results.back().ok;
  }
  run->bar.clear();
  run->report += roundtrip ? sync_roundtrip_section(results) : sync_latency_section(results);
  run->files.push_back({std::string(scenario_name(o.scenario)) + ".csv", sync_csv(results)});
  for (const sim::SyncResult& r : results) {
    run->files.push_back(
        {sim::strf("%s-%uk.svg", scenario_name(o.scenario), r.lab.bitrate_kbit), sync_svg(r, roundtrip)});
  }
}

void run_sync_processing(const Options& o, const std::string& elf, LabRun* run) {
  const SyncProcessingResult r = sync_processing_run(elf, o.syncs, o.line.seed);
  run->report += sync_processing_section(r);
  run->files.push_back({"sync-processing.svg", sync_processing_svg(r)});
  run->pass = run->pass && r.ok;
}

/// Seed 000 §11's three paths side by side at every bit rate.
void run_alternative(const Options& o, LabRun* run) {
  std::vector<sim::AlternativeResult> results;
  for (size_t i = 0; i < o.bitrates.size(); ++i) {
    const std::string stage = sim::strf("alternative %uk", o.bitrates[i]);
    results.push_back(sim::alternative_scenario(o.line, o.bitrates[i], o.presses, &run->log, [&](double f) {
      run->bar.show(stage, (static_cast<double>(i) + f) / static_cast<double>(o.bitrates.size()),
                    monotonic_ns());
    }));
    const sim::AlternativeResult& r = results.back();
    run->simulated_s +=
        static_cast<double>(r.modbus.duration_ns + r.canopen.duration_ns + r.arduino.duration_ns) / 1e9;
    run->pass = run->pass && r.ok;
  }
  run->bar.clear();
  run->report += alternative_section(results);
  for (const sim::AlternativeResult& r : results)
    run->files.push_back({sim::strf("alternative-%uk.svg", r.bitrate_kbit), alternative_svg(r)});
}

}  // namespace

void run_scenarios(const Options& o, const std::string& elf, LabRun* run) {
  const bool all = o.scenario == Scenario::kDefault;
  if (o.scenario == Scenario::kRun) run_production(o, run);
  if (all || o.scenario == Scenario::kStop2) run_stop2(o, run);
  if (all || o.scenario == Scenario::kLatency) run_latency(o, run);
  if (o.scenario == Scenario::kFaults) run_faults(o, run);
  if (o.scenario == Scenario::kSyncRoundtrip || o.scenario == Scenario::kSyncLatency) run_sync_lab(o, run);
  if (o.scenario == Scenario::kSyncProcessing) run_sync_processing(o, elf, run);
  if (o.scenario == Scenario::kAlternative) run_alternative(o, run);
}

}  // namespace lab
}  // namespace mb2co
