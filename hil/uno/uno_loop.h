// mb2co-uno's loop (docs/uno-sim.md): one thread, in passes of up to 2 ms of
// simulated time: run the simulation up to 2 ms ahead of the wall clock,
// move what the pass produced out in one call per kind, read the clock
// once, wait in one poll() for input or the clock and take what came in
// one read per input (io_counts.h: the system calls a pass makes, which
// user-mode Linux traps).
#pragma once
#include <poll.h>
#include <stdint.h>

#include <string>

#include "eeprom_image.h"
#include "host/status.h"
#include "io_counts.h"
#include "pacer.h"
#include "platform/serial_port.h"
#include "platform/socketcan_port.h"
#include "uno_options.h"
#include "uno_rig.h"

namespace mb2co {
namespace uno {

/// What the Uno is wired to: its EEPROM file, the CAN interface and the
/// pty of USART0. Opened before the loop starts, closed (and the EEPROM
/// saved) after it ends.
struct UnoWiring {
  explicit UnoWiring(const UnoOptions& opt) : eeprom(opt.eeprom), with_can(opt.can != "none") {}

  /// Loads `opt.elf` into `rig`, the EEPROM file into its board, binds
  /// the CAN interface and makes the pty; fails with the line to print.
  Status open(const UnoOptions& opt, UnoRig& rig);
  /// Closes the ports and writes the board's EEPROM back to its file.
  Status close(const UnoOptions& opt, UnoRig& rig);

  EepromImage eeprom;
  linux_port::SocketCanPort can;
  bool with_can;
  port::SerialPort serial;
};

/// The paced loop over an opened wiring. `stop_fd` becomes readable on
/// SIGINT/SIGTERM. Not copyable.
class UnoLoop {
 public:
  UnoLoop(const UnoOptions& opt, UnoRig& rig, UnoWiring& wiring, int stop_fd);
  UnoLoop(const UnoLoop&) = delete;
  UnoLoop& operator=(const UnoLoop&) = delete;

  /// Runs until "quit", a signal, --duration or a failure; the exit status
  /// (0, or 1 after a failure whose line was printed).
  int run();
  /// The simulated and wall time on stderr, and with --stats the system
  /// calls the loop made.
  void report() const;

 private:
  /// Runs the image for one pass and moves out what it produced; false
  /// when the image stopped or the pty refused bytes (exit_code_ set).
  bool run_pass();
  void send_can(const std::vector<CanWire::Sent>& sent);
  /// Waits for the wall clock to catch up, taking the input that comes
  /// meanwhile; false on a failure (exit_code_ set).
  bool wait_for_the_clock();
  int poll_inputs(pollfd* fds, uint64_t wait_us, bool* cut);
  bool take_input(const pollfd* fds);
  void take_can_frames();
  /// Answers each whole command line that came on stdin.
  void answer_commands();
  std::string answer(const std::string& line);
  void show_leds(uint64_t sim_us);
  uint32_t at_us(uint64_t sim_us) const { return static_cast<uint32_t>(pacer_.wall_of(sim_us)); }
  int fail(const std::string& what);

  const UnoOptions& opt_;
  UnoRig& rig_;
  UnoWiring& wiring_;
  const int stop_fd_;
  const uint64_t wall_start_;
  Pacer pacer_;
  const uint64_t end_us_;  ///< simulated time of --duration; UINT64_MAX: none
  /// The wall clock as last read, or a moment known to have passed since:
  /// one reading per pass, after the run. Under user-mode Linux (the vcan
  /// tests, hil/live) clock_gettime() is a trapped system call (~15 us of its
  /// one CPU), not the vDSO's 20 ns; unpaced, nothing needs it.
  /// The pacer never sees a time later than the true one, so its lead holds.
  uint64_t wall_known_us_;
  std::string leds_shown_;  ///< the levels of the last "leds" line
  bool ready_said_ = false;
  bool stdin_open_ = true;
  bool stop_ = false;
  std::string input_;  ///< stdin not yet taken as whole lines
  int exit_code_ = 0;
  IoCounts io_;
};

}  // namespace uno
}  // namespace mb2co
