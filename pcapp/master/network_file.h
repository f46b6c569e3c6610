// A network's nodes and their DCFs, in the style of a CiA 306-3 project
// file: [Topology] with Nodes=COUNT and, for each node id X (decimal),
// NodeXPresent=1, NodeXName=TEXT and NodeXDCFName=PATH (relative to the
// network file). What configure reads; other sections and keys are ignored.
#pragma once
#include <stdint.h>

#include <string>
#include <vector>

#include "host/status.h"

namespace mb2co {
namespace master {

struct NetworkNode {
  uint8_t id = 0;        ///< 1..127
  std::string name;      ///< NodeXName (may be empty)
  std::string dcf_path;  ///< NodeXDCFName resolved against the network file's folder
};

struct NetworkFile {
  std::vector<NetworkNode> nodes;  ///< the present nodes, by node id
};

/// Parses the text of a network file; `filename` names it in errors and
/// gives the folder DCF paths are relative to. Errors are "file:line: what"
/// (one line): a line that is no section, key=value or comment, a bad node
/// id or value, a present node without a DCF, a Nodes= count that does not
/// match the present nodes, no [Topology].
Status parse_network(const std::string& text, const std::string& filename, NetworkFile* out);
/// parse_network() of a file's contents ("file: cannot read" when unreadable).
Status read_network_file(const std::string& path, NetworkFile* out);

}  // namespace master
}  // namespace mb2co
