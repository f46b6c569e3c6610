// POSIX signals into the Qt event loop: the handler only writes the signal
// number into a pipe (async-signal-safe); a QSocketNotifier on the read end
// emits received() from the event loop, where anything may be done.
#pragma once
#include <QObject>
#include <initializer_list>

class QSocketNotifier;

namespace mb2co {
namespace pcapp {

/// One instance per process (the handler needs a static pipe).
class SignalPipe : public QObject {
  Q_OBJECT
 public:
  /// Installs the handler for each of `numbers` (e.g. SIGINT, SIGTERM).
  explicit SignalPipe(std::initializer_list<int> numbers, QObject* parent = nullptr);
  ~SignalPipe() override;
  /// False when the pipe or a handler could not be set up.
  bool ok() const { return ok_; }

 signals:
  void received(int signal_number);

 private:
  void drain();
  static void handler(int signal_number);
  static int fds_[2];
  QSocketNotifier* notifier_ = nullptr;
  bool ok_ = false;
};

}  // namespace pcapp
}  // namespace mb2co
