#include "ascii_request.h"

#include <ctype.h>

namespace mb2co {
namespace master {
namespace ascii {

namespace {

/// Anything but printable ASCII separates tokens (CANopenNode: !isgraph).
bool blank(char c) {
  const unsigned char u = static_cast<unsigned char>(c);
  return u <= 0x20 || u >= 0x7F;
}

/// Walks the line token by token; a '#' ends it (a comment).
class Cursor {
 public:
  explicit Cursor(const std::string& line) : s_(line) {}
  /// The next token; false at the end of the line or a comment.
  bool next(std::string* token) {
    if (at_end()) return false;
    const size_t start = i_;
    while (i_ < s_.size() && !blank(s_[i_]) && s_[i_] != '#') ++i_;
    token->assign(s_, start, i_ - start);
    return true;
  }
  /// Only blanks and a comment are left.
  bool at_end() {
    while (i_ < s_.size() && blank(s_[i_])) ++i_;
    return i_ >= s_.size() || s_[i_] == '#';
  }
  /// The next character without taking it ('\0' at the end).
  char peek() const { return i_ < s_.size() ? s_[i_] : '\0'; }
  char take() { return i_ < s_.size() ? s_[i_++] : '\0'; }
  bool done() const { return i_ >= s_.size(); }

 private:
  const std::string& s_;
  size_t i_ = 0;
};

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(tolower(static_cast<unsigned char>(c)));
  return s;
}

/// A visible string: "quoted" ("" inside is one quote) or one word. Then
/// only a comment may follow.
bool scan_visible_string(Cursor& c, std::vector<uint8_t>* out) {
  out->clear();
  if (c.at_end()) return false;
  if (c.peek() == '"') {
    c.take();
    for (;;) {
      if (c.done()) return false;  // no closing quote
      const char ch = c.take();
      if (ch == '"') {
        if (c.peek() != '"') break;
        c.take();
      }
      out->push_back(static_cast<uint8_t>(ch));
    }
    if (!c.done() && !blank(c.peek()) && c.peek() != '#') return false;  // text glued to the quote
  } else {
    // One word: a quote inside must be doubled, as CANopenNode reads it;
    // '#' is part of the word there.
    while (!c.done() && !blank(c.peek())) {
      const char ch = c.take();
      if (ch == '"' && c.take() != '"') return false;
      out->push_back(static_cast<uint8_t>(ch));
    }
  }
  return !out->empty() && c.at_end();
}

/// Hex pairs to the end of the line, blanks between bytes optional; a
/// lone digit before a blank is a byte of its own (as CANopenNode).
bool scan_hex(Cursor& c, std::vector<uint8_t>* out) {
  out->clear();
  int high = -1;
  while (!c.done() && c.peek() != '#') {
    const char ch = c.take();
    if (blank(ch)) {
      if (high >= 0) out->push_back(static_cast<uint8_t>(high));
      high = -1;
      continue;
    }
    if (!isxdigit(static_cast<unsigned char>(ch))) return false;
    const int d = isdigit(static_cast<unsigned char>(ch)) ? ch - '0' : (tolower(ch) - 'a' + 10);
    if (high < 0) {
      high = d;
    } else {
      out->push_back(static_cast<uint8_t>(high << 4 | d));
      high = -1;
    }
  }
  if (high >= 0) out->push_back(static_cast<uint8_t>(high));
  return !out->empty();
}

/// The VALUE of a write, by its type.
bool scan_value(DataType t, Cursor& c, std::vector<uint8_t>* out) {
  std::string token;
  switch (t) {
    case DataType::kVisibleString:
      return scan_visible_string(c, out);
    case DataType::kHex:
      return scan_hex(c, out);
    case DataType::kOctetString:
    case DataType::kUnicodeString:
    case DataType::kDomain:
      return c.next(&token) && decode_base64(token, out) && !out->empty() && c.at_end();
    default:
      return c.next(&token) && parse_fixed_value(t, token, out) && c.at_end();
  }
}

bool parse_seq(const std::string& token, uint32_t* seq) {
  if (token.size() < 3 || token.front() != '[' || token.back() != ']') return false;
  uint64_t v = 0;
  if (!parse_unsigned(token.substr(1, token.size() - 2), 0xFFFFFFFFu, &v)) return false;
  *seq = static_cast<uint32_t>(v);
  return true;
}

Request failed(Request r, GatewayError e) {
  r.kind = Request::Kind::kError;
  r.error = e;
  r.value.clear();
  return r;
}

/// `set ...`: one number and the end of the line.
Request parse_set(Request r, Cursor& c, uint32_t prefix_numbers, const ParseContext& context) {
  std::string what, value;
  if (prefix_numbers > 1) return failed(r, GatewayError::kSyntax);  // [NET] only
  if (!c.next(&what) || !c.next(&value) || !c.at_end()) return failed(r, GatewayError::kSyntax);
  what = lower(what);
  struct Setting {
    const char* word;
    Request::Kind kind;
    uint64_t min, max;
  };
  static const Setting kSettings[] = {
      {"network", Request::Kind::kSetNetwork, 0, 0xFFFF},
      {"node", Request::Kind::kSetNode, 1, 127},
      {"sdo_timeout", Request::Kind::kSetSdoTimeout, 1, 0xFFFF},
      {"sdo_block", Request::Kind::kSetSdoBlock, 0, 1},
      {"events", Request::Kind::kSetEvents, 0, 1},
  };
  for (const Setting& s : kSettings) {
    if (what != s.word) continue;
    uint64_t v = 0;
    if (!parse_unsigned(value, s.max, &v) || v < s.min) return failed(r, GatewayError::kSyntax);
    if (s.kind == Request::Kind::kSetNetwork && v != context.net)
      return failed(r, GatewayError::kUnsupportedNet);
    r.kind = s.kind;
    r.number = static_cast<uint32_t>(v);
    return r;
  }
  return failed(r, GatewayError::kRequestNotSupported);
}

/// The node of a node command: from the line or `set node`; 0 only for NMT.
GatewayError check_node(int32_t node, bool zero_allowed, uint8_t* out) {
  if (node < 0) return GatewayError::kNoDefaultNode;
  if (node > 127 || (node == 0 && !zero_allowed)) return GatewayError::kUnsupportedNode;
  *out = static_cast<uint8_t>(node);
  return GatewayError::kNone;
}

Request parse_sdo(Request r, Cursor& c, bool write, const ParseContext& context) {
  std::string index, sub, type;
  uint64_t i = 0, s = 0;
  if (!c.next(&index) || !parse_unsigned(index, 0xFFFF, &i) || !c.next(&sub) ||
      !parse_unsigned(sub, 0xFF, &s))
    return failed(r, GatewayError::kSyntax);
  r.index = static_cast<uint16_t>(i);
  r.sub = static_cast<uint8_t>(s);
  r.type = DataType::kHex;
  if (c.next(&type)) {
    if (!type_of_word(lower(type), &r.type)) return failed(r, GatewayError::kSyntax);
  } else if (write) {
    return failed(r, GatewayError::kSyntax);
  }
  if (!write) {
    if (!c.at_end()) return failed(r, GatewayError::kSyntax);
    r.kind = Request::Kind::kRead;
    return r;
  }
  if (!scan_value(r.type, c, &r.value)) return failed(r, GatewayError::kSyntax);
  if (r.value.size() > context.max_value_bytes) return failed(r, GatewayError::kOutOfMemory);
  r.kind = Request::Kind::kWrite;
  return r;
}

Request parse_nmt(Request r, Cursor& c, const std::string& verb) {
  struct Command {
    const char* word;
    uint8_t command;  // CiA 301's command byte
  };
  static const Command kCommands[] = {
      {"start", 0x01}, {"stop", 0x02}, {"preop", 0x80}, {"preoperational", 0x80}};
  for (const Command& k : kCommands) {
    if (verb != k.word) continue;
    if (!c.at_end()) return failed(r, GatewayError::kSyntax);
    r.kind = Request::Kind::kNmt;
    r.nmt = k.command;
    return r;
  }
  // reset node | reset comm[unication]
  std::string what;
  if (!c.next(&what) || !c.at_end()) return failed(r, GatewayError::kSyntax);
  what = lower(what);
  if (what == "node")
    r.nmt = 0x81;
  else if (what == "comm" || what == "communication")
    r.nmt = 0x82;
  else
    return failed(r, GatewayError::kSyntax);
  r.kind = Request::Kind::kNmt;
  return r;
}

}  // namespace

uint32_t leading_seq(const std::string& text, uint32_t fallback) {
  Cursor c(text);
  std::string token;
  uint32_t seq = fallback;
  if (c.next(&token) && parse_seq(token, &seq)) return seq;
  return fallback;
}

Request parse_request(const std::string& line, const ParseContext& context) {
  Request r;
  r.seq = context.last_seq;
  Cursor c(line);
  std::string token;
  if (!c.next(&token)) return r;  // blank or comment only
  if (!parse_seq(token, &r.seq)) return failed(r, GatewayError::kSyntax);
  r.seq_given = true;

  // [[NET] NODE]: numbers (or `all`) before the command word.
  uint64_t numbers[2] = {0, 0};
  uint32_t count = 0;
  for (;;) {
    if (!c.next(&token)) return failed(r, GatewayError::kSyntax);
    const bool all = lower(token) == "all";
    if (!all && !isdigit(static_cast<unsigned char>(token[0]))) break;
    if (count == 2) return failed(r, GatewayError::kSyntax);
    if (!all && !parse_unsigned(token, 0xFFFFFFFFu, &numbers[count])) return failed(r, GatewayError::kSyntax);
    ++count;
  }
  const std::string verb = lower(token);
  if (verb == "set") return parse_set(r, c, count, context);
  if (verb == "help" || verb == "info" || verb == "log") {
    std::string what;
    if (verb == "help" && c.next(&what)) {
      if (lower(what) != "datatype") return failed(r, GatewayError::kRequestNotSupported);
      r.kind = Request::Kind::kHelpDatatype;
    } else {
      r.kind = verb == "help"   ? Request::Kind::kHelp
               : verb == "info" ? Request::Kind::kInfo
                                : Request::Kind::kLog;
    }
    return c.at_end() ? r : failed(r, GatewayError::kSyntax);
  }

  const bool sdo = verb == "r" || verb == "read" || verb == "w" || verb == "write";
  const bool nmt =
      verb == "start" || verb == "stop" || verb == "preop" || verb == "preoperational" || verb == "reset";
  if (!sdo && !nmt) return failed(r, GatewayError::kRequestNotSupported);

  int64_t node = context.default_node;
  int64_t net = context.net;
  if (count == 1) node = static_cast<int64_t>(numbers[0]);
  if (count == 2) {
    net = static_cast<int64_t>(numbers[0]);
    node = static_cast<int64_t>(numbers[1]);
  }
  const GatewayError e = check_node(node > 127 ? 128 : static_cast<int32_t>(node), nmt, &r.node);
  if (e != GatewayError::kNone) return failed(r, e);
  if (net != context.net) return failed(r, GatewayError::kUnsupportedNet);
  if (nmt) return parse_nmt(r, c, verb);
  return parse_sdo(r, c, verb[0] == 'w', context);
}

}  // namespace ascii
}  // namespace master
}  // namespace mb2co
