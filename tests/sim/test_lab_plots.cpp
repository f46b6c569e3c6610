// mb2co-lab's plots and progress bar: round axis ticks, a count axis on the
// histograms, and a progress bar that redraws at most ~10 times a second.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <regex>
#include <string>
#include <vector>

#include "plot_axis.h"
#include "progress_bar.h"
#include "report.h"

namespace mb2co {
namespace lab {
namespace {

TEST(LabPlotAxis, TicksAreOneTwoOrFiveTimesAPowerOfTen) {
  // The histogram that showed 8, 16, ..., 49, 57: about 57 ms of data.
  const PlotAxis a = round_axis(57.3, 10);
  EXPECT_DOUBLE_EQ(a.step, 10);
  EXPECT_EQ(a.ticks, 6);
  EXPECT_EQ(a.label(0), "0");
  EXPECT_EQ(a.label(3), "30");
  EXPECT_EQ(a.label(6), "60");

  EXPECT_DOUBLE_EQ(round_axis(0.73, 10).step, 0.1);
  EXPECT_EQ(round_axis(0.73, 10).label(7), "0.7");
  EXPECT_DOUBLE_EQ(round_axis(13, 10).step, 2);
  EXPECT_EQ(round_axis(13, 10).ticks, 7);
  EXPECT_DOUBLE_EQ(round_axis(250, 5).step, 50);
  EXPECT_DOUBLE_EQ(round_axis(3, 5).step, 1);  // counts: whole steps
  EXPECT_EQ(round_axis(3, 5).ticks, 3);
}

TEST(LabPlotAxis, EveryAxisCoversItsDataWithinTheTickLimit) {
  for (double v = 0.0013; v < 2e6; v *= 1.37) {
    for (int max_ticks : {3, 5, 10}) {
      const PlotAxis a = round_axis(v, max_ticks);
      EXPECT_GE(a.max(), v * (1 - 1e-9)) << v;
      EXPECT_LE(a.ticks, max_ticks) << v;
      EXPECT_GE(a.ticks, 1) << v;
      // Not wastefully coarse: the next finer 1-2-5 step would need too many ticks.
      const double m = a.step / std::pow(10.0, std::floor(std::log10(a.step) + 1e-9));
      const double finer = m > 4 ? a.step * 0.4 : m > 1.5 ? a.step * 0.5 : a.step * 0.5;
      EXPECT_GT(std::ceil(v / finer - 1e-9), max_ticks) << v << " step " << a.step;
    }
  }
  EXPECT_EQ(round_axis(0, 10).ticks, 1);
}

std::vector<std::string> axis_labels(const std::string& svg, const std::string& anchor) {
  std::vector<std::string> out;
  const std::regex re("<text x=\"[0-9.]+\" y=\"[0-9.]+\" text-anchor=\"" + anchor + "\">([0-9.]+)</text>");
  for (auto it = std::sregex_iterator(svg.begin(), svg.end(), re); it != std::sregex_iterator(); ++it)
    out.push_back((*it)[1]);
  return out;
}

TEST(LabLatencyPlot, HistogramHasRoundTimeTicksAndACountAxis) {
  sim::LatencyResult r;
  r.c.bitrate_kbit = 125;
  r.c.remote = false;
  // 200 presses 20..46.9 ms: the axis ends at 50 ms, bins are 0.5 ms wide.
  for (uint64_t k = 0; k < 200; ++k) r.samples_ns.push_back(20'000'000 + k * 135'000);
  // Presses 10 and 11 of one bin on top: that bin holds the peak.
  r.samples_ns.insert(r.samples_ns.end(), 9, 30'000'000);
  r.min_ns = 20'000'000;
  r.max_ns = 20'000'000 + 199 * 135'000;
  const std::string svg = latency_svg({r}, 125);
  const std::vector<std::string> x = axis_labels(svg, "middle");
  ASSERT_EQ(x.size(), 11u) << svg;  // 0, 5, ..., 50 ms
  EXPECT_EQ(x.front(), "0");
  EXPECT_EQ(x[1], "5");
  EXPECT_EQ(x[7], "35");
  EXPECT_EQ(x.back(), "50");
  EXPECT_NE(svg.find(">count</text>"), std::string::npos);
  EXPECT_NE(svg.find("presses per 0.5 ms bin"), std::string::npos);
  const std::vector<std::string> y = axis_labels(svg, "end");
  ASSERT_GE(y.size(), 2u);
  EXPECT_EQ(y.front(), "0");
  // Bin 60 (30.0-30.5 ms) holds the 9 extra presses and 3 of the even
  // spread (30.125, 30.26, 30.395): 12, on an axis 0, 5, 10, 15.
  EXPECT_EQ(y.back(), "15");
  EXPECT_EQ(y.size(), 4u);
}

TEST(LabProgressBar, RedrawsAtMostTenTimesASecond) {
  std::FILE* sink = std::tmpfile();
  ASSERT_NE(sink, nullptr);
  ProgressBar bar(sink);
  // 40,000 presses reported every 10 presses over 2 s: 4,000 calls.
  const uint64_t calls = 4000;
  const uint64_t run_ns = 2'000'000'000;
  for (uint64_t k = 1; k <= calls; ++k)
    bar.show("latency 125k modbus", static_cast<double>(k) / static_cast<double>(calls), run_ns * k / calls);
  EXPECT_LE(bar.redraws(), 2u + run_ns / ProgressBar::kMinRedrawNs);
  EXPECT_GE(bar.redraws(), 10u);  // it does move
  // The last state drawn is 100 %.
  std::fflush(sink);
  const long size = std::ftell(sink);
  ASSERT_GT(size, 40);
  std::vector<char> text(static_cast<size_t>(size));
  std::rewind(sink);
  ASSERT_EQ(std::fread(text.data(), 1, text.size(), sink), text.size());
  const std::string all(text.begin(), text.end());
  EXPECT_NE(all.rfind("100%"), std::string::npos);
  EXPECT_GT(all.rfind("100%"), all.rfind("\r"));
  std::fclose(sink);
}

TEST(LabProgressBar, ANewStageIsDrawnAtOnce) {
  std::FILE* sink = std::tmpfile();
  ProgressBar bar(sink);
  bar.show("stop2", 0.5, 1000);
  bar.show("faults", 0.5, 1001);  // 1 ns later, but another stage
  EXPECT_EQ(bar.redraws(), 2u);
  std::fclose(sink);
  ProgressBar off(nullptr);
  off.show("run", 1, 0);
  EXPECT_EQ(off.redraws(), 0u);
}

// The report's CAN line says which error frames a lone station caused at
// power-up (a PASS of stop2 showed "916 error frames" without a word).
TEST(LabReport, ErrorFramesSayHowManyWereAckErrors) {
  sim::LineSummary s;
  EXPECT_EQ(error_frames_text(s), "0 error frames");
  s.error_frames = 916;
  s.ack_error_frames = 916;
  EXPECT_EQ(error_frames_text(s),
            "916 error frames (all ACK errors: no other station powered yet to acknowledge)");
  s.error_frames = 920;
  EXPECT_EQ(error_frames_text(s),
            "920 error frames (916 of them ACK errors: no other station powered yet to acknowledge)");
  s.ack_error_frames = 0;
  EXPECT_EQ(error_frames_text(s), "920 error frames") << "corruption only";
}

}  // namespace
}  // namespace lab
}  // namespace mb2co
