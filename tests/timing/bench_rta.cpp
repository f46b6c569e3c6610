// Benchmark: response-time analysis of the 1,000-message set in
// data/rta_1000.csv at 1 Mbit/s (Davis frame bits), as `mb2co-timing rta`
// runs it. docs/timing.md reports the figures.
#include <benchmark/benchmark.h>

#include <cstdio>
#include <cstdlib>
#include <vector>

#include "csv_set.h"
#include "timing/message_set.h"
#include "timing/time_base.h"

namespace {

using namespace mb2co;

struct Set1000 {
  std::vector<timing::RtaMessage> rta;
  std::vector<timing::RtaResult> results;

  Set1000() {
    std::vector<timing::MessageSpec> specs;
    const Status status = timing_cli::read_message_csv(MB2CO_TIMING_DATA "/rta_1000.csv", specs);
    if (!status) {
      std::fprintf(stderr, "%s\n", status.message().c_str());
      std::exit(1);
    }
    timing::sort_by_priority(specs.data(), specs.size());
    rta.resize(specs.size());
    results.resize(specs.size());
    for (size_t i = 0; i < specs.size(); ++i) {
      rta[i] = timing::to_rta(specs[i], 1000000, timing::WorstCase::kDavis);
    }
  }
};

const Set1000& set1000() {
  static const Set1000 set;
  return set;
}

// The whole analysis: first attempt and revised analysis of every message.
void BM_Rta1000(benchmark::State& state) {
  Set1000 s = set1000();
  size_t bad = 0;
  for (auto _ : state) {
    timing::analyse(s.rta.data(), s.rta.size(), timing::bits_to_ticks(1), s.results.data(), &bad);
    benchmark::DoNotOptimize(s.results.data());
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(s.rta.size()));
}
BENCHMARK(BM_Rta1000)->Unit(benchmark::kMillisecond);

// The revised analysis of the lowest priority alone: the costliest message.
void BM_RevisedLowestOf1000(benchmark::State& state) {
  const Set1000& s = set1000();
  const size_t i = s.rta.size() - 1;
  for (auto _ : state) {
    timing::Bound b = timing::Bound::kBounded;
    const uint64_t busy = timing::busy_period(s.rta.data(), i, 0, &b);
    benchmark::DoNotOptimize(busy);
  }
}
BENCHMARK(BM_RevisedLowestOf1000)->Unit(benchmark::kMicrosecond);

}  // namespace
