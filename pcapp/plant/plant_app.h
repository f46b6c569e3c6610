// The application object: owns the mode (station or latency), the link
// supervisor, the cycle timer, the log and the status view, and runs one
// control cycle per timer tick. Exit codes: 0 after a signal, --cycles or
// --presses; 1 when the first connection fails (LinkSupervisor: not for a
// slave that answers late or garbled); 2 for a bad config or log;
// 3 (kExitNotConfirmed) when it stops without the gateway having taken the
// safe outputs (link down, or the last write failed).
#pragma once
#include <QElapsedTimer>
#include <QObject>
#include <QTimer>
#include <memory>

#include "cycle_log.h"
#include "cycle_mode.h"
#include "latency_stats.h"
#include "link_supervisor.h"
#include "options.h"
#include "remote_clock.h"
#include "status_view.h"
#include "transaction_plan.h"

namespace mb2co {
namespace pcapp {

class LatencyCycle;

class PlantApp : public QObject {
  Q_OBJECT
 public:
  /// Stopped, but the gateway did not confirm RUN=0 / lab LED 0: its Modbus
  /// watchdog (2000h/9) stops the station instead.
  static constexpr int kExitNotConfirmed = 3;
  /// latency --remote with nothing to measure: no common clock (TIME), no
  /// previous station, or the remote station unreachable (one line why).
  static constexpr int kExitNothingToMeasure = 4;

  explicit PlantApp(const AppOptions& options, QObject* parent = nullptr);
  ~PlantApp() override;

  /// Reads the config, builds the mode and the plan, opens the log. 0 or an
  /// exit code, with the one-line reason already printed.
  int prepare();
  /// Starts the first connection; the cycle timer runs from the start.
  void start();
  /// Writes the safe outputs (if the link is up), closes everything, prints
  /// the summary and emits finished(code).
  void shutdown(int code, const QString& why);

 signals:
  void finished(int code);

 private:
  void tick();
  void lose_link(const std::string& reason);
  void log_cycle(bool link_up, uint32_t modbus_us);
  double seconds() const { return static_cast<double>(clock_.nsecsElapsed()) / 1e9; }
  void log_event(const QString& text);
  /// Once a second in the station mode: the gateway's network view into
  /// neighbours_ (changes as events). Stops for good at exception 01.
  void poll_neighbours(int64_t now_ns);
  std::string cycle_summary() const;
  /// latency --remote: the probe before the first cycle (false: refused,
  /// shutting down), then the remote edge of a press just seen.
  bool remote_ready();
  void read_remote_edge();

  AppOptions options_;
  int cycle_ms_ = 20;
  RegisterLayout layout_;
  std::unique_ptr<CycleMode> mode_;
  LatencyCycle* latency_ = nullptr;  ///< mode_ in the latency mode (for its CSV)
  RemoteClock remote_clock_;         ///< latency --remote
  bool remote_probed_ = false;
  TransactionPlan plan_;
  RegisterImage in_;
  RegisterImage out_;
  LinkSupervisor* supervisor_ = nullptr;
  QTimer timer_;
  QElapsedTimer clock_;
  StatusView view_;
  CycleLog log_;
  std::vector<LogValue> row_;
  uint64_t cycles_ = 0;
  uint64_t late_cycles_ = 0;  ///< ticks that came more than half a period late
  int64_t last_tick_ns_ = -1;
  int64_t last_status_ns_ = 0;
  uint64_t link_losses_ = 0;
  uint64_t exceptions_ = 0;
  LatencyStats modbus_us_;  ///< Modbus time per cycle (all its transactions)
  uint32_t last_modbus_us_ = 0;
  std::string last_exception_;  ///< reported once until the next good cycle
  bool shutting_down_ = false;
  bool link_was_up_ = false;  ///< the gateway was reached: its outputs are ours to make safe
  NeighboursView neighbours_;
  bool neighbours_asked_ = true;  ///< false once the gateway said it has no network view
  int64_t last_view_ns_ = 0;
};

}  // namespace pcapp
}  // namespace mb2co
