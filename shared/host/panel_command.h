// The operator-panel commands that mb2co-node's control channel and
// mb2co-uno's panel share (docs/mb2co-node.md, docs/uno-sim.md): press,
// release and click of a button: the station's START, STOP, STOP2, or the
// buttons a panel names (PanelButtons: the I/O node's joystick). Command
// words and button names are read in any letter case ("click start" is
// "click START"); the error texts are the channels' replies after "error ".
#pragma once
#include <stdint.h>
#include <stdlib.h>

#include <sstream>
#include <string>

namespace mb2co {

struct PanelCommand {
  enum Kind : uint8_t {
    kBlank,   ///< an empty line: no reply
    kButton,  ///< press/release/click of `button`
    kOther,   ///< another command: `word` (lower case) and `rest`, for the channel
    kError,   ///< a malformed button command: reply "error " + `error`
  };
  enum Action : uint8_t { kPress, kRelease, kClick };
  Kind kind = kBlank;
  Action action = kPress;
  int button = -1;         ///< index into the panel's names (station: 0 START, 1 STOP, 2 STOP2)
  uint32_t hold_ms = 100;  ///< click: released after this long (1..60000)
  std::string word;        ///< the command word, lower case
  std::string rest;        ///< kOther: the words after it, as typed
  std::string error;
};

/// The buttons of a panel by name, index = bit of the pressed mask (at most
/// 8). `names` outlives the parse (a static table).
struct PanelButtons {
  const char* const* names;
  int count;
};

/// The station's operator panel: START, STOP, STOP2.
inline PanelButtons panel_station_buttons() {
  static const char* const kNames[3] = {"START", "STOP", "STOP2"};
  return PanelButtons{kNames, 3};
}

/// "START, STOP, STOP2"
inline std::string panel_button_list(const PanelButtons& buttons) {
  std::string out;
  for (int b = 0; b < buttons.count; ++b) out += (b ? ", " : "") + std::string(buttons.names[b]);
  return out;
}

inline std::string panel_lower(std::string s) {
  for (char& c : s) c = (c >= 'A' && c <= 'Z') ? static_cast<char>(c - 'A' + 'a') : c;
  return s;
}

inline PanelCommand parse_panel_command(const std::string& line,
                                        const PanelButtons& buttons = panel_station_buttons()) {
  PanelCommand c;
  std::istringstream in(line);
  std::string word, arg, extra;
  if (!(in >> word)) return c;
  c.word = panel_lower(word);
  if (c.word != "press" && c.word != "release" && c.word != "click") {
    c.kind = PanelCommand::kOther;
    std::getline(in, c.rest);
    c.rest.erase(0, c.rest.find_first_not_of(' '));
    return c;
  }
  c.kind = PanelCommand::kError;
  c.action = c.word == "press"     ? PanelCommand::kPress
             : c.word == "release" ? PanelCommand::kRelease
                                   : PanelCommand::kClick;
  in >> arg;
  const std::string name = panel_lower(arg);
  for (int b = 0; b < buttons.count; ++b) {
    if (name == panel_lower(buttons.names[b])) c.button = b;
  }
  if (c.button < 0) {
    c.error = "unknown button '" + arg + "' (" + panel_button_list(buttons) + ")";
    return c;
  }
  if (in >> extra) {
    if (c.action != PanelCommand::kClick) {
      c.error = "unexpected '" + extra + "'";
      return c;
    }
    char* end = nullptr;
    const long ms = strtol(extra.c_str(), &end, 10);
    if (*end != '\0' || ms < 1 || ms > 60000) {
      c.error = "bad click duration '" + extra + "' (1..60000 ms)";
      return c;
    }
    c.hold_ms = static_cast<uint32_t>(ms);
    if (in >> extra) {
      c.error = "unexpected '" + extra + "'";
      return c;
    }
  }
  c.kind = PanelCommand::kButton;
  return c;
}

/// The button lines of `help` (each channel adds its own queries).
inline std::string panel_help_lines(const PanelButtons& buttons = panel_station_buttons()) {
  return "help press B | release B | click B [ms]   B: " + panel_button_list(buttons) +
         " (any case); click: 1..60000 ms, default 100";
}

}  // namespace mb2co
