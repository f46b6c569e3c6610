// Seed 000 §5.1 on the real image: the gateway's AVR image (mb2co-gateway.elf)
// runs in simavr on hil/uno's rig (UnoRig: ATmega328P at 16 MHz, the
// MCP2515 model on its SPI bus). As a student would, the run configures
// TPDO2 as synchronous by SDO (1801h/2 = 1, disabled around the change),
// starts the node, then injects SYNCs at random phases of the main loop and
// counts the CPU cycles from the SYNC's reception into the MCP2515 (end of
// its last bit) to the end of the SPI instruction after which the response
// PDO is in a transmit buffer (TXREQ set): "the time your code takes to
// determine that you received a synch message, and the time it takes to
// build (but not send) the response PDO frame".
#pragma once
#include <stdint.h>

#include <string>
#include <vector>

namespace mb2co {
namespace lab {

struct SyncProcessingResult {
  std::string elf;
  std::string error;  ///< why the run stopped early ("" when it did not)
  uint8_t node_id = 0;
  std::vector<uint64_t> cycles;  ///< per SYNC: reception → PDO in a TX buffer
  uint64_t min_cycles = 0, max_cycles = 0;
  double mean_cycles = 0;
  /// The bound: the simulator's sync_pass worst case for the uno profile
  /// (sim::uno_timing(), the pass times measure-pass-time.sh measured on
  /// this firmware): a pass in progress + the pass that hands the SYNC in.
  uint64_t bound_us = 0;
  uint64_t pass_max_us = 0;  ///< the model's longest pass with the frames it may hand in
  uint32_t wanted = 0;
  bool ok = false;  ///< every SYNC answered and every count within the bound
};

/// Runs `syncs` SYNCs through the image at `elf_path`; `seed` picks the
/// random waits between them (3..8 ms).
SyncProcessingResult sync_processing_run(const std::string& elf_path, uint32_t syncs, uint64_t seed);

/// The report section (cycles and µs at 16 MHz, min/mean/max, the bound, verdict).
std::string sync_processing_section(const SyncProcessingResult& r);
/// Histogram of the counts in µs (16 cycles each), the bound drawn.
std::string sync_processing_svg(const SyncProcessingResult& r);

}  // namespace lab
}  // namespace mb2co
