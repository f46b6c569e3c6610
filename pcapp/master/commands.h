// mb2co-master's commands. Each reads its operands and options (parsed and
// checked against its table in cli_options.cpp), runs on an open transport
// (SocketCAN or a gateway) and returns an ExitCode; results go to `out` (plain lines or, with
// --json, one JSON object per line), the one-line error to `err`.
#pragma once
#include <ostream>

#include "cli_options.h"
#include "transport.h"

namespace mb2co {
namespace master {

int scan_command(const Options& o, Transport& transport, std::ostream& out, std::ostream& err);
int read_command(const Options& o, Transport& transport, std::ostream& out, std::ostream& err);
int write_command(const Options& o, Transport& transport, std::ostream& out, std::ostream& err);
int upload_command(const Options& o, Transport& transport, std::ostream& out, std::ostream& err);
int download_command(const Options& o, Transport& transport, std::ostream& out, std::ostream& err);
int nmt_command(const Options& o, Transport& transport, std::ostream& out, std::ostream& err);
int sync_command(const Options& o, Transport& transport, std::ostream& out, std::ostream& err);
int time_command(const Options& o, Transport& transport, std::ostream& out, std::ostream& err);
int watch_command(const Options& o, Transport& transport, std::ostream& out, std::ostream& err);
int dump_command(const Options& o, Transport& transport, std::ostream& out, std::ostream& err);
int configure_command(const Options& o, Transport& transport, std::ostream& out, std::ostream& err);
int serve_command(const Options& o, Transport& transport, std::ostream& out, std::ostream& err);

using CommandFunction = int (*)(const Options& o, Transport& transport, std::ostream& out, std::ostream& err);
/// The function of the command named `name` (one of program()'s); null for
/// a name that is none.
CommandFunction command_function(const std::string& name);

/// Opens `transport` (Transport::open): kExitOk, or kExitBus with the
/// reason printed.
int open_transport(const Options& o, Transport& transport, std::ostream& err);

/// Prints "mb2co-master: WHY" and returns `code` (the one error style).
int fail(std::ostream& err, int code, const std::string& why);

}  // namespace master
}  // namespace mb2co
