// mb2co-master's command line on the shared layer (shared/host/cli.h,
// docs/cli.md): one cli::Command per subcommand with its own options, the
// global options (-i, -t, --watchdog, --json, --eds, --via-modbus ...)
// accepted before or after the subcommand's name. The parser checks every
// option value; the operands (NODE INDEX SUB ...) are each command's to read
// (number_words.h).
#pragma once
#include <stdint.h>

#include <string>
#include <vector>

#include "host/cli.h"
#include "host/status.h"
#include "host/tcp_address.h"
#include "modbus/parity.h"
#include "number_words.h"

namespace mb2co {
namespace master {

/// upload --max-bytes: the most bytes an upload takes unless told (16 MiB:
/// ten times the largest object an mb2co node serves, room for a device's
/// firmware image). A value for `read` and the other commands takes at
/// most kValueMaxBytes (transfer_network.h).
static const uint32_t kUploadMaxBytesDefault = 16u * 1024u * 1024u;

/// serve: where it listens and when it drops a silent client, unless told.
static const char kServeListenDefault[] = "unix:/tmp/CO_command_socket";
static const uint32_t kServeIdleDefaultMs = 600000;

/// One invocation: the global options as values, the command's own options
/// and operands as the parser left them (already checked against the table).
struct Options {
  std::string iface = "can0";  ///< -i IFACE
  uint32_t timeout_ms = 1000;  ///< -t MS: SDO client timeout (CiA 301 leaves it to us)
  bool json = false;           ///< --json: one JSON object per line
  bool verbose = false;        ///< -v: how the CAN socket moves frames, one line on stderr
  /// --watchdog MS: end the transfers of a node whose heartbeats stop for MS
  /// (heartbeat consumer time for SDO commands; 0: none). Not `watch
  /// --heartbeat`, which is watch's own consumer time.
  uint16_t watchdog_ms = 0;
  std::string eds;  ///< --eds FILE: types for read/write, entries for dump
  /// --via-modbus PORT[:SLAVE]: the gateway's serial device ("": SocketCAN)
  /// and its Modbus address; --baud, --parity: the line (8 data bits).
  std::string gateway_port;
  uint8_t gateway_slave = 1;
  /// --via-modbus tcp:HOST:PORT: Modbus/TCP to mb2co-node --tcp instead of
  /// a serial port (gateway_port keeps the text; gateway_slave is the unit
  /// id, 0xFF).
  bool gateway_on_tcp = false;
  TcpAddress gateway_tcp;
  uint32_t baud = 115200;
  modbus::Parity parity = modbus::Parity::kNone;
  std::string command;
  cli::Args args;  ///< the command's own options (args.has("--block")) and its operands
};

/// The tables: commands, their options, the global options, the footer
/// with the exit codes (exit_codes.h).
const cli::Program& program();

/// Fills `out` from a parse that ran (cli::Action::kRun). Fails with one
/// line (no prefix) where the table cannot say it: PORT:SLAVE out of range,
/// --baud or --parity without --via-modbus, via_modbus_refusal().
Status apply_options(const cli::Args& args, Options* out);

/// Why a command (or option) cannot run through a gateway: one line,
/// "watch needs raw CAN frames (...)"; "" when it can.
std::string via_modbus_refusal(const Options& o);
/// The same reason for a command that needs the SocketCAN loop.
std::string needs_can_frames(const std::string& what);

}  // namespace master
}  // namespace mb2co
