#include "number_words.h"

#include <ctype.h>
#include <errno.h>
#include <stdlib.h>

#include <algorithm>

namespace mb2co {
namespace master {

Status parse_number(const std::string& text, uint64_t max, const char* what, uint64_t* value) {
  std::string t = text;
  int base = 10;
  if (t.size() > 2 && t[0] == '0' && (t[1] == 'x' || t[1] == 'X')) {
    t = t.substr(2);
    base = 16;
  } else if (t.size() > 1 && (t.back() == 'h' || t.back() == 'H')) {
    t.pop_back();
    base = 16;
  }
  const bool digits = !t.empty() && std::all_of(t.begin(), t.end(), [base](char c) {
    return base == 16 ? isxdigit(static_cast<unsigned char>(c)) != 0 : (c >= '0' && c <= '9');
  });
  errno = 0;
  const unsigned long long v = digits && t.size() <= 20 ? strtoull(t.c_str(), nullptr, base) : 0;
  if (!digits || t.size() > 20 || errno != 0 || v > max) {
    return Status::failure(std::string(what) + " must be 0.." + std::to_string(max) +
                           " (decimal, 0x.. or ..h), got \"" + text + "\"");
  }
  *value = v;
  return Status::ok();
}

Status parse_node_id(const std::string& text, bool allow_all, uint8_t* node_id) {
  if (allow_all && (text == "all" || text == "0")) {
    *node_id = 0;
    return Status::ok();
  }
  uint64_t v = 0;
  if (!parse_number(text, 127, "node id", &v) || v == 0) {
    return Status::failure(std::string("node id must be 1..127") + (allow_all ? " or all" : "") + ", got \"" +
                           text + "\"");
  }
  *node_id = static_cast<uint8_t>(v);
  return Status::ok();
}

Status parse_node_list(const std::string& text, std::vector<uint8_t>* nodes) {
  size_t start = 0;
  while (start <= text.size()) {
    const size_t comma = text.find(',', start);
    const std::string part =
        text.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    const size_t dash = part.find('-');
    uint8_t a = 0, b = 0;
    Status s = parse_node_id(part.substr(0, dash), false, &a);
    if (s && dash != std::string::npos) s = parse_node_id(part.substr(dash + 1), false, &b);
    if (!s) return s;
    if (dash == std::string::npos) b = a;
    if (b < a) return Status::failure("a node range must run upwards (5-7), got \"" + part + "\"");
    for (int id = a; id <= b; ++id) nodes->push_back(static_cast<uint8_t>(id));
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  return Status::ok();
}

Status parse_index_sub(const std::string& index, const std::string& sub, uint16_t* i, uint8_t* s) {
  // An index is hexadecimal in every CANopen text (1018h): "1018", "0x1018"
  // and "1018h" are the same object.
  uint64_t v = 0;
  const bool marked = index.rfind("0x", 0) == 0 || index.rfind("0X", 0) == 0 ||
                      (!index.empty() && (index.back() == 'h' || index.back() == 'H'));
  Status st = parse_number(marked ? index : "0x" + index, 0xFFFF, "index", &v);
  if (!st) return Status::failure("index must be hexadecimal 0000..FFFF, got \"" + index + "\"");
  *i = static_cast<uint16_t>(v);
  st = parse_number(sub, 0xFF, "sub-index", &v);
  if (!st) return st;
  *s = static_cast<uint8_t>(v);
  return Status::ok();
}

}  // namespace master
}  // namespace mb2co
