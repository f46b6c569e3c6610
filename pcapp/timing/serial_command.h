// `mb2co-timing serial`: cycle time, token round and worst-case latency of
// CANopen on a serial multi-drop segment (seed 003, shared/timing/
// serial_segment.h) for given node counts, identifier width, access method,
// baud rate and window. Its option table joins the program's (options.cpp)
// and run() hands it the parsed arguments: one line each.
#pragma once
#include <ostream>

#include "host/cli.h"

namespace mb2co {
namespace timing_cli {

/// The command's entry in the program's option tables.
cli::Command serial_command();
/// Runs it on arguments the parser checked against serial_command().
/// Exit status: 0 done, 2 usage error (one line on `err`).
int serial_run(const cli::Args& args, std::ostream& out, std::ostream& err);

}  // namespace timing_cli
}  // namespace mb2co
