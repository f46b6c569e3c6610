#include "link_supervisor.h"

#include "port_finder.h"

namespace mb2co {
namespace pcapp {

LinkSupervisor::LinkSupervisor(const SupervisorConfig& config, QObject* parent)
    : QObject(parent),
      config_(config),
      backoff_(static_cast<uint32_t>(config.reconnect_first_ms),
               static_cast<uint32_t>(config.reconnect_max_ms)) {
  timer_.setSingleShot(true);
}

void LinkSupervisor::start() {
  first_ = true;
  heard_ = false;
  attempt();
}

void LinkSupervisor::attempt() {
  if (stopped_) return;
  LinkSettings settings = config_.link;
  const std::vector<PortInfo> ports = settings.on_tcp ? std::vector<PortInfo>() : list_ports();
  if (settings.path.empty() && !settings.on_tcp) {
    QString path;
    const Status picked = pick_arduino(ports, &path);
    if (!picked) return failed(QString::fromStdString(picked.message()));
    settings.path = path.toStdString();
  }
  const Status opened = link_.open(settings);
  if (!opened) return failed(QString::fromStdString(opened.message()));
  int wait_ms = config_.boot_wait_ms;
  if (wait_ms < 0)
    wait_ms = is_arduino_port(ports, QString::fromStdString(settings.path)) ? kArduinoBootWaitMs : 0;
  // Opening the port pulsed DTR: an Uno is in its boot loader now. Wait on
  // the event loop (signals are still served), then verify.
  timer_.disconnect();
  connect(&timer_, &QTimer::timeout, this, &LinkSupervisor::verify);
  timer_.start(wait_ms);
}

void LinkSupervisor::verify() {
  if (stopped_) return;
  std::string identity;
  const LinkResult identified = link_.identify(identity);
  if (!identified.ok()) {
    link_.close();
    const LinkSettings& s = link_.settings();
    std::string why = s.where() + ": " + identified.status.message();
    const bool definite = identified.outcome == LinkStatus::kException;
    if (!definite && identified.heard) {
      heard_ = true;
      const bool late = identified.status.message().find("later than") != std::string::npos;
      why += late ? " (--timeout-ms?)" : ", late or corrupt (--timeout-ms, --baud, --parity?)";
    } else if (!definite) {
      why += " (" + std::to_string(s.retries + 1) + " attempts of " + std::to_string(s.timeout_ms) + " ms)";
    }
    return failed(QString::fromStdString(why), definite);
  }
  up_ = true;
  first_ = false;
  backoff_.reset();
  emit connected(QString::fromStdString(link_.settings().where() + " slave " +
                                        std::to_string(link_.settings().slave) + ": " + identity));
}

void LinkSupervisor::failed(const QString& reason, bool definite) {
  if (first_ && (definite || !heard_)) {
    stopped_ = true;
    emit fatal(reason);
    return;
  }
  const int next = static_cast<int>(backoff_.next_ms());
  emit retrying(reason, next);
  timer_.disconnect();
  connect(&timer_, &QTimer::timeout, this, &LinkSupervisor::attempt);
  timer_.start(next);
}

void LinkSupervisor::lost(const QString& reason) {
  if (!up_) return;
  up_ = false;
  link_.close();
  emit disconnected(reason);
  const int next = static_cast<int>(backoff_.next_ms());
  timer_.disconnect();
  connect(&timer_, &QTimer::timeout, this, &LinkSupervisor::attempt);
  timer_.start(next);
}

void LinkSupervisor::stop() {
  stopped_ = true;
  timer_.stop();
  up_ = false;
  link_.close();
}

}  // namespace pcapp
}  // namespace mb2co
