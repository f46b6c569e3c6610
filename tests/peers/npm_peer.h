// What the tests against npm's canopen share: the peer (tests/peers/
// canopen_peer.js under Node.js) as a child process, its one-line results,
// the data pattern its server holds, and default values from an EDS file.
#pragma once
#include <stddef.h>
#include <stdint.h>

#include <chrono>
#include <string>
#include <vector>

#include "line_child.h"

namespace mb2co {
namespace test {

using namespace std::chrono_literals;

/// Bounds a failure only: user-mode Linux on a shared host is slow
/// (a 64 KiB segmented transfer takes ~17 s there).
constexpr auto kPeerDeadline = 120s;

/// `node canopen_peer.js --can vcan0` followed by `args`.
std::vector<std::string> peer_command(const std::vector<std::string>& args);

/// The outcome of one `canopen_peer.js client ...` run.
struct PeerResult {
  int exit_code = -1;  ///< 0 ok, 1 SDO abort, 2 usage, 3 other failure, -1 hung
  std::string line;    ///< its "ok ..." or "abort ..." line ("" when none)
  std::string stderr_text;
  /// Field `name=value` of the result line ("" when absent).
  std::string field(const std::string& name) const;
  /// The abort code (code=XXXXXXXX), 0 when the transfer succeeded.
  uint32_t abort_code() const;
  /// The uploaded bytes of data=HEX.
  std::vector<uint8_t> data() const;
  /// Everything, for failure messages.
  std::string describe() const;
};

/// Runs one client transfer to its end.
PeerResult run_peer_client(const std::vector<std::string>& args);

/// The peer's pattern: byte i is (7 * i + (i >> 8)) mod 256.
std::vector<uint8_t> peer_pattern(size_t size);
/// Another content of `size` bytes, unlike the pattern (an LCG stream from
/// `seed`): what a download writes, so that a read-back proves the write.
std::vector<uint8_t> other_content(size_t size, uint32_t seed);

std::string to_hex(const std::vector<uint8_t>& bytes);
bool write_file(const std::string& path, const std::vector<uint8_t>& bytes);
std::vector<uint8_t> read_file(const std::string& path);

/// DefaultValue of [index] or [indexsubS] of an EDS file ("" when absent).
std::string eds_default(const std::string& eds_path, uint16_t index, uint8_t sub);

}  // namespace test
}  // namespace mb2co
