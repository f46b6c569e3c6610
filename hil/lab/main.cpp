// mb2co-lab: runs the simulated production line and prints a report (the
// main job of hil/, docs/lab.md). Exit status: 0 every verdict passed,
// 3 some verdict failed, 2 bad command line, 1 the output could not be written.
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>

#include "host/pcap_can.h"
#include "options.h"
#include "plant/plant_config.h"
#include "progress_bar.h"
#include "report.h"
#include "sim/can_trace.h"
#include "sim/scenarios.h"
#include "sync_processing.h"
#include "sync_report.h"

namespace {

using namespace mb2co;

uint64_t monotonic_ns() {
  return static_cast<uint64_t>(std::chrono::duration_cast<std::chrono::nanoseconds>(
                                   std::chrono::steady_clock::now().time_since_epoch())
                                   .count());
}

Status write_file(const std::filesystem::path& path, const std::string& text) {
  std::ofstream f(path, std::ios::binary);
  f << text;
  f.close();
  if (!f) return Status::failure("cannot write " + path.string());
  return Status::ok();
}

}  // namespace

int main(int argc, char** argv) {
  const cli::Parsed parsed = cli::parse(lab::program(), argc, argv);
  const int early = cli::finish_early(lab::program(), parsed, std::cout, std::cerr);
  if (early >= 0) return early;
  lab::Options o;
  const Status applied = lab::apply_options(parsed.args, &o);
  if (!applied) {
    std::fprintf(stderr, "mb2co-lab: %s\n", applied.message().c_str());
    return 2;
  }
  Status usable = sim::check_line_config(o.line);
  const bool sync_lab = o.scenario == lab::Scenario::kSyncRoundtrip ||
                        o.scenario == lab::Scenario::kSyncLatency ||
                        o.scenario == lab::Scenario::kSyncProcessing;
  if (usable && o.scenario != lab::Scenario::kLatency && o.scenario != lab::Scenario::kAlternative &&
      !sync_lab) {
    plant::PlantConfig pc;
    pc.step_ms = static_cast<uint32_t>(o.line.pc.cycle_ns / sim::kNsPerMs);
    plant::ConfigError ce;
    uint16_t keys = 0;
    if (!plant::check_plant_config(pc, ce, keys))
      usable = Status::failure(std::string("plant with this PC cycle: ") + ce.message);
  }
  if (!usable) {
    std::fprintf(stderr, "mb2co-lab: %s\n", usable.message().c_str());
    return 2;
  }
  if (o.scenario == lab::Scenario::kRun && o.duration_s < sim::run_min_duration_s(o.line)) {
    std::fprintf(stderr,
                 "mb2co-lab: --duration %u is too short for the run scenario's criterion (every station "
                 "fills a bottle): at least %u s with this plant\n",
                 o.duration_s, sim::run_min_duration_s(o.line));
    return 2;
  }
  // sync-processing runs the real AVR image: without one there is nothing to
  // measure, which is not a failed verdict (exit 3) but a missing input.
  const std::string elf = o.elf.empty() ? std::string(MB2CO_LAB_DEFAULT_ELF) : o.elf;
  if (o.scenario == lab::Scenario::kSyncProcessing && !std::filesystem::is_regular_file(elf)) {
    std::fprintf(stderr,
                 "mb2co-lab: no AVR image %s for sync-processing (--elf FILE, or build the firmware: "
                 "scripts/build.sh)\n",
                 elf.c_str());
    return 1;
  }
  const std::filesystem::path out(o.out_dir);
  std::error_code ec;
  std::filesystem::create_directories(out, ec);
  if (ec) {
    std::fprintf(stderr, "mb2co-lab: cannot create %s: %s\n", o.out_dir.c_str(), ec.message().c_str());
    return 1;
  }

  lab::ProgressBar bar(!o.quiet && isatty(STDOUT_FILENO) ? stdout : nullptr);
  // Without --events nothing is logged: no line is formatted that would not be written.
  sim::EventLog log(o.events);
  sim::CanTrace trace;
  if (!o.trace_path.empty()) log.set_can_trace(&trace);
  std::string report = lab::report_header(o);
  std::vector<std::pair<std::string, std::string>> files;
  bool pass = true;
  double simulated_s = 0;
  const auto wall0 = std::chrono::steady_clock::now();
  const bool all = o.scenario == lab::Scenario::kDefault;

  if (o.scenario == lab::Scenario::kRun) {
    const sim::RunResult r = sim::run_scenario(o.line, o.duration_s * sim::kNsPerS, &log,
                                               [&](double f) { bar.show("run", f, monotonic_ns()); });
    bar.clear();
    report += lab::run_section(r);
    files.push_back({"timeline-run.svg", lab::timeline_svg(r.line, o.line.stations, "run")});
    simulated_s += static_cast<double>(r.line.duration_ns) / 1e9;
    pass = pass && r.ok;
  }
  if (all || o.scenario == lab::Scenario::kStop2) {
    const sim::Stop2Result r =
        sim::stop2_scenario(o.line, &log, [&](double f) { bar.show("stop2", f, monotonic_ns()); });
    bar.clear();
    report += lab::stop2_section(r);
    files.push_back({"timeline-stop2.svg", lab::timeline_svg(r.line, o.line.stations, "stop2")});
    simulated_s += static_cast<double>(r.line.duration_ns) / 1e9;
    pass = pass && r.ok;
  }
  if (all || o.scenario == lab::Scenario::kLatency) {
    std::vector<sim::LatencyResult> results;
    const size_t cases = o.bitrates.size() * 2;
    for (size_t i = 0; i < cases; ++i) {
      const sim::LatencyCase lc{o.bitrates[i / 2], i % 2 == 1, o.worst};
      const std::string stage =
          sim::strf("latency %uk %s", lc.bitrate_kbit, lc.remote ? "canopen" : "modbus");
      results.push_back(sim::latency_scenario(o.line, lc, o.presses, &log, [&](double f) {
        bar.show(stage, (static_cast<double>(i) + f) / static_cast<double>(cases), monotonic_ns());
      }));
      simulated_s += static_cast<double>(results.back().duration_ns) / 1e9;
    }
    bar.clear();
    report += lab::latency_section(results);
    for (const sim::LatencyResult& r : results) pass = pass && r.ok;
    files.push_back({"latency.csv", lab::latency_csv(results)});
    files.push_back({"latency-bounds.csv", lab::bound_terms_csv(results)});
    for (uint32_t b : o.bitrates)
      files.push_back({sim::strf("latency-%uk.svg", b), lab::latency_svg(results, b)});
  }
  if (o.scenario == lab::Scenario::kFaults) {
    const sim::FaultsResult r =
        sim::faults_scenario(o.line, &log, [&](double f) { bar.show("faults", f, monotonic_ns()); });
    bar.clear();
    report += lab::faults_section(r);
    files.push_back({"timeline-faults.svg", lab::timeline_svg(r.line, o.line.stations, "faults")});
    simulated_s += static_cast<double>(r.line.duration_ns) / 1e9;
    pass = pass && r.ok;
  }
  if (o.scenario == lab::Scenario::kSyncRoundtrip || o.scenario == lab::Scenario::kSyncLatency) {
    const bool roundtrip = o.scenario == lab::Scenario::kSyncRoundtrip;
    std::vector<sim::SyncResult> results;
    for (size_t i = 0; i < o.bitrates.size(); ++i) {
      sim::SyncLabConfig lc;
      lc.bitrate_kbit = o.bitrates[i];
      lc.sync_period_us = o.sync_period_us;
      lc.transmission_type = static_cast<uint8_t>(o.transmission_type);
      lc.bound_sync_period_us = o.bound_sync_period_us;
      const std::string stage = sim::strf("%s %uk", lab::scenario_name(o.scenario), lc.bitrate_kbit);
      const auto shown = [&](double f) {
        bar.show(stage, (static_cast<double>(i) + f) / static_cast<double>(o.bitrates.size()),
                 monotonic_ns());
      };
      results.push_back(roundtrip ? sim::sync_roundtrip_scenario(o.line, lc, o.syncs, &log, shown)
                                  : sim::sync_latency_scenario(o.line, lc, o.presses, &log, shown));
      simulated_s += static_cast<double>(results.back().duration_ns) / 1e9;
      pass = pass && results.back().ok;
    }
    bar.clear();
    report += roundtrip ? lab::sync_roundtrip_section(results) : lab::sync_latency_section(results);
    files.push_back({std::string(lab::scenario_name(o.scenario)) + ".csv", lab::sync_csv(results)});
    for (const sim::SyncResult& r : results) {
      files.push_back({sim::strf("%s-%uk.svg", lab::scenario_name(o.scenario), r.lab.bitrate_kbit),
                       lab::sync_svg(r, roundtrip)});
    }
  }
  if (o.scenario == lab::Scenario::kSyncProcessing) {
    const lab::SyncProcessingResult r = lab::sync_processing_run(elf, o.syncs, o.line.seed);
    report += lab::sync_processing_section(r);
    files.push_back({"sync-processing.svg", lab::sync_processing_svg(r)});
    pass = pass && r.ok;
  }
  if (o.scenario == lab::Scenario::kAlternative) {
    std::vector<sim::AlternativeResult> results;
    for (size_t i = 0; i < o.bitrates.size(); ++i) {
      const std::string stage = sim::strf("alternative %uk", o.bitrates[i]);
      results.push_back(sim::alternative_scenario(o.line, o.bitrates[i], o.presses, &log, [&](double f) {
        bar.show(stage, (static_cast<double>(i) + f) / static_cast<double>(o.bitrates.size()),
                 monotonic_ns());
      }));
      const sim::AlternativeResult& r = results.back();
      simulated_s +=
          static_cast<double>(r.modbus.duration_ns + r.canopen.duration_ns + r.arduino.duration_ns) / 1e9;
      pass = pass && r.ok;
    }
    bar.clear();
    report += lab::alternative_section(results);
    for (const sim::AlternativeResult& r : results)
      files.push_back({sim::strf("alternative-%uk.svg", r.bitrate_kbit), lab::alternative_svg(r)});
  }
  const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();

  report += sim::strf("\nfiles in %s/: report.txt%s", o.out_dir.c_str(), o.events ? " events.csv" : "");
  for (const auto& f : files) report += " " + f.first;
  report += sim::strf("\nresult: %s\n", pass ? "PASS" : "FAIL");
  std::fputs(report.c_str(), stdout);
  std::fflush(stdout);

  if (!o.trace_path.empty()) {
    // A path ending in .pcap gets pcap (LINKTYPE_CAN_SOCKETCAN) of the same frames.
    const bool pcap = is_pcap_path(o.trace_path);
    std::string pcap_bytes;
    Status written = pcap ? pcap_from_candump_log(trace.text(), &pcap_bytes) : Status::ok();
    if (written) written = write_file(o.trace_path, pcap ? pcap_bytes : trace.text());
    if (!written) {
      std::fprintf(stderr, "mb2co-lab: %s\n", written.message().c_str());
      return 1;
    }
  }
  files.push_back({"report.txt", report});
  if (o.events) files.push_back({"events.csv", std::string(sim::EventLog::header()) + log.text()});
  for (const auto& f : files) {
    const Status written = write_file(out / f.first, f.second);
    if (!written) {
      std::fprintf(stderr, "mb2co-lab: %s\n", written.message().c_str());
      return 1;
    }
  }
  if (!o.quiet) {
    std::fprintf(stderr, "mb2co-lab: simulated %.1f s of line time in %.2f s of CPU: %.0fx real time\n",
                 simulated_s, wall_s, wall_s > 0 ? simulated_s / wall_s : 0.0);
  }
  return pass ? 0 : 3;
}
