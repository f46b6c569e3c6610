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
  RegTable table = RegTable::none;
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

}  // namespace pcapp
}  // namespace mb2co
