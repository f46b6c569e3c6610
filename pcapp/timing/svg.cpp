#include "svg.h"

#include <cstdio>
#include <sstream>

#include "report.h"
#include "timing/bus_trace.h"
#include "timing/time_base.h"

namespace mb2co {
namespace timing_cli {
namespace {

constexpr size_t kMaxSegments = 20000;  // beyond this the picture says "truncated"
constexpr double kLeft = 150.0;
constexpr double kPlotWidth = 800.0;
constexpr double kTop = 50.0;
constexpr double kRowHeight = 22.0;

std::string escape(const std::string& s) {
  std::string out;
  for (const char c : s) {
    if (c == '<')
      out += "&lt;";
    else if (c == '>')
      out += "&gt;";
    else if (c == '&')
      out += "&amp;";
    else if (c == '"')
      out += "&quot;";
    else
      out += c;
  }
  return out;
}

std::string us_text(uint64_t ticks, uint32_t bitrate) {
  return format_us(timing::ticks_to_ns_ceil(ticks, bitrate)) + " \xC2\xB5s";
}

// A step of 1, 2 or 5 · 10^k µs giving about 8 ticks over `span_us`.
uint64_t axis_step_us(uint64_t span_us) {
  uint64_t step = 1;
  for (;;) {
    for (const uint64_t m : {1u, 2u, 5u}) {
      if (span_us / (step * m) <= 8) return step * m;
    }
    step *= 10;
  }
}

}  // namespace

std::string busy_period_svg(const std::vector<timing::MessageSpec>& set,
                            const std::vector<timing::RtaMessage>& rta, size_t target,
                            const timing::RtaResult& result, uint32_t bitrate_bps) {
  std::vector<timing::BusSegment> segments(kMaxSegments);
  std::vector<uint64_t> sent(target + 1);
  bool truncated = false;
  const size_t count = timing::trace_busy_period(rta.data(), rta.size(), target, timing::bits_to_ticks(1),
                                                 sent.data(), segments.data(), segments.size(), &truncated);
  segments.resize(count);

  // Rows: the blocker (if any) first, then priorities 0..target.
  const bool blocked = !segments.empty() && segments[0].message > target;
  const size_t rows = target + 1 + (blocked ? 1u : 0u);
  auto row_of = [&](size_t message) { return message > target ? 0u : message + (blocked ? 1u : 0u); };
  const uint64_t end = segments.empty() ? 1u : segments.back().end;
  auto x = [&](uint64_t t) { return kLeft + kPlotWidth * static_cast<double>(t) / static_cast<double>(end); };
  const double height = kTop + kRowHeight * static_cast<double>(rows) + 50.0;

  std::ostringstream svg;
  char buf[256];
  std::snprintf(buf, sizeof buf,
                "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%.0f\" height=\"%.0f\" "
                "font-family=\"sans-serif\" font-size=\"12\">\n",
                kLeft + kPlotWidth + 120.0, height);
  svg << buf << "<rect width=\"100%\" height=\"100%\" fill=\"white\"/>\n";
  const std::string r_text =
      result.revised == timing::Bound::kBounded
          ? us_text(result.r, bitrate_bps) + " (instance " + std::to_string(result.critical_instance) + ")"
          : "unbounded";
  svg << "<text x=\"10\" y=\"20\" font-size=\"14\">Worst-case busy period of " << escape(set[target].name)
      << ": L = " << us_text(end, bitrate_bps) << ", R = " << escape(r_text)
      << (truncated ? " [truncated]" : "") << "</text>\n";

  // Row labels and guide lines.
  for (size_t r = 0; r < rows; ++r) {
    const bool is_blocker = blocked && r == 0;
    const size_t message = is_blocker ? segments[0].message : r - (blocked ? 1u : 0u);
    const double y = kTop + kRowHeight * static_cast<double>(r);
    svg << "<text x=\"10\" y=\"" << y + 15 << "\"" << (message == target ? " font-weight=\"bold\"" : "")
        << ">" << (is_blocker ? "blocker " : "") << escape(set[message].name) << "</text>\n";
    svg << "<line x1=\"" << kLeft << "\" x2=\"" << kLeft + kPlotWidth << "\" y1=\"" << y + kRowHeight
        << "\" y2=\"" << y + kRowHeight << "\" stroke=\"#ddd\"/>\n";
  }
  // Transmissions and queuing instants.
  for (const timing::BusSegment& s : segments) {
    const double y = kTop + kRowHeight * static_cast<double>(row_of(s.message));
    const char* fill = s.message > target ? "#999" : s.message == target ? "#d62728" : "#1f77b4";
    std::snprintf(buf, sizeof buf,
                  "<rect x=\"%.2f\" y=\"%.1f\" width=\"%.2f\" height=\"%.1f\" fill=\"%s\" "
                  "stroke=\"black\" stroke-width=\"0.5\"/>\n",
                  x(s.start), y + 3, x(s.end) - x(s.start), kRowHeight - 6, fill);
    svg << buf;
    if (s.message <= target) {
      const double ax = x(timing::worst_case_arrival(rta[s.message], s.instance));
      std::snprintf(buf, sizeof buf, "<path d=\"M%.2f %.1f l-4 -6 h8 z\" fill=\"black\"/>\n", ax, y + 3);
      svg << buf;
    }
    if (s.message == target) {
      // Response time of this instance, from its event q T - J (eq. 6.13).
      const uint64_t event_plus_j = s.instance * rta[target].t;
      const uint64_t response = s.end + rta[target].j - event_plus_j;
      std::snprintf(buf, sizeof buf, "<text x=\"%.2f\" y=\"%.1f\" font-size=\"10\">", x(s.end) + 2, y + 14);
      svg << buf << "R" << s.instance << " = " << escape(us_text(response, bitrate_bps)) << "</text>\n";
    }
  }
  // Time axis in µs.
  const double axis_y = kTop + kRowHeight * static_cast<double>(rows) + 10.0;
  svg << "<line x1=\"" << kLeft << "\" x2=\"" << kLeft + kPlotWidth << "\" y1=\"" << axis_y << "\" y2=\""
      << axis_y << "\" stroke=\"black\"/>\n";
  const uint64_t span_us = end / bitrate_bps + 1u;
  const uint64_t step = axis_step_us(span_us);
  for (uint64_t t_us = 0; timing::us_to_ticks(t_us, bitrate_bps) <= end; t_us += step) {
    const double tx = x(timing::us_to_ticks(t_us, bitrate_bps));
    svg << "<line x1=\"" << tx << "\" x2=\"" << tx << "\" y1=\"" << axis_y << "\" y2=\"" << axis_y + 5
        << "\" stroke=\"black\"/>\n";
    svg << "<text x=\"" << tx << "\" y=\"" << axis_y + 18 << "\" text-anchor=\"middle\">" << t_us
        << "</text>\n";
  }
  svg << "<text x=\"" << kLeft + kPlotWidth << "\" y=\"" << axis_y + 34
      << "\" text-anchor=\"end\">time from the critical instant (\xC2\xB5s)</text>\n";
  svg << "</svg>\n";
  return svg.str();
}

}  // namespace timing_cli
}  // namespace mb2co
