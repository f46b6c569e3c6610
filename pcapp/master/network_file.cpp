#include "network_file.h"

#include <fstream>
#include <map>
#include <sstream>

#include "eds_value.h"

namespace mb2co {
namespace master {

namespace {

std::string trim(const std::string& s) {
  const size_t a = s.find_first_not_of(" \t\r");
  if (a == std::string::npos) return "";
  const size_t b = s.find_last_not_of(" \t\r");
  return s.substr(a, b - a + 1);
}

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(tolower(static_cast<unsigned char>(c)));
  return s;
}

/// What the [Topology] lines of one node id said, with their line numbers.
struct NodeLines {
  int present_line = 0;
  bool present = false;
  std::string name;
  std::string dcf;
  int dcf_line = 0;
};

}  // namespace

Status parse_network(const std::string& text, const std::string& filename, NetworkFile* out) {
  const auto error = [&](int line, const std::string& what) {
    return Status::failure(filename + ":" + std::to_string(line) + ": " + what);
  };
  const size_t slash = filename.rfind('/');
  const std::string folder = slash == std::string::npos ? "" : filename.substr(0, slash + 1);
  std::istringstream in(text);
  std::string raw;
  int line = 0;
  std::string section;
  bool topology = false;
  int nodes_line = 0;
  uint64_t nodes_count = 0;
  std::map<uint8_t, NodeLines> nodes;
  while (std::getline(in, raw)) {
    ++line;
    const std::string l = trim(raw);
    if (l.empty() || l[0] == ';') continue;
    if (l[0] == '[') {
      if (l.back() != ']' || l.size() < 3) return error(line, "bad section header '" + l + "'");
      section = lower(trim(l.substr(1, l.size() - 2)));
      if (section == "topology") {
        if (topology) return error(line, "second [Topology] section");
        topology = true;
      }
      continue;
    }
    const size_t eq = l.find('=');
    if (eq == std::string::npos || eq == 0) return error(line, "want KEY=VALUE, not '" + l + "'");
    if (section.empty()) return error(line, "key outside any section");
    if (section != "topology") continue;
    const std::string key = lower(trim(l.substr(0, eq)));
    const std::string value = trim(l.substr(eq + 1));
    if (key == "nodes") {
      const auto n = eds::parse_unsigned(value, 127);
      if (!n) return error(line, "Nodes='" + value + "' is not a count 0..127");
      nodes_count = *n;
      nodes_line = line;
      continue;
    }
    if (key.compare(0, 4, "node") != 0) continue;  // NetName, ...
    size_t digits = 4;
    while (digits < key.size() && isdigit(static_cast<unsigned char>(key[digits]))) ++digits;
    const std::string what = key.substr(digits);
    if (digits == 4 || (what != "present" && what != "name" && what != "dcfname")) continue;
    const auto id = eds::parse_unsigned(key.substr(4, digits - 4), 127);
    if (!id || *id == 0) return error(line, "node id in '" + trim(l.substr(0, eq)) + "' is not 1..127");
    NodeLines& n = nodes[static_cast<uint8_t>(*id)];
    if (what == "present") {
      const auto p = eds::parse_unsigned(value, 1);
      if (!p) return error(line, "NodeXPresent='" + value + "' is not 0 or 1");
      n.present = *p == 1;
      n.present_line = line;
    } else if (what == "name") {
      n.name = value;
    } else {
      if (value.empty()) return error(line, "empty DCF name");
      n.dcf = value;
      n.dcf_line = line;
    }
  }
  if (!topology) return error(line, "no [Topology] section");
  if (nodes_line == 0) return error(line, "[Topology] has no Nodes= count");
  out->nodes.clear();
  for (const auto& p : nodes) {
    const NodeLines& n = p.second;
    if (!n.present) continue;
    if (n.dcf.empty())
      return error(n.present_line, "node " + std::to_string(p.first) + " is present but has no Node" +
                                       std::to_string(p.first) + "DCFName");
    NetworkNode node;
    node.id = p.first;
    node.name = n.name;
    node.dcf_path = n.dcf[0] == '/' ? n.dcf : folder + n.dcf;
    out->nodes.push_back(node);
  }
  if (out->nodes.size() != nodes_count)
    return error(nodes_line, "Nodes=" + std::to_string(nodes_count) + " but " +
                                 std::to_string(out->nodes.size()) + " nodes are present");
  return Status::ok();
}

Status read_network_file(const std::string& path, NetworkFile* out) {
  std::ifstream f(path, std::ios::binary);
  if (!f) return Status::failure(path + ": cannot read");
  std::ostringstream text;
  text << f.rdbuf();
  return parse_network(text.str(), path, out);
}

}  // namespace master
}  // namespace mb2co
