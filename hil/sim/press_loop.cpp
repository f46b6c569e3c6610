#include "sim/press_loop.h"

#include <algorithm>
#include <functional>

#include "gateway/line_app.h"

namespace mb2co {
namespace sim {

PressRun run_presses(Line& line, int button_station, int led_station, uint32_t presses, Rng& rng,
                     const Progress& progress) {
  constexpr SimNs kMs = kNsPerMs;
  constexpr SimNs kS = kNsPerS;
  PressRun r;
  enum class Phase { kIdle, kWaitOn, kHold, kWaitOff } phase = Phase::kIdle;
  SimNs pressed_at = 0;
  uint32_t done = 0;
  uint32_t attempt = 0;
  std::function<void()> next_press;
  auto release = [&] {
    line.set_button(button_station, gateway::kStart, false);
    phase = Phase::kWaitOff;
    const uint32_t a = attempt;
    line.at(line.now() + kS, [&, a] {  // LED stuck on: go on anyway
      if (phase == Phase::kWaitOff && attempt == a) next_press();
    });
  };
  next_press = [&] {
    phase = Phase::kIdle;
    if (done >= presses) return;
    line.at(line.now() + rng.range(20 * kMs, 60 * kMs), [&] {
      ++attempt;
      pressed_at = line.now();
      phase = Phase::kWaitOn;
      line.set_button(button_station, gateway::kStart, true);
      const uint32_t a = attempt;
      line.at(pressed_at + kS, [&, a] {
        if (phase != Phase::kWaitOn || attempt != a) return;
        ++r.lost;
        ++done;
        release();
      });
    });
  };
  line.on_leds = [&](int s, uint8_t leds) {
    if (s != led_station) return;
    const bool lab = (leds & gateway::kLedLab) != 0;
    if (phase == Phase::kWaitOn && lab) {
      r.samples_ns.push_back(line.now() - pressed_at);
      ++done;
      phase = Phase::kHold;
      line.at(line.now() + rng.range(20 * kMs, 50 * kMs), release);
    } else if (phase == Phase::kWaitOff && !lab) {
      next_press();
    }
  };
  line.at(kS, next_press);
  uint32_t reported = 0;
  while (done < presses) {
    line.run_for(100 * kMs);
    if (progress && done / 10 != reported) {
      reported = done / 10;
      progress(static_cast<double>(done) / presses);
    }
  }
  line.on_leds = nullptr;
  return r;
}

SampleStats sample_stats(const std::vector<SimNs>& samples) {
  SampleStats s;
  if (samples.empty()) return s;
  std::vector<SimNs> sorted = samples;
  std::sort(sorted.begin(), sorted.end());
  s.min_ns = sorted.front();
  s.max_ns = sorted.back();
  const size_t rank = (sorted.size() * 99 + 99) / 100;  // nearest rank, ceil(0.99 n)
  s.p99_ns = sorted[rank - 1];
  long double sum = 0;
  for (SimNs v : sorted) sum += static_cast<long double>(v);
  s.mean_ns = static_cast<double>(sum / static_cast<long double>(sorted.size()));
  return s;
}

void judge_latency(LatencyResult& r) {
  const SampleStats st = sample_stats(r.samples_ns);
  r.min_ns = st.min_ns;
  r.max_ns = st.max_ns;
  r.p99_ns = st.p99_ns;
  r.mean_ns = st.mean_ns;
  if (r.bound.ok) {
    for (SimNs v : r.samples_ns) {
      if (v < r.bound.bound.best_ns || v > r.bound.bound.worst_ns) ++r.outside;
    }
  }
  r.ok = r.bound.ok && r.outside == 0 && !r.samples_ns.empty();
}

}  // namespace sim
}  // namespace mb2co
