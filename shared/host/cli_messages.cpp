#include "host/cli_messages.h"

#include <algorithm>

namespace mb2co {
namespace cli {

size_t edit_distance(const std::string& a, const std::string& b) {
  // Three rows of the dynamic-programming table: the swap needs two back.
  std::vector<size_t> before(b.size() + 1), last(b.size() + 1), row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) last[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const size_t change = last[j - 1] + (a[i - 1] == b[j - 1] ? 0 : 1);
      row[j] = std::min({last[j] + 1, row[j - 1] + 1, change});
      if (i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1]) {
        row[j] = std::min(row[j], before[j - 2] + 1);
      }
    }
    before.swap(last);
    last.swap(row);
  }
  return last[b.size()];
}

std::string nearest_word(const std::string& word, const std::vector<std::string>& known) {
  const size_t letters = word.size() - std::min(word.find_first_not_of('-'), word.size());
  const size_t near_enough = std::min<size_t>(3, std::max<size_t>(1, letters / 3));
  std::string best;
  size_t best_distance = near_enough + 1;
  bool tie = false;
  for (const std::string& k : known) {
    const bool prefix = letters >= 3 && k.size() > word.size() && k.compare(0, word.size(), word) == 0;
    const size_t d = prefix ? 1 : edit_distance(word, k);
    if (d < best_distance) {
      best = k;
      best_distance = d;
      tie = false;
    } else if (d == best_distance && k != best) {
      tie = true;
    }
  }
  return tie ? "" : best;
}

std::string try_help(const std::string& program, const std::string& command) {
  return "(try " + program + (command.empty() ? "" : " " + command) + " --help)";
}

std::string unknown_option(const std::string& program, const std::string& command, const std::string& word,
                           const std::vector<std::string>& known) {
  const std::string near = nearest_word(word, known);
  return "unknown option " + word + (near.empty() ? "" : ", did you mean " + near + "?") + " " +
         try_help(program, command);
}

std::string missing_operand(const std::string& program, const std::string& command,
                            const std::string& operands) {
  return "missing operand: " + (command.empty() ? "" : command + " ") + operands + " " +
         try_help(program, command);
}

std::string bad_value(const std::string& option, const std::string& what, const std::string& value) {
  return option + " must be " + what + ", got \"" + value + "\"";
}

}  // namespace cli
}  // namespace mb2co
