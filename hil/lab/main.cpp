// mb2co-lab: runs the simulated production line and prints a report (the
// main job of hil/, docs/lab.md). Exit status: 0 every verdict passed,
// 3 some verdict failed, 2 bad command line, 1 the output could not be written.
#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>

#include "host/pcap_can.h"
#include "options.h"
#include "plant/plant_config.h"
#include "report.h"
#include "scenario_runs.h"
#include "sim/scenarios.h"

namespace {

using namespace mb2co;

/// Exit status of a check that lets the program go on (cli::finish_early's convention).
constexpr int kGoOn = -1;

Status write_file(const std::filesystem::path& path, const std::string& text) {
  std::ofstream f(path, std::ios::binary);
  f << text;
  f.close();
  if (!f) return Status::failure("cannot write " + path.string());
  return Status::ok();
}

/// A line, plant or run length the scenario cannot use: one line and exit 2.
int refuse_unusable(const lab::Options& o) {
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
  return kGoOn;
}

/// A missing AVR image for sync-processing or an output directory that
/// cannot be made: one line and exit 1.
int refuse_missing(const lab::Options& o, const std::string& elf) {
  // sync-processing runs the real AVR image: without one there is nothing to
  // measure, which is not a failed verdict (exit 3) but a missing input.
  if (o.scenario == lab::Scenario::kSyncProcessing && !std::filesystem::is_regular_file(elf)) {
    std::fprintf(stderr,
                 "mb2co-lab: no AVR image %s for sync-processing (--elf FILE, or build the firmware: "
                 "scripts/build.sh)\n",
                 elf.c_str());
    return 1;
  }
  std::error_code ec;
  std::filesystem::create_directories(std::filesystem::path(o.out_dir), ec);
  if (ec) {
    std::fprintf(stderr, "mb2co-lab: cannot create %s: %s\n", o.out_dir.c_str(), ec.message().c_str());
    return 1;
  }
  return kGoOn;
}

/// The list of files and the result line end the report, which goes to stdout.
void print_report(const lab::Options& o, lab::LabRun* run) {
  run->report += sim::strf("\nfiles in %s/: report.txt%s", o.out_dir.c_str(), o.events ? " events.csv" : "");
  for (const auto& f : run->files) run->report += " " + f.first;
  run->report += sim::strf("\nresult: %s\n", run->pass ? "PASS" : "FAIL");
  std::fputs(run->report.c_str(), stdout);
  std::fflush(stdout);
}

/// --trace, then report.txt, the scenarios' files and events.csv in --out.
Status write_outputs(const lab::Options& o, lab::LabRun* run) {
  if (!o.trace_path.empty()) {
    // A path ending in .pcap gets pcap (LINKTYPE_CAN_SOCKETCAN) of the same frames.
    const bool pcap = is_pcap_path(o.trace_path);
    std::string pcap_bytes;
    Status written = pcap ? pcap_from_candump_log(run->trace.text(), &pcap_bytes) : Status::ok();
    if (written) written = write_file(o.trace_path, pcap ? pcap_bytes : run->trace.text());
    if (!written) return written;
  }
  run->files.push_back({"report.txt", run->report});
  if (o.events) run->files.push_back({"events.csv", std::string(sim::EventLog::header()) + run->log.text()});
  const std::filesystem::path out(o.out_dir);
  for (const auto& f : run->files) {
    Status written = write_file(out / f.first, f.second);
    if (!written) return written;
  }
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
  const int unusable = refuse_unusable(o);
  if (unusable != kGoOn) return unusable;
  const std::string elf = o.elf.empty() ? std::string(MB2CO_LAB_DEFAULT_ELF) : o.elf;
  const int missing = refuse_missing(o, elf);
  if (missing != kGoOn) return missing;

  lab::LabRun run(o);
  run.report = lab::report_header(o);
  const auto wall0 = std::chrono::steady_clock::now();
  lab::run_scenarios(o, elf, &run);
  const double wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();

  print_report(o, &run);
  Status written = write_outputs(o, &run);
  if (!written) {
    std::fprintf(stderr, "mb2co-lab: %s\n", written.message().c_str());
    return 1;
  }
  if (!o.quiet) {
    std::fprintf(stderr, "mb2co-lab: simulated %.1f s of line time in %.2f s of CPU: %.0fx real time\n",
                 run.simulated_s, wall_s, wall_s > 0 ? run.simulated_s / wall_s : 0.0);
  }
  return run.pass ? 0 : 3;
}
