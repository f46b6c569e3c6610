// The Modbus round trip of mb2co-node as a master sees it: COUNT FC 03
// requests of one holding register, one after the other, by libmodbus on
// the RTU pty (--rtu DEV, 115200 8N1, slave 1) or on Modbus/TCP (--tcp
// HOST:PORT, unit 255); each timed from before the call to its return
// (CLOCK_MONOTONIC). Prints one line: min, median, p99, max and mean in µs.
// Run by bench_round_trip.sh (docs/performance.md "Modbus/TCP round trip").
#include <errno.h>
#include <modbus.h>
#include <time.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

namespace {

int64_t now_ns() {
  timespec ts;
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<int64_t>(ts.tv_sec) * 1000000000 + ts.tv_nsec;
}

int usage() {
  std::fprintf(stderr, "usage: bench_round_trip --rtu DEV | --tcp HOST:PORT [COUNT]\n");
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) return usage();
  const std::string how = argv[1], where = argv[2];
  const long count = argc > 3 ? std::strtol(argv[3], nullptr, 10) : 2000;
  if (count < 1) return usage();
  modbus_t* ctx = nullptr;
  if (how == "--rtu") {
    ctx = modbus_new_rtu(where.c_str(), 115200, 'N', 8, 1);
    if (ctx != nullptr) modbus_set_slave(ctx, 1);
  } else if (how == "--tcp") {
    const size_t colon = where.rfind(':');
    if (colon == std::string::npos) return usage();
    ctx = modbus_new_tcp_pi(where.substr(0, colon).c_str(), where.substr(colon + 1).c_str());
  } else {
    return usage();
  }
  if (ctx == nullptr || modbus_connect(ctx) != 0) {
    std::fprintf(stderr, "bench_round_trip: %s: %s\n", where.c_str(), modbus_strerror(errno));
    return 1;
  }
  modbus_set_response_timeout(ctx, 1, 0);
  std::vector<int64_t> us;
  us.reserve(static_cast<size_t>(count));
  for (long i = 0; i < count; ++i) {
    uint16_t value = 0;
    const int64_t t0 = now_ns();
    if (modbus_read_registers(ctx, 7, 1, &value) != 1) {
      std::fprintf(stderr, "bench_round_trip: request %ld: %s\n", i, modbus_strerror(errno));
      return 1;
    }
    us.push_back((now_ns() - t0) / 1000);
  }
  modbus_close(ctx);
  modbus_free(ctx);
  std::sort(us.begin(), us.end());
  int64_t sum = 0;
  for (int64_t u : us) sum += u;
  const size_t n = us.size();
  std::printf("%s %ld requests: min %lld median %lld p99 %lld max %lld mean %lld us\n", how.c_str() + 2,
              count, static_cast<long long>(us[0]), static_cast<long long>(us[n / 2]),
              static_cast<long long>(us[std::min(n - 1, n * 99 / 100)]), static_cast<long long>(us[n - 1]),
              static_cast<long long>(sum / static_cast<int64_t>(n)));
  return 0;
}
