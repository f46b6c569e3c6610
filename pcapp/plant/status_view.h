// What the user sees. On a terminal: one live status line, redrawn in
// place, with events printed above it. Otherwise (a pipe, a file, a test):
// plain log lines, one per event, "<seconds> <event>".
// Also the neighbours: the other CANopen nodes as the gateway's network
// view (FC 2Bh/MEI 0Dh, docs/gateway-network.md) shows them, their NMT
// state on the live line and each change as an event.
#pragma once
#include <stdint.h>

#include <cstdio>
#include <string>
#include <vector>

#include "modbus/network_pdu.h"

namespace mb2co {
namespace pcapp {

class StatusView {
 public:
  /// `terminal`: draw the live line (normally isatty(fileno(out))).
  StatusView(std::FILE* out, bool terminal) : out_(out), terminal_(terminal) {}

  /// An event line, stamped with `t_s` seconds since the start; flushed.
  void event(double t_s, const std::string& text);
  /// The live line (terminal only; ignored otherwise).
  void status(const std::string& line);
  /// Leaves the live line in place and moves below it.
  void finish();
  bool terminal() const { return terminal_; }

 private:
  std::FILE* out_;
  bool terminal_;
  bool line_shown_ = false;
};

/// The CiA 301 name of a heartbeat state byte ("operational", "stopped",
/// "pre-operational", "boot-up"; "unknown" for the view's FFh).
const char* nmt_state_name(uint8_t state);

/// The entries of a network view response (`m.data_length / 4` of them)
/// appended to `out`; false when the data are not whole entries.
bool append_view_entries(const modbus::NetMessage& m, std::vector<modbus::NetViewEntry>* out);

/// The neighbours from one network view poll to the next.
class NeighboursView {
 public:
  /// A node heard longer ago than this is shown silent.
  static const uint16_t kSilentMs = 3000;

  /// Takes a whole view (every entry of one poll, in node id order) and
  /// returns what changed since the previous one, one event line each:
  /// "node 4 heard: operational", "node 4 operational -> stopped",
  /// "node 4 silent for 3.2 s", "node 4 heard again: operational".
  std::vector<std::string> update(const std::vector<modbus::NetViewEntry>& view);
  /// For the live line: "neighbours 4 operational, 5 stopped (silent)";
  /// "neighbours none heard" once a view came, "" before.
  std::string summary() const;

 private:
  struct Known {
    uint8_t node_id;
    uint8_t state;
    bool silent;
  };
  std::vector<Known> known_;
  bool polled_ = false;
};

}  // namespace pcapp
}  // namespace mb2co
