// The mb2co-timing command: frame, load, rta and latency. run() is main()
// without the process: streams in, exit status out, so tests can drive it.
#pragma once
#include <ostream>

namespace mb2co {
namespace timing_cli {

/// Exit status: 0 done, 1 error (one line on `err`), 3 `rta --check` found
/// a message that misses its deadline.
int run(int argc, char** argv, std::ostream& out, std::ostream& err);

}  // namespace timing_cli
}  // namespace mb2co
