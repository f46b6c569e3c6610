// A serial multi-drop line (RS-485 and the like) in virtual time, for CANopen
// on a serial segment (seed 003, shared/serialnet): one talker at a time,
// every byte delivered to every other device when its last bit has arrived
// (10 bits per byte at the baud rate, serialnet::byte_time_us), and two
// talkers whose bytes overlap corrupt each other: both messages are lost, as
// on RS-485, so a talker outside its window is a collision. A log of every
// message written, decoded by the bus itself, with its talker and its time
// on the line, for checking who talked when and how long a message waited.
//
// Devices are driven from event to event (a byte's last bit, a device's
// next_deadline), never by polling time. The log grows by one entry per
// message (about 36 bytes); collision checks look only at messages still on
// the line, so a run costs time linear in its traffic.
#pragma once
#include <stdint.h>

#include <deque>
#include <functional>
#include <vector>

#include "canopen/clock.h"
#include "platform/device_port.h"
#include "serialnet/frame_codec.h"

namespace mb2co {
namespace sim {

/// One device on the line, as the bus drives it.
class BusDevice {
 public:
  virtual ~BusDevice() = default;
  virtual void on_byte(uint8_t byte, uint32_t byte_us) = 0;
  virtual void process(uint32_t now_us) = 0;
  virtual void next_deadline(NextDeadline& d) const = 0;
};

class SerialBus {
 public:
  /// One message as written to the line.
  struct Sent {
    int talker;
    uint32_t start_us, end_us;     ///< its first bit, its last bit
    serialnet::SerialMessage msg;  ///< decoded from the written bytes
    uint16_t can_id;               ///< serial_to_can of msg.id (0xFFFF: none)
    bool collided = false;         ///< overlapped another talker's bytes
  };

  SerialBus(const serialnet::ConnectionSet& set, uint32_t baud);

  uint32_t now = 0;  ///< virtual µs
  std::vector<Sent> log;
  int collisions = 0;
  /// Called with each message as it is written (before its bytes arrive):
  /// measurements of long runs that need no log afterwards.
  std::function<void(const Sent&)> on_sent;

  /// A sink for talker `index` (stable: ports live in a deque).
  modbus::ByteSink port(int index);
  /// Device `index` (the index its port() was made with) joins the line.
  void attach(int index, BusDevice* device);
  /// The device is unplugged: it neither runs, hears nor talks from now on.
  void detach(int index);

  /// Raw bytes from `talker` at now (noise, a device talking out of turn).
  void inject(int talker, const std::vector<uint8_t>& bytes);

  /// Runs every device and the line until `until_us` (virtual time): from
  /// event to event (a byte's last bit, a device's deadline), never past it.
  void run_until(uint32_t until_us);
  void run_for(uint32_t us) { run_until(now + us); }

  uint32_t byte_us() const { return byte_us_; }

 private:
  static const uint32_t kRetryStepUs = 20;  ///< a device that asks for now again: let time pass
  struct Port {
    SerialBus* bus;
    int index;
  };
  struct Byte {
    uint32_t at_us;  ///< its last bit
    uint8_t value;
    int talker;
    size_t sent;  ///< index into log
  };

  static bool write(void* ctx, const uint8_t* data, uint16_t length);
  void transmit(int talker, const uint8_t* data, uint8_t n);
  /// Bytes whose slot overlaps another talker's message arrive as garbage.
  void deliver_due();
  bool overlaps_other(const Byte& b) const;
  /// Forgets messages that ended more than a byte before now: no new byte
  /// can overlap them.
  void prune_on_line();

  serialnet::ConnectionSet set_;
  uint32_t byte_us_;
  std::deque<Port> ports_;
  std::vector<BusDevice*> devices_;
  std::deque<Byte> bytes_;
  std::vector<size_t> on_line_;  ///< indices into log of messages not long over
  bool processed_at_now_ = false;
};

}  // namespace sim
}  // namespace mb2co
