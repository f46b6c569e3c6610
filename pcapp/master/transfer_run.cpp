#include "transfer_run.h"

#include <cstdio>

#include "canopen/clock.h"
#include "exit_codes.h"

namespace mb2co {
namespace master {

/// Redraws "[#####     ] 52%  68/131 KiB  97 KiB/s" every 200 ms.
class TransferRun::Progress : public ProgressHook {
 public:
  Progress(const TransferNetwork* net, uint8_t node, std::ostream* out) : net_(net), node_(node), out_(out) {}
  void update(uint32_t now_us) override {
    if (start_us_ == 0) start_us_ = now_us | 1u;
    if (!time_reached(now_us, next_us_)) return;
    next_us_ = now_us + 200000u;
    uint32_t moved = 0, size = 0;
    net_->progress(node_, &moved, &size);
    const double s = static_cast<double>(now_us - start_us_) / 1e6;
    const double rate = s > 0 ? moved / 1024.0 / s : 0;
    char line[128];
    if (size) {
      const int filled = static_cast<int>(30.0 * moved / size);
      std::snprintf(line, sizeof line, "\r[%-30.*s] %3u%%  %u/%u KiB  %.0f KiB/s ", filled,
                    "##############################", static_cast<unsigned>(100.0 * moved / size),
                    moved / 1024, size / 1024, rate);
    } else {
      std::snprintf(line, sizeof line, "\r%u KiB  %.0f KiB/s ", moved / 1024, rate);
    }
    *out_ << line << std::flush;
    drawn_ = true;
  }
  uint32_t next_us() const override { return next_us_; }
  void end() {
    if (drawn_) *out_ << "\n" << std::flush;
  }

 private:
  const TransferNetwork* net_;
  uint8_t node_;
  std::ostream* out_;
  uint32_t start_us_ = 0;
  uint32_t next_us_ = 0;
  bool drawn_ = false;
};

bool TransferRun::run() {
  Progress progress(network_.get(), progress_node_, progress_out_);
  const bool done = network_->run(progress_out_ ? &progress : nullptr);
  progress.end();
  if (!done) {
    network_->abort_all(canopen::kAbortGeneral);
    return false;
  }
  return true;
}

int exit_code_of(const Transfer& t) {
  if (t.ok()) return kExitOk;
  if (t.link_down) return kExitBus;
  if (!t.gateway_error.empty()) return kExitRefused;
  if (t.node_lost || (t.result == canopen::kAbortTimeout && !t.by_server)) return kExitNoAnswer;
  return kExitRefused;
}

}  // namespace master
}  // namespace mb2co
