// The whole production line in one process: N gateways (NodeStation) on one
// CAN bus, each wired by its own serial link to its PC (PcStation), in one
// virtual clock. Commissioning is done like a technician would before the
// line runs: every Arduino gets its station configuration by OD writes and
// saves it (1010h); then all power on together.
#pragma once
#include <stdint.h>

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "host/status.h"
#include "sim/can_bus.h"
#include "sim/event_log.h"
#include "sim/event_queue.h"
#include "sim/node_station.h"
#include "sim/pc_station.h"
#include "sim/rng.h"
#include "sim/serial_link.h"

namespace mb2co {
namespace sim {

struct LineConfig {
  int stations = 4;             ///< node ids 1..N
  bool ring = false;            ///< 2000h/3: chain (false) or ring
  uint32_t bitrate_kbit = 500;  ///< 125, 250, 500 or 1000
  uint32_t baud = 115200;       ///< Modbus RTU, 8E1 (11-bit characters)
  NodeTiming node;
  PcTiming pc;
  uint16_t debounce_ms = 20;           ///< 2000h/6
  uint16_t heartbeat_ms = 100;         ///< 1017h (consumers watch for 3x this)
  uint16_t tpdo1_inhibit_100us = 100;  ///< 1800h/3 of TPDO1 (line state)
  /// Latency lab (seed 000 §11), 0-based stations; -1: not configured. The
  /// PC's Arduino watches the remote one's buttons (2130h/2, RPDO3 from its
  /// TPDO2) and sends its lab LED (6200h/1) by TPDO3 to the remote one's
  /// RPDO4, so the remote LED follows what the PC writes.
  int lab_pc = -1;
  int lab_remote = -1;
  /// power_on_all() switches the Arduinos on within this window (USB
  /// enumeration, bootloaders): their periodic traffic is not in step.
  SimNs power_on_spread_ns = 300 * kNsPerMs;
  uint64_t seed = 1;
  /// More commissioning after the station's own (the SYNC labs: a SYNC
  /// producer, a synchronous TPDO, an RPDO to the LED), as a technician
  /// would write it by SDO before saving. Unset: none.
  std::function<void(int station, canopen::ObjectDictionary& od)> commission_more;
};

/// A commissioning OD write; throws std::logic_error when the OD refuses it
/// (a line that cannot be commissioned is a programming error of the caller).
void commission_write(canopen::ObjectDictionary& od, uint16_t index, uint8_t sub, uint32_t value,
                      uint16_t size);
/// Maps `entry` (index<<16 | sub<<8 | bits) as the only object of PDO
/// mapping `map_index` and enables communication record `comm_index` with
/// `cob_id` (CiA 301 order: disable, map, enable).
void commission_pdo(canopen::ObjectDictionary& od, uint16_t comm_index, uint16_t map_index, uint32_t entry,
                    uint32_t cob_id);

/// Checks the configuration: ok when it is usable.
Status check_line_config(const LineConfig& c);

class Line {
 public:
  /// Builds and commissions the line (config must pass check_line_config);
  /// nothing is powered yet. `log` may be null.
  Line(const LineConfig& config, EventLog* log);
  Line(const Line&) = delete;
  Line& operator=(const Line&) = delete;

  const LineConfig& config() const { return config_; }
  int size() const { return config_.stations; }
  EventQueue& queue() { return q_; }
  SimNs now() const { return q_.now(); }
  CanBus& bus() { return *bus_; }
  NodeStation& node(int i) { return *nodes_[static_cast<size_t>(i)]; }
  PcStation& pc(int i) { return *pcs_[static_cast<size_t>(i)]; }
  SerialLink& link(int i) { return *links_[static_cast<size_t>(i)]; }
  EventLog* log() { return log_; }

  /// Powers every Arduino on at a random time within power_on_spread_ns
  /// from now.
  void power_on_all();
  void run_until(SimNs t) { q_.run_until(t); }
  void run_for(SimNs d) { q_.run_until(q_.now() + d); }
  /// Calls `fn` at `t` (≥ now) inside the event order.
  void at(SimNs t, std::function<void()> fn);

  /// Operator actions and faults, logged.
  void set_button(int station, uint8_t button, bool pressed);
  void power(int station, bool on);
  void plug(int station, bool connected);
  void note(int station, const char* event, const std::string& detail);

  /// Observers for scenarios (called after logging).
  std::function<void(int station, uint8_t leds)> on_leds;
  std::function<void(int station, const NodeState& before, const NodeState& after)> on_state;
  std::function<void(int station, uint8_t button, bool pressed)> on_button;
  std::function<void(const CanAttempt& attempt)> on_can;

 private:
  class Script final : public Handler {
   public:
    void on_event(uint32_t, uint64_t arg) override;
    std::vector<std::function<void()>> fns;
  };
  void commission(int i);
  void wire_log();

  LineConfig config_;
  EventLog* log_;
  EventQueue q_;
  std::unique_ptr<CanBus> bus_;
  std::vector<std::unique_ptr<NodeStation>> nodes_;
  std::vector<std::unique_ptr<SerialLink>> links_;
  std::vector<std::unique_ptr<PcStation>> pcs_;
  Script script_;
  Rng rng_;
};

}  // namespace sim
}  // namespace mb2co
