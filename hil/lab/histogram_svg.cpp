#include "histogram_svg.h"

#include <algorithm>

#include "plot_axis.h"
#include "sim/event_log.h"

namespace mb2co {
namespace lab {

using sim::strf;

std::string histogram_svg(const std::string& heading, const char* counted, const HistogramUnit& unit,
                          const std::vector<HistogramPanel>& panels) {
  const double per = unit.per_unit;
  const auto shown = [per](uint64_t v) { return strf("%.2f", static_cast<double>(v) / per); };
  uint64_t x_max = 1;
  for (const HistogramPanel& p : panels) {
    x_max = std::max<uint64_t>(x_max, p.max);
    if (p.bounded) x_max = std::max<uint64_t>(x_max, p.worst);
  }
  // Round ticks (1, 2 or 5 x 10^k units) and 100 bins over the whole axis.
  const PlotAxis x_axis = round_axis(static_cast<double>(x_max) / per * 1.02, 10);
  const double x_units = x_axis.max();
  const int W = 900, panel_h = 220, left = 70, right = 20, top = 40;
  const int H = top + static_cast<int>(panels.size()) * (panel_h + 40) + 20;
  const double pw = W - left - right;
  const int kBins = 100;  // a round axis over 100 bins: round bin widths too
  std::string s = strf(
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%d\" height=\"%d\" font-family=\"sans-serif\" "
      "font-size=\"12\">\n<rect width=\"100%%\" height=\"100%%\" fill=\"white\"/>\n",
      W, H);
  s += strf(
      "<text x=\"%d\" y=\"22\" font-size=\"15\">%s measured histogram (%s per %s %s bin), analytical bounds "
      "(red)</text>\n",
      left, heading.c_str(), counted, strf("%g", x_units / kBins).c_str(), unit.name);
  const double bin_units = x_units / kBins;
  for (size_t k = 0; k < panels.size(); ++k) {
    const HistogramPanel& p = panels[k];
    const std::vector<uint64_t> none;
    const std::vector<uint64_t>& samples = p.samples != nullptr ? *p.samples : none;
    const int y0 = top + static_cast<int>(k) * (panel_h + 40) + 10;
    std::vector<uint32_t> bins(kBins, 0);
    for (uint64_t v : samples) {
      const size_t b = static_cast<size_t>(static_cast<double>(v) / per / bin_units);
      ++bins[std::min<size_t>(b, kBins - 1)];
    }
    const uint32_t peak = std::max<uint32_t>(1, *std::max_element(bins.begin(), bins.end()));
    const PlotAxis y_axis = round_axis(peak, 5);
    s += strf("<text x=\"%d\" y=\"%d\">%s: n=%zu, min %s, max %s %s</text>\n", left, y0 + 12, p.name.c_str(),
              samples.size(), shown(p.min).c_str(), shown(p.max).c_str(), unit.name);
    const int base = y0 + panel_h;
    const double ph = panel_h - 30;  // bar height of y_axis.max()
    for (int t = 0; t <= y_axis.ticks; ++t) {
      const double y = base - ph * t / y_axis.ticks;
      s += strf("<line x1=\"%d\" y1=\"%.1f\" x2=\"%d\" y2=\"%.1f\" stroke=\"#e0e0e0\"/>\n", left, y,
                W - right, y);
      s += strf("<text x=\"%d\" y=\"%.1f\" text-anchor=\"end\">%s</text>\n", left - 6, y + 4,
                y_axis.label(t).c_str());
    }
    s += strf("<text x=\"14\" y=\"%d\" text-anchor=\"middle\" transform=\"rotate(-90 14 %d)\">count</text>\n",
              base - panel_h / 2, base - panel_h / 2);
    s += strf("<line x1=\"%d\" y1=\"%d\" x2=\"%d\" y2=\"%d\" stroke=\"black\"/>\n", left, base, W - right,
              base);
    s += strf("<line x1=\"%d\" y1=\"%.1f\" x2=\"%d\" y2=\"%d\" stroke=\"black\"/>\n", left, base - ph, left,
              base);
    for (size_t b = 0; b < bins.size(); ++b) {
      if (bins[b] == 0) continue;
      const double h = ph * static_cast<double>(bins[b]) / y_axis.max();
      s += strf("<rect x=\"%.1f\" y=\"%.1f\" width=\"%.1f\" height=\"%.1f\" fill=\"%s\"/>\n",
                left + pw * static_cast<double>(b) / kBins, base - h, pw / kBins, h, p.fill);
    }
    if (p.bounded) {
      for (int side = p.has_best ? 0 : 1; side < 2; ++side) {
        const uint64_t v = side ? p.worst : p.best;
        const double x = left + pw * (static_cast<double>(v) / per) / x_units;
        s += strf("<line x1=\"%.1f\" y1=\"%d\" x2=\"%.1f\" y2=\"%d\" stroke=\"red\" stroke-width=\"2\"/>\n",
                  x, y0 + 18, x, base);
        s += strf("<text x=\"%.1f\" y=\"%d\" fill=\"red\" text-anchor=\"%s\">%s %s</text>\n",
                  x + (side ? -4 : 4), y0 + 30, side ? "end" : "start", side ? p.worst_label : "best",
                  shown(v).c_str());
      }
    }
    for (int t = 0; t <= x_axis.ticks; ++t) {
      const double x = left + pw * t / x_axis.ticks;
      s += strf("<text x=\"%.1f\" y=\"%d\" text-anchor=\"middle\">%s</text>\n", x, base + 15,
                x_axis.label(t).c_str());
    }
    s += strf("<text x=\"%d\" y=\"%d\" text-anchor=\"end\">%s</text>\n", W - right, base + 30, unit.name);
  }
  return s + "</svg>\n";
}

}  // namespace lab
}  // namespace mb2co
