// Serial line for the Linux build of the firmware (and for host test peers):
// either a fresh pseudo-terminal pair whose far end is the "device" a Modbus
// master opens, or an existing tty (USB adapter) in raw mode.
// Non-blocking; bytes come with CLOCK_MONOTONIC µs timestamps for RTU framing.
#pragma once
#include <stddef.h>
#include <stdint.h>

#include <string>

#include "host/status.h"
#include "modbus/parity.h"

namespace mb2co {
namespace port {

/// Microseconds of CLOCK_MONOTONIC, truncated to 32 bits (wraps like micros()).
uint32_t monotonic_us();

/// Owns one file descriptor (and a symlink, if it made one). Not copyable.
/// Every call that can fail answers with a Status (its message: one line).
/// A failed create_pty()/open_tty() leaves the port closed.
class SerialPort {
 public:
  SerialPort() = default;
  ~SerialPort();
  SerialPort(const SerialPort&) = delete;
  SerialPort& operator=(const SerialPort&) = delete;

  /// Creates a pty pair; we keep the master side. The slave side (what a
  /// master such as libmodbus opens) is path(); with a non-empty `link_path`
  /// a symlink to it is made there (an existing symlink is replaced, any
  /// other file is an error) and removed again by close(). The slave side is
  /// kept open in raw mode, so no echo happens and our reads never see a
  /// hang-up when a client closes it.
  Status create_pty(const std::string& link_path = std::string());

  /// Opens an existing tty raw at `baud` (a standard rate), 8 data bits,
  /// `parity`, `stop_bits` 1 or 2; input/output queues flushed.
  Status open_tty(const std::string& path, uint32_t baud, modbus::Parity parity, unsigned stop_bits = 1);

  void close();
  bool is_open() const { return fd_ >= 0; }
  /// For poll(): POLLIN when bytes are waiting.
  int fd() const { return fd_; }
  /// The device a peer opens: the pty's slave side, or the tty opened.
  const std::string& path() const { return path_; }
  const std::string& link_path() const { return link_; }

  /// Reads what is waiting, up to `capacity` bytes, without blocking. Every
  /// byte of one read(2) gets the same stamp, taken just before it: a stamp is
  /// never earlier than the byte's arrival minus the read's own latency.
  /// *count = bytes read (0: nothing waiting, also on failure).
  Status read(uint8_t* bytes, uint32_t* stamps_us, size_t capacity, size_t* count);

  /// Writes all of `data` (waits with poll() while the kernel queue is full).
  Status write(const uint8_t* data, size_t length);

 private:
  /// Closes the port; the failure `what` with errno's text.
  Status fail(const std::string& what);

  int fd_ = -1;
  int pty_slave_fd_ = -1;  ///< held open for the reasons given at create_pty()
  std::string path_;
  std::string link_;
};

}  // namespace port
}  // namespace mb2co
