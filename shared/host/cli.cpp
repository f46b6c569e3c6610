#include "host/cli.h"

#include <utility>

#include "host/cli_messages.h"

namespace mb2co {
namespace cli {
namespace {

bool has_commands(const Program& p) {
  return !(p.commands.size() == 1 && p.commands[0].name.empty());
}

const Command* find_command(const Program& p, const std::string& name) {
  for (const Command& c : p.commands) {
    if (c.name == name) return &c;
  }
  return nullptr;
}

const Option* find_in(const std::vector<Option>& options, const std::string& name) {
  for (const Option& o : options) {
    if (o.name == name ||
        (o.short_name != 0 && name.size() == 2 && name[0] == '-' && name[1] == o.short_name)) {
      return &o;
    }
  }
  return nullptr;
}

/// The command's own option, else a global one.
const Option* find_option(const Program& p, const Command& c, const std::string& name) {
  const Option* o = find_in(c.options, name);
  return o != nullptr ? o : find_in(p.global_options, name);
}

/// The option word `a` without an "=value" part.
std::string option_name(const std::string& a) {
  const size_t eq = a.find('=');
  return a[1] == '-' && eq != std::string::npos ? a.substr(0, eq) : a;
}

std::string command_names(const Program& p) {
  std::string s;
  for (size_t i = 0; i < p.commands.size(); ++i) {
    if (i > 0) s += i + 1 == p.commands.size() ? " or " : ", ";
    s += p.commands[i].name;
  }
  return s;
}

/// "--name", "-x"; not "-" alone nor a negative number ("-5" is a value,
/// as "-12" already is: no program has a digit as a short option).
bool is_option_word(const std::string& a) {
  return (a.size() > 2 && a[0] == '-' && a[1] == '-') ||
         (a.size() == 2 && a[0] == '-' && a[1] != '-' && (a[1] < '0' || a[1] > '9'));
}

Parsed usage_error(std::string why) {
  Parsed p;
  p.action = Action::kUsageError;
  p.text = std::move(why);
  return p;
}

std::string try_help(const Program& p, const Command* c) {
  return cli::try_help(p.name, c != nullptr ? c->name : "");
}

/// The long names a command takes (its own, then the global ones): what a
/// near miss is compared with.
std::vector<std::string> option_names(const Program& p, const Command& c) {
  std::vector<std::string> names;
  for (const std::vector<Option>* list : {&c.options, &p.global_options}) {
    for (const Option& o : *list) {
      if (o.kind != Kind::kRefused) names.push_back(o.name);
    }
  }
  names.insert(names.end(), {"--help", "--version"});
  return names;
}

std::vector<std::string> command_list(const Program& p) {
  std::vector<std::string> names;
  for (const Command& c : p.commands) names.push_back(c.name);
  return names;
}

// The option words given before "--", to find --help and the like wherever they stand.
bool asked(int argc, const char* const* argv, int from, const char* a, const char* b) {
  for (int i = from; i < argc; ++i) {
    const std::string w = argv[i];
    if (w == "--") return false;
    if (w == a || (b != nullptr && w == b)) return true;
  }
  return false;
}

Option make(std::string name, Kind kind, std::string value_name, std::string help) {
  Option o;
  o.name = std::move(name);
  o.kind = kind;
  o.value_name = std::move(value_name);
  o.help = std::move(help);
  return o;
}

std::string option_label(const Option& o) {
  std::string s = o.short_name != 0 ? std::string("-") + o.short_name + ", " : "";
  s += o.name;
  if (o.takes_value()) s += " " + o.value_name;
  return s;
}

void append_option_line(std::string& out, const std::string& label, const std::string& help) {
  constexpr size_t kColumn = 28;
  std::string line = "  " + label;
  // A label too long for the column gets its help on the next line.
  line +=
      line.size() + 2 <= kColumn ? std::string(kColumn - line.size(), ' ') : "\n" + std::string(kColumn, ' ');
  for (const char ch : help) {
    line += ch;
    if (ch == '\n') line += std::string(kColumn, ' ');
  }
  out += line + "\n";
}

}  // namespace

const char* version() {
  return MB2CO_VERSION;
}

Option Option::with_short(char c) const {
  Option o = *this;
  o.short_name = c;
  return o;
}

Option flag(std::string name, std::string help) {
  return make(std::move(name), Kind::kFlag, "", std::move(help));
}
Option text(std::string name, std::string value_name, std::string help) {
  return make(std::move(name), Kind::kText, std::move(value_name), std::move(help));
}
Option file(std::string name, std::string value_name, std::string help) {
  return make(std::move(name), Kind::kFile, std::move(value_name), std::move(help));
}
Option dir(std::string name, std::string value_name, std::string help) {
  return make(std::move(name), Kind::kDir, std::move(value_name), std::move(help));
}
Option choice(std::string name, std::vector<std::string> choices, std::string help) {
  std::string value_name;
  for (const std::string& c : choices) value_name += (value_name.empty() ? "" : "|") + c;
  Option o = make(std::move(name), Kind::kChoice, value_name, std::move(help));
  o.choices = std::move(choices);
  return o;
}
Option uint_range(std::string name, std::string value_name, uint64_t min, uint64_t max, std::string help) {
  Option o = make(std::move(name), Kind::kUint, std::move(value_name), std::move(help));
  o.min = min;
  o.max = max;
  return o;
}
Option bitrate(std::string name, uint32_t min_bps, uint32_t max_bps, std::string help) {
  Option o = make(std::move(name), Kind::kBitrate, "B", std::move(help));
  o.min = min_bps;
  o.max = max_bps;
  return o;
}
Option bitrate_of(std::string name, std::vector<uint32_t> allowed_bps, std::string help) {
  Option o = make(std::move(name), Kind::kBitrate, "B", std::move(help));
  o.bitrates = std::move(allowed_bps);
  return o;
}
Option bitrate_list(std::string name, std::vector<uint32_t> allowed_bps, std::string help) {
  Option o = make(std::move(name), Kind::kBitrates, "LIST", std::move(help));
  o.bitrates = std::move(allowed_bps);
  return o;
}
Option parity(std::string name, std::string help) {
  return make(std::move(name), Kind::kParity, "N|E|O", std::move(help));
}
Option duration(std::string name, uint64_t min_ms, uint64_t max_ms, std::string help) {
  Option o = make(std::move(name), Kind::kDuration, "T", std::move(help));
  o.min = min_ms;
  o.max = max_ms;
  return o;
}
Option refused(std::string name, std::string why) {
  return make(std::move(name), Kind::kRefused, "", std::move(why));
}

Status check_value(const Option& o, const std::string& v) {
  uint64_t n = 0;
  uint32_t bps = 0;
  std::vector<uint32_t> list;
  Parity par = Parity::kNone;
  switch (o.kind) {
    case Kind::kFlag:
    case Kind::kRefused:
      return Status::ok();
    case Kind::kText:
    case Kind::kFile:
    case Kind::kDir:
      return v.empty() ? Status::failure(o.name + " needs a value") : Status::ok();
    case Kind::kChoice:
      for (const std::string& c : o.choices) {
        if (c == v) return Status::ok();
      }
      return Status::failure(o.name + " must be " + o.value_name + ", got \"" + v + "\"");
    case Kind::kUint:
      return parse_uint(o.name, v, o.min, o.max, &n);
    case Kind::kBitrate:
      if (!o.bitrates.empty()) return parse_bitrate_in(o.name, v, o.bitrates, &bps);
      return parse_bitrate(o.name, v, static_cast<uint32_t>(o.min),
                           static_cast<uint32_t>(o.max > UINT32_MAX ? UINT32_MAX : o.max), &bps);
    case Kind::kBitrates:
      return parse_bitrate_list(o.name, v, o.bitrates, &list);
    case Kind::kParity:
      return parse_parity(o.name, v, &par);
    case Kind::kDuration:
      return parse_duration_ms(o.name, v, o.min, o.max, &n);
  }
  return Status::ok();
}

std::string Args::get(const std::string& name, const std::string& fallback) const {
  const auto it = values_.find(name);
  return it == values_.end() ? fallback : it->second;
}

uint64_t Args::uint(const std::string& name, uint64_t fallback) const {
  uint64_t v = fallback;
  if (has(name)) (void)parse_uint(name, get(name), 0, UINT64_MAX, &v);
  return v;
}

uint32_t Args::bitrate_bps(const std::string& name, uint32_t fallback) const {
  uint32_t v = fallback;
  if (has(name)) (void)parse_bitrate(name, get(name), 0, UINT32_MAX, &v);
  return v;
}

std::vector<uint32_t> Args::bitrates_bps(const std::string& name, std::vector<uint32_t> fallback) const {
  if (!has(name)) return fallback;
  const std::string& text = get(name);
  std::vector<uint32_t> list;
  size_t start = 0;
  for (;;) {
    const size_t comma = text.find(',', start);
    uint32_t v = 0;
    (void)parse_bitrate(name, text.substr(start, comma == std::string::npos ? comma : comma - start), 0,
                        UINT32_MAX, &v);
    list.push_back(v);
    if (comma == std::string::npos) return list;
    start = comma + 1;
  }
}

Parity Args::parity(const std::string& name, Parity fallback) const {
  Parity v = fallback;
  if (has(name)) (void)parse_parity(name, get(name), &v);
  return v;
}

uint64_t Args::duration_ms(const std::string& name, uint64_t fallback) const {
  uint64_t v = fallback;
  if (has(name)) (void)parse_duration_ms(name, get(name), 0, UINT64_MAX, &v);
  return v;
}

Parsed parse(const Program& program, int argc, const char* const* argv) {
  Parsed r;
  // Global options may stand before the command's name: skip them (they are
  // parsed with the command's own below).
  // A value that is wrong for its option is that option's error, found
  // here: `-t read 1 1000 0` would else end as "unknown command 1".
  int name_at = 1;
  std::string global_error;
  while (name_at < argc && is_option_word(argv[name_at])) {
    const Option* g = find_in(program.global_options, option_name(argv[name_at]));
    if (g == nullptr) break;
    const bool inline_value = std::string(argv[name_at]).find('=') != std::string::npos;
    if (g->takes_value() && !inline_value && global_error.empty()) {
      if (name_at + 1 >= argc || is_option_word(argv[name_at + 1])) {
        global_error = g->name + " needs a value";
      } else {
        const Status s = check_value(*g, argv[name_at + 1]);
        if (!s) global_error = s.message();
      }
    }
    name_at += g->takes_value() && !inline_value ? 2 : 1;
  }
  const Command* command = has_commands(program) ? nullptr : &program.commands[0];
  if (command == nullptr && name_at < argc) command = find_command(program, argv[name_at]);
  if (asked(argc, argv, 1, "--help", "-h")) {
    r.action = Action::kHelp;
    r.text = help_text(program, command);
    return r;
  }
  if (asked(argc, argv, 1, "--version", nullptr)) {
    r.action = Action::kVersion;
    r.text = program.name + " " + version() + "\n";
    return r;
  }
  if (asked(argc, argv, 1, "--list-options", nullptr)) {
    r.action = Action::kListOptions;
    r.text = list_options(program, command);
    return r;
  }
  if (!global_error.empty()) return usage_error(global_error);
  if (command == nullptr) {
    if (name_at >= argc) {
      return usage_error("missing command (" + command_names(program) + ") " + try_help(program, nullptr));
    }
    if (is_option_word(argv[name_at])) {
      Command globals;
      return usage_error(
          unknown_option(program.name, "", option_name(argv[name_at]), option_names(program, globals)));
    }
    const std::string near = nearest_word(argv[name_at], command_list(program));
    return usage_error("unknown command \"" + std::string(argv[name_at]) + "\" (" +
                       (near.empty() ? command_names(program) : "did you mean " + near + "?") + ") " +
                       try_help(program, nullptr));
  }
  r.args.command = command;
  std::map<std::string, bool> seen;
  for (int i = 1; i < argc; ++i) {
    if (has_commands(program) && i == name_at) continue;
    std::string a = argv[i];
    if (a == "--") {
      for (++i; i < argc; ++i) r.args.operands.push_back(argv[i]);
      break;
    }
    if (!is_option_word(a)) {
      r.args.operands.push_back(a);
      continue;
    }
    std::string value;
    bool inline_value = false;
    const size_t eq = a.find('=');
    if (a[1] == '-' && eq != std::string::npos) {
      value = a.substr(eq + 1);
      a.resize(eq);
      inline_value = true;
    }
    const Option* o = find_option(program, *command, a);
    if (o == nullptr) {
      for (const Command& other : program.commands) {
        if (find_in(other.options, a) != nullptr) {
          return usage_error(a + " is not an option of " + command->name + " " + try_help(program, command));
        }
      }
      return usage_error(unknown_option(program.name, command->name, a, option_names(program, *command)));
    }
    if (o->kind == Kind::kRefused) return usage_error(o->name + " " + o->help);
    if (!o->takes_value() && inline_value) return usage_error(o->name + " takes no value");
    if (o->takes_value() && !inline_value) {
      if (i + 1 >= argc || is_option_word(argv[i + 1]) || std::string(argv[i + 1]) == "--") {
        return usage_error(o->name + " needs a value");
      }
      value = argv[++i];
    }
    if (o->takes_value() && value.empty()) return usage_error(o->name + " needs a value");
    if (seen[o->name]) return usage_error(o->name + " given twice");
    seen[o->name] = true;
    const Status s = check_value(*o, value);
    if (!s) return usage_error(s.message());
    r.args.set(o->name, value);
  }
  if (r.args.operands.size() < command->min_operands) {
    return usage_error(missing_operand(program.name, command->name, command->operands));
  }
  if (r.args.operands.size() > command->max_operands) {
    return usage_error("unexpected argument \"" + r.args.operands[command->max_operands] + "\" " +
                       try_help(program, command));
  }
  return r;
}

int finish_early(const Program& program, const Parsed& parsed, std::ostream& out, std::ostream& err) {
  switch (parsed.action) {
    case Action::kRun:
      return -1;
    case Action::kHelp:
    case Action::kVersion:
    case Action::kListOptions:
      out << parsed.text;
      return kExitDone;
    case Action::kUsageError:
      err << program.name << ": " << parsed.text << '\n';
      return kExitUsage;
  }
  return kExitUsage;
}

std::string help_text(const Program& p, const Command* c) {
  std::string s = "usage: " + p.name;
  if (c == nullptr && has_commands(p)) {
    s += " COMMAND [options]\n" + p.description + "\ncommands:\n";
    for (const Command& cmd : p.commands) append_option_line(s, cmd.name, cmd.summary);
    s += "\n\"" + p.name + " COMMAND --help\" lists the options of COMMAND.\n";
    for (const Option& o : p.global_options) append_option_line(s, option_label(o), o.help);
    append_option_line(s, "-h, --help", "this text");
    append_option_line(s, "--version", std::string("print \"") + p.name + " " + version() + "\"");
    return s + p.footer;
  }
  if (!c->name.empty()) s += " " + c->name;
  s += " [options]";
  if (!c->operands.empty()) s += " " + c->operands;
  s += "\n" + (c->name.empty() ? p.description : c->summary + "\n") + "\noptions:\n";
  for (const std::vector<Option>* list : {&c->options, &p.global_options}) {
    for (const Option& o : *list) {
      if (o.kind != Kind::kRefused) append_option_line(s, option_label(o), o.help);
    }
  }
  append_option_line(s, "-h, --help", "this text");
  append_option_line(s, "--version", std::string("print \"") + p.name + " " + version() + "\"");
  return s + p.footer;
}

std::string list_options(const Program& p, const Command* c) {
  std::string s;
  if (c == nullptr) {
    for (const Command& cmd : p.commands) s += cmd.name + "\n";
  }
  std::vector<Option> options = p.global_options;
  if (c != nullptr) options.insert(options.begin(), c->options.begin(), c->options.end());
  for (const Option& o : options) {
    if (o.kind == Kind::kRefused) continue;
    s += o.name;
    switch (o.kind) {
      case Kind::kFlag:
        s += " flag";
        break;
      case Kind::kFile:
        s += " file";
        break;
      case Kind::kDir:
        s += " dir";
        break;
      case Kind::kChoice:
        s += " choice";
        for (const std::string& w : o.choices) s += " " + w;
        break;
      case Kind::kParity:
        s += " choice N E O none even odd";
        break;
      case Kind::kBitrate:
      case Kind::kBitrates:
        s += o.bitrates.empty() ? " value 125k 250k 500k 1M" : " choice";
        for (const uint32_t b : o.bitrates) s += " " + bitrate_text(b);
        break;
      default:
        s += " value";
        break;
    }
    s += "\n";
  }
  return s + "--help flag\n--version flag\n";
}

}  // namespace cli
}  // namespace mb2co
