#include "plant_app.h"

#include <unistd.h>

#include <QFile>
#include <cstdio>

#include "latency_cycle.h"
#include "plant/config_parser.h"
#include "station_cycle.h"
#include "timing/latency.h"

namespace mb2co {
namespace pcapp {

namespace {
constexpr int kDefaultCycleMs = 20;
constexpr int64_t kStatusPeriodNs = 100 * 1000 * 1000;  // the live line at 10 Hz
// The network view at 1 Hz: one short extra transaction (4 bytes per node
// heard) now and then, not one per cycle.
constexpr int64_t kViewPeriodNs = 1000 * 1000 * 1000;

void say_error(const QString& line) {
  std::fprintf(stderr, "mb2co-plant: %s\n", line.toLocal8Bit().constData());
}

timing::SerialFormat serial_format(const AppOptions& o) {
  timing::SerialFormat f;
  f.baud = static_cast<uint32_t>(o.baud);
  f.parity = o.parity;
  return f;
}

/// The plant config: the file's (keys left out keep docs/plant.md's
/// defaults), step_ms replaced by --cycle-ms; without a file, the defaults
/// with a 20 ms step.
Status load_config(const AppOptions& o, plant::PlantConfig& config, int& cycle_ms) {
  plant::ConfigError error{};
  if (!o.config.isEmpty()) {
    QFile file(o.config);
    if (!file.open(QIODevice::ReadOnly))
      return Status::failure(QString(o.config + ": " + file.errorString()).toStdString());
    const QByteArray text = file.readAll();
    if (!plant::parse_plant_config(text.constData(), static_cast<size_t>(text.size()), config, error)) {
      return Status::failure(QStringLiteral("%1:%2:%3: %4")
                                 .arg(o.config)
                                 .arg(error.line)
                                 .arg(error.column)
                                 .arg(error.message)
                                 .toStdString());
    }
  } else {
    config.step_ms = kDefaultCycleMs;
  }
  if (o.cycle_ms > 0) config.step_ms = static_cast<uint32_t>(o.cycle_ms);
  uint16_t keys = 0;
  if (!plant::check_plant_config(config, error, keys)) {
    return Status::failure(
        QStringLiteral("--cycle-ms %1: %2").arg(config.step_ms).arg(error.message).toStdString());
  }
  cycle_ms = static_cast<int>(config.step_ms);
  return Status::ok();
}
}  // namespace

PlantApp::PlantApp(const AppOptions& options, QObject* parent)
    : QObject(parent), options_(options), view_(stdout, !options.plain && isatty(fileno(stdout)) != 0) {}

PlantApp::~PlantApp() = default;

int PlantApp::prepare() {
  layout_ = default_layout();
  if (options_.latency) {
    cycle_ms_ = options_.cycle_ms > 0 ? options_.cycle_ms : kDefaultCycleMs;
    ClockBound bound;
    bound.spread_us = timing::LatencyParams().fw_loop_us;
    bound.drift_ppm = options_.drift_ppm;
    latency_ = new LatencyCycle(layout_, options_.remote, options_.button, options_.presses, bound);
    mode_.reset(latency_);
  } else {
    plant::PlantConfig config;
    const Status loaded = load_config(options_, config, cycle_ms_);
    if (!loaded) {
      say_error(QString::fromStdString(loaded.message()));
      return 2;
    }
    mode_.reset(new StationCycle(layout_, config));
  }
  const Status planned =
      plan_transactions(layout_, mode_->required_reads(), mode_->optional_reads(), mode_->writes(), plan_);
  if (!planned) {
    say_error(QString::fromStdString(planned.message()));
    return 2;
  }
  in_.resize(plan_);
  out_.resize(plan_);
  mode_->safe_outputs(out_);

  std::vector<const char*> names = {"cycle", "t_us", "link", "modbus_us"};
  for (const char* n : mode_->column_names()) names.push_back(n);
  if (!options_.log.isEmpty()) {
    const Status opened = log_.open(options_.log.toStdString(), names);
    if (!opened) {
      say_error(QString::fromStdString(opened.message()));
      return 2;
    }
  }
  SupervisorConfig sc;
  sc.link.path = options_.port.toStdString();
  sc.link.on_tcp = options_.on_tcp;
  sc.link.tcp = options_.tcp;
  sc.link.baud = options_.baud;
  sc.link.parity = options_.parity;
  sc.link.slave = options_.slave;
  const timing::SerialFormat wire = serial_format(options_);
  sc.link.timeout_ms = options_.timeout_ms > 0 ? options_.timeout_ms
                                               : derived_timeout_ms(plan_, options_.on_tcp ? nullptr : &wire);
  sc.link.retries = options_.retries;
  sc.boot_wait_ms = options_.boot_wait_ms;
  sc.reconnect_max_ms = options_.reconnect_max_ms;
  supervisor_ = new LinkSupervisor(sc, this);
  connect(supervisor_, &LinkSupervisor::connected, this, [this](const QString& d) {
    link_was_up_ = true;
    const timing::SerialFormat f = serial_format(options_);
    const QString line = options_.on_tcp
                             ? QString("Modbus/TCP")
                             : "frames " + QString::number(plan_frame_time_ns(plan_, f) / 1000) +
                                   " us + t3.5 = " + QString::number(plan_wire_time_ns(plan_, f) / 1000) +
                                   " us at " + QString::number(options_.baud) + " baud";
    log_event("link up " + d + " | cycle " + QString::number(cycle_ms_) +
              " ms: " + QString::fromStdString(describe(plan_)) + ", " + line);
  });
  connect(supervisor_, &LinkSupervisor::disconnected, this,
          [this](const QString& why) { log_event("link lost: " + why + " | plant safe, reconnecting"); });
  connect(supervisor_, &LinkSupervisor::retrying, this, [this](const QString& why, int next_ms) {
    log_event((link_was_up_ ? "reconnect failed: " : "connect failed: ") + why + " | next attempt in " +
              QString::number(next_ms) + " ms");
  });
  connect(supervisor_, &LinkSupervisor::fatal, this, [this](const QString& why) {
    say_error(why);
    shutting_down_ = true;
    timer_.stop();
    emit finished(1);
  });
  timer_.setTimerType(Qt::PreciseTimer);
  timer_.setInterval(cycle_ms_);
  connect(&timer_, &QTimer::timeout, this, &PlantApp::tick);
  return 0;
}

void PlantApp::start() {
  clock_.start();
  supervisor_->start();
  if (!shutting_down_) timer_.start();
}

void PlantApp::log_event(const QString& text) {
  view_.event(seconds(), text.toStdString());
}

void PlantApp::tick() {
  const int64_t now_ns = clock_.nsecsElapsed();
  if (last_tick_ns_ >= 0 && now_ns - last_tick_ns_ > int64_t{cycle_ms_} * 1500000) ++late_cycles_;
  last_tick_ns_ = now_ns;
  ++cycles_;
  bool stepped = false;
  bool exchanged = false;
  uint32_t modbus_us = 0;
  if (supervisor_->up() && !remote_ready()) return;
  if (supervisor_->up()) {
    ModbusLink& link = supervisor_->link();
    QElapsedTimer t;
    t.start();
    LinkResult s = link.read(plan_, out_, in_);
    int64_t ns = t.nsecsElapsed();
    if (s.ok()) {
      mode_->step(in_, out_);
      stepped = true;
      if (!plan_.read_write) {
        t.restart();
        s = link.write(plan_, out_);
        ns += t.nsecsElapsed();
      }
    }
    modbus_us = static_cast<uint32_t>(ns / 1000);
    const std::string& error = s.status.message();
    if (s.ok()) {
      exchanged = true;
      modbus_us_.add(modbus_us);
      last_exception_.clear();
    } else if (s.outcome == LinkStatus::kFailed) {
      lose_link(error);
    } else {
      // The gateway refused a request: the inputs or the written RUN state
      // are not what the controller assumes, so it is made safe.
      ++exceptions_;
      mode_->link_lost();
      mode_->safe_outputs(out_);
      if (error != last_exception_) log_event(QString::fromStdString("modbus " + error + " | plant safe"));
      last_exception_ = error;
    }
  }
  if (!stepped) mode_->step_offline();
  // After the cycle's write: the LED of this press is already on its way.
  if (latency_ != nullptr && latency_->wants_remote_edge() && supervisor_->up()) read_remote_edge();
  poll_neighbours(now_ns);
  for (const QString& line : QString::fromStdString(mode_->take_event()).split('\n', Qt::SkipEmptyParts)) {
    log_event(line);
  }
  if (log_.is_open()) log_cycle(exchanged, modbus_us);
  if (view_.terminal() && now_ns - last_status_ns_ >= kStatusPeriodNs) {
    last_status_ns_ = now_ns;
    char tail[96];
    std::snprintf(tail, sizeof tail, " | %s %.1f ms | errors %llu",
                  supervisor_->up() ? "modbus" : "LINK DOWN", modbus_us / 1000.0,
                  static_cast<unsigned long long>(link_losses_) + exceptions_);
    const std::string neighbours = neighbours_.summary();
    view_.status(mode_->status() + tail + (neighbours.empty() ? "" : " | " + neighbours));
  }
  if (mode_->done())
    shutdown(0, "done");
  else if (options_.cycles != 0 && cycles_ >= options_.cycles)
    shutdown(0, "cycles done");
}

bool PlantApp::remote_ready() {
  if (!options_.remote || remote_probed_) return true;
  const Status s = remote_clock_.probe(supervisor_->link());
  if (!s) {
    say_error("latency --remote: nothing to measure: " + QString::fromStdString(s.message()));
    shutdown(kExitNothingToMeasure, "nothing to measure");
    return false;
  }
  remote_probed_ = true;
  log_event(QStringLiteral("remote button on station %1, LED here on station %2: common clock (TIME)")
                .arg(remote_clock_.remote_id())
                .arg(remote_clock_.here_id()));
  return true;
}

void PlantApp::read_remote_edge() {
  RemoteEdge e;
  const Status s = remote_clock_.read_edge(supervisor_->link(), e);
  if (s) {
    latency_->set_remote_edge(e);
  } else {
    latency_->remote_edge_lost();
    log_event(QString::fromStdString("press missed: " + s.message()));
  }
}

void PlantApp::poll_neighbours(int64_t now_ns) {
  // Not in the latency lab: an extra transaction would be in its numbers.
  if (!neighbours_asked_ || latency_ != nullptr || !supervisor_->up()) return;
  if (last_view_ns_ != 0 && now_ns - last_view_ns_ < kViewPeriodNs) return;
  last_view_ns_ = now_ns | 1;
  std::vector<modbus::NetViewEntry> view;
  bool unsupported = false;
  const LinkResult s = supervisor_->link().network_view(view, unsupported);
  if (s.ok()) {
    for (const std::string& e : neighbours_.update(view)) log_event(QString::fromStdString(e));
  } else if (unsupported) {
    neighbours_asked_ = false;
    log_event("the gateway has no network view (FC 2Bh/0Dh: exception 01): neighbours not shown");
  }
  // Anything else (busy, a lost frame) waits for the next poll; a lost link
  // is the cycle's to find.
}

void PlantApp::log_cycle(bool link_up, uint32_t modbus_us) {
  row_.clear();
  row_.push_back(LogValue{static_cast<int64_t>(cycles_), nullptr});
  row_.push_back(LogValue{last_tick_ns_ / 1000, nullptr});
  row_.push_back(LogValue{link_up ? 1 : 0, nullptr});
  row_.push_back(LogValue{modbus_us, nullptr});
  mode_->columns(row_);
  log_.write(row_);
}

void PlantApp::lose_link(const std::string& reason) {
  ++link_losses_;
  mode_->link_lost();
  mode_->safe_outputs(out_);
  supervisor_->lost(QString::fromStdString(reason));
}

std::string PlantApp::cycle_summary() const {
  std::string s = "summary cycles=" + std::to_string(cycles_) + " late=" + std::to_string(late_cycles_) +
                  " link_losses=" + std::to_string(link_losses_) +
                  " exceptions=" + std::to_string(exceptions_) +
                  " retries=" + std::to_string(supervisor_->link().retries_used()) +
                  " late_bytes_dropped=" + std::to_string(supervisor_->link().stale_bytes_dropped());
  if (modbus_us_.count() > 0) {
    s += " modbus_us_per_cycle min=" + std::to_string(modbus_us_.min_us()) +
         " mean=" + std::to_string(modbus_us_.mean_us()) +
         " p99=" + std::to_string(modbus_us_.percentile_us(99)) +
         " max=" + std::to_string(modbus_us_.max_us());
  }
  // The serial line's frame times; Modbus/TCP has no such bound.
  if (!options_.on_tcp)
    s += " wire_us=" + std::to_string(plan_wire_time_ns(plan_, serial_format(options_)) / 1000);
  return s;
}

void PlantApp::shutdown(int code, const QString& why) {
  if (shutting_down_) return;
  shutting_down_ = true;
  timer_.stop();
  QString done = why;
  const QString safe_value = options_.latency ? "lab LED 0" : "RUN=0";
  // The gateway is known safe only when it took the safe outputs; otherwise
  // its watchdog (2000h/9) stops the station later, and a script that
  // stopped the app must hear that this stop was not confirmed.
  bool confirmed = false;
  if (supervisor_->up()) {
    mode_->safe_outputs(out_);
    const LinkResult written = supervisor_->link().write(plan_, out_);
    confirmed = written.ok();
    done += confirmed ? ": " + safe_value + " written"
                      : QString::fromStdString(": safe write failed (" + written.status.message() + ")");
  } else if (link_was_up_) {
    done += ": " + safe_value + " not written (no link)";
  }
  if (!confirmed && link_was_up_ && code == 0) code = kExitNotConfirmed;
  supervisor_->stop();
  log_event(done + ", port closed");
  log_event(QString::fromStdString(cycle_summary()));
  const std::string m = mode_->summary();
  if (!m.empty()) log_event(QString::fromStdString(m));
  log_.close();
  if (latency_ != nullptr && !options_.csv.isEmpty()) {
    QFile csv(options_.csv);
    const std::string text = latency_->csv();
    if (!csv.open(QIODevice::WriteOnly | QIODevice::Truncate) ||
        csv.write(text.data(), static_cast<qint64>(text.size())) != static_cast<qint64>(text.size())) {
      say_error(options_.csv + ": " + csv.errorString());
      code = code == 0 ? 1 : code;
    }
  }
  view_.finish();
  emit finished(code);
}

}  // namespace pcapp
}  // namespace mb2co
