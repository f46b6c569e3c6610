// The command line of mb2co-plant (QCommandLineParser): `mb2co-plant
// [station|latency] [options]`. Every bad value gives one line and exit 2.
#pragma once
#include <stdint.h>

#include <QString>
#include <QStringList>

#include "host/status.h"
#include "host/tcp_address.h"
#include "modbus/parity.h"

namespace mb2co {
namespace pcapp {

struct AppOptions {
  bool latency = false;  ///< mode: the latency lab instead of the station
  bool list_ports = false;
  QString port;  ///< empty: auto-detect an Arduino
  /// --tcp HOST:PORT: Modbus/TCP to mb2co-node --tcp instead of a port.
  bool on_tcp = false;
  TcpAddress tcp;
  int baud = 115200;
  modbus::Parity parity = modbus::Parity::kNone;
  int slave = 1;        ///< --tcp: the unit id, 255 unless given
  int cycle_ms = -1;    ///< -1: the config's step_ms if it sets one, else 20
  QString config;       ///< plant config file (station mode)
  int timeout_ms = -1;  ///< -1: derived from the line (derived_timeout_ms, transaction_plan.h)
  int retries = 2;
  int boot_wait_ms = -1;  ///< -1: 2000 for an Arduino port, 0 otherwise
  int reconnect_max_ms = 5000;
  QString log;               ///< FILE.csv or FILE.jsonl
  bool plain = false;        ///< log lines even on a terminal
  uint64_t cycles = 0;       ///< stop after this many cycles (0: run until a signal)
  bool remote = false;       ///< latency: the button is on the watched remote station
  uint32_t drift_ppm = 100;  ///< latency --remote: most two station clocks run apart
  uint8_t button = 1;        ///< latency: gateway::Button bit (default START)
  uint32_t presses = 0;      ///< latency: stop after this many measured presses
  QString csv;               ///< latency: CSV of every press
  QString exit_text;         ///< --help / --version: print this and exit 0 ("" to run)
};

/// `args` includes the program name (QCoreApplication::arguments()). Fails
/// with one line on a bad option; --help and --version set `exit_text`.
Status parse_options(const QStringList& args, AppOptions& options);

}  // namespace pcapp
}  // namespace mb2co
