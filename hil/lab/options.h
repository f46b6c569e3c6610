// Command line of mb2co-lab. Every bad option is one line of text and exit 2.
#pragma once
#include <stdint.h>

#include <string>
#include <vector>

#include "sim/line.h"

namespace mb2co {
namespace lab {

enum class Scenario { kDefault, kRun, kStop2, kLatency, kFaults };

struct Options {
  Scenario scenario = Scenario::kDefault;
  sim::LineConfig line;  ///< stations, seed, timing
  std::vector<uint32_t> bitrates = {125, 250, 500, 1000};
  uint32_t presses = 1000;
  std::string out_dir = "out";
  std::string trace_path;        ///< --trace: the bus as a candump -L log ("" none)
  uint32_t duration_s = 30;      ///< run scenario
  std::string firmware = "uno";  ///< uno | fast
  bool quiet = false;
  bool help = false;
};

/// Parses argv; a failure says why in one line.
Status parse_options(int argc, char** argv, Options* out);
const char* usage();
const char* scenario_name(Scenario s);

}  // namespace lab
}  // namespace mb2co
