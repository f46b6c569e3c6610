// Command line of mb2co-node (the convention of docs/cli.md,
// shared/host/cli.h): one option table from which the parser, --help and the
// bash completion come. Bad input is one line and exit 2; tests call
// apply_options directly.
#pragma once
#include <stdint.h>

#include <string>

#include "host/cli.h"
#include "host/status.h"
#include "host/tcp_address.h"
#include "modbus/parity.h"

namespace mb2co {
namespace node {

struct NodeOptions {
  std::string can = "vcan0";  ///< interface name, or "none": Modbus and OD without a bus
  std::string pty_link;       ///< --pty PATH: symlink to the pty we create
  std::string serial;         ///< --serial DEV: an existing tty instead of a pty
  uint32_t baud = 115200;
  modbus::Parity parity = modbus::Parity::kNone;
  uint8_t node_id = 1;        ///< used when no saved parameters say otherwise
  uint16_t bitrate_kbit = 0;  ///< 0: as stored / default (500); else 125, 250, 500 or 1000 (2000h/2's unit)
  uint8_t stations = 0;       ///< 0: as stored / default (4)
  int topology = -1;          ///< -1 as stored, 0 chain, 1 ring
  std::string eeprom;         ///< file backing 1010h "save" (like the Uno's EEPROM)
  uint32_t eeprom_write_us = 0;  ///< time to program one EEPROM byte (0: at once; the Uno: 3300)
  std::string trace_can;         ///< --trace-can FILE: every frame sent and received ("" none)
  /// --tcp HOST:PORT: Modbus/TCP beside (or, with --serial none, instead
  /// of) the serial line; tcp_given false: no Modbus/TCP.
  TcpAddress tcp;
  bool tcp_given = false;
  uint32_t tcp_clients = 8;  ///< --tcp-clients N: connections at once
};

/// --serial's value for "no serial line at all" (Modbus/TCP only).
constexpr const char* kNoSerial = "none";

/// The option table of mb2co-node (help, parser and completion come from it).
const cli::Program& program();
/// Fills `out` from a parse of program() (options not given keep their
/// value); fails, a usage error, for combinations the table cannot express.
Status apply_options(const cli::Args& args, NodeOptions* out);

}  // namespace node
}  // namespace mb2co
