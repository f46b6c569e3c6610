// The lab's outputs: the text report (deterministic: no wall-clock figures),
// the CSV of latency samples and the SVG plots. All built as strings.
#pragma once
#include <string>
#include <vector>

#include "histogram_svg.h"
#include "options.h"
#include "sim/scenarios.h"

namespace mb2co {
namespace lab {

std::string report_header(const Options& o);
std::string run_section(const sim::RunResult& r);
std::string stop2_section(const sim::Stop2Result& r);
/// "916 error frames (all ACK errors: no other station powered yet to
/// acknowledge)": the count, and how many of them a station alone on the bus
/// caused (power-up), so a PASS with error frames is not read as a bad bus.
std::string error_frames_text(const sim::LineSummary& s);
std::string latency_section(const std::vector<sim::LatencyResult>& results);
std::string faults_section(const sim::FaultsResult& r);

/// One row per press: bitrate_kbit,path,press,latency_ns,best_ns,worst_ns,inside.
std::string latency_csv(const std::vector<sim::LatencyResult>& results);
/// One row per bound term and case (the breakdown of shared/timing).
std::string bound_terms_csv(const std::vector<sim::LatencyResult>& results);

/// A latency case as a histogram panel named `name` (blue: Modbus only,
/// orange: over CANopen); `r` must outlive the panel.
HistogramPanel latency_panel(const sim::LatencyResult& r, const char* name);
/// Latency histograms of every case at `bitrate_kbit`, bounds drawn.
std::string latency_svg(const std::vector<sim::LatencyResult>& results, uint32_t bitrate_kbit);
/// RUN/stopped lanes per station with STOP2 and START presses.
std::string timeline_svg(const sim::LineSummary& line, int stations, const std::string& title);

}  // namespace lab
}  // namespace mb2co
