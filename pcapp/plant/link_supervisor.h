// The link's life cycle: open the port (given, or the one Arduino on USB;
// or the Modbus/TCP connection), wait for the Uno's boot loader (opening
// the port resets it; none on TCP), verify
// the slave (FC 2B/0E, else 08/00), then report it up. A lost link is closed
// and reopened with back-off until the gateway answers again.
//
// The first connection is fatal when it cannot work as asked: the port cannot
// be opened (or no single Arduino is found), nothing answers, or the slave
// that answers is definitely not an mb2co gateway (a bad --port or --slave
// must end the program with one line). A slave that answers, but late or
// garbled (a loaded simulator, a disturbed line, a wrong baud rate), is there:
// that is retried with back-off like a reconnection, one line per attempt,
// from then on for every failure but a definite one.
#pragma once
#include <QObject>
#include <QString>
#include <QTimer>

#include "backoff.h"
#include "modbus_link.h"

namespace mb2co {
namespace pcapp {

struct SupervisorConfig {
  LinkSettings link;      ///< link.path empty: auto-detect an Arduino
  int boot_wait_ms = -1;  ///< -1: 2000 for an Arduino port, 0 otherwise
  int reconnect_first_ms = 100;
  int reconnect_max_ms = 5000;
};

class LinkSupervisor : public QObject {
  Q_OBJECT
 public:
  static constexpr int kArduinoBootWaitMs = 2000;

  explicit LinkSupervisor(const SupervisorConfig& config, QObject* parent = nullptr);

  /// First connection (asynchronous: connected() or fatal()).
  void start();
  bool up() const { return up_; }
  ModbusLink& link() { return link_; }
  /// The cycle found the link dead: close it, report, reconnect later.
  void lost(const QString& reason);
  /// No more reconnecting (shutdown); closes the port.
  void stop();

 signals:
  /// Verified; `description`: port, slave and its identity.
  void connected(const QString& description);
  void disconnected(const QString& reason);
  /// An attempt to (re)connect failed; the next one follows in `next_ms`.
  void retrying(const QString& reason, int next_ms);
  /// The first connection failed: one line for the user.
  void fatal(const QString& message);

 private:
  void attempt();
  void verify();
  /// `definite`: the slave is not an mb2co gateway (not worth retrying at
  /// the first connection).
  void failed(const QString& reason, bool definite = false);

  SupervisorConfig config_;
  ModbusLink link_;
  Backoff backoff_;
  QTimer timer_;        ///< boot wait and reconnection delays (single shot)
  bool first_ = true;   ///< not verified yet since start()
  bool heard_ = false;  ///< a slave answered something since start()
  bool up_ = false;
  bool stopped_ = false;
};

}  // namespace pcapp
}  // namespace mb2co
