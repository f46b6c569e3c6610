// Which Modbus requests one control cycle makes. One FC 17h (write the
// outputs, then read the inputs, in one transaction) when the holding-register
// map holds every field the cycle reads and writes in one block each;
// otherwise reads (FC 04 input registers / FC 03 holding registers) and
// writes (FC 06 one register / FC 10h a block). The gateway's default map
// keeps the panel's inputs in the input registers, so it gets FC 04 + FC 06.
#pragma once
#include <stdint.h>

#include <string>
#include <vector>

#include "host/status.h"
#include "register_layout.h"
#include "timing/rtu_timing.h"

namespace mb2co {
namespace pcapp {

struct Block {
  RegTable table = RegTable::kNone;
  uint16_t start = 0;
  uint16_t count = 0;
};

/// Invariant: with read_write, reads and writes hold exactly one block each
/// (both holding). Read blocks only cover mapped addresses; write blocks only
/// the fields to write (never a register we do not own).
struct TransactionPlan {
  bool read_write = false;
  std::vector<Block> reads;
  std::vector<Block> writes;
  uint16_t read_registers[2] = {0, 0};  ///< image size per table (holding, input)
};

/// Plans the cycle's requests. `required` fields must be mapped (else it
/// fails); `optional` ones are read when mapped. Every field in `writes` must
/// be a writable holding register.
Status plan_transactions(const RegisterLayout& layout, const std::vector<Field>& required,
                         const std::vector<Field>& optional, const std::vector<Field>& writes,
                         TransactionPlan& plan);

/// "FC 04 IR 0-22 + FC 06 HR 0": the plan in one line.
std::string describe(const TransactionPlan& plan);

/// Request and response bytes of every transaction of one cycle, summed
/// time on the wire at `format` with the slave's t3.5 after each request and
/// no turnaround (the lower bound a measured cycle is compared with).
uint64_t plan_wire_time_ns(const TransactionPlan& plan, const timing::SerialFormat& format);
/// The same without the slave's t3.5: the frame times alone.
uint64_t plan_frame_time_ns(const TransactionPlan& plan, const timing::SerialFormat& format);
/// Transactions per cycle.
size_t transaction_count(const TransactionPlan& plan);

/// The Uno gateway's reply time the response timeout allows for, from the
/// end of a request's t3.5 to the first byte of its answer: its slowest
/// answer (FC 04 of the whole map, 2,012 µs), one loop pass to notice the
/// silence (≤ 428 µs) and a CAN frame handed in in that pass (≤ 736 µs),
/// 3,176 µs measured cycle-exactly (docs/performance.md, "Gateway on the
/// Uno"), rounded up.
constexpr uint64_t kGatewayReplyNs = 4000000;
/// What a loaded host adds: the app, a USB adapter's latency timer or the
/// simulated Uno not scheduled for a while (the old fixed 25 ms timeout,
/// which alone retried on a loaded host).
constexpr uint64_t kHostMarginNs = 25000000;
/// FC 2B/0E basic device identification, the link check: request 7 bytes;
/// the answer (vendor, product and version of the gateway, 39 bytes with
/// version 0.1.0) bounded at 48 bytes.
constexpr timing::RtuExchange kIdentificationExchange = {7, 48};

/// The response timeout derived from the line (docs/mb2co-plant.md, "Response
/// timeout"): the longest transaction the app makes (the cycle's and FC 2B/0E)
/// request + answer frames at `format`, + the slave's t3.5 + kGatewayReplyNs
/// + kHostMarginNs, in whole ms rounded up. `format` null: Modbus/TCP, no
/// wire time.
int derived_timeout_ms(const TransactionPlan& plan, const timing::SerialFormat* format);

}  // namespace pcapp
}  // namespace mb2co
