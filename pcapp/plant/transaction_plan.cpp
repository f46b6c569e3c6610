#include "transaction_plan.h"

#include <algorithm>
#include <cstdio>

namespace mb2co {
namespace pcapp {

namespace {
constexpr uint16_t kMaxReadRegisters = 125;       // FC 03/04/17h read quantity
constexpr uint16_t kMaxReadWriteRegisters = 121;  // FC 17h write quantity

int table_slot(RegTable t) {
  return t == RegTable::kHolding ? 0 : 1;
}

bool mapped_between(const RegisterLayout& layout, RegTable table, uint16_t from, uint16_t to) {
  const std::vector<bool>& m = layout.mapped[table_slot(table)];
  for (uint16_t a = from; a < to; ++a) {
    if (a >= m.size() || !m[a]) return false;
  }
  return true;
}

/// Blocks of one table covering `locations` (sorted by address); gaps are
/// bridged when `bridge` and every address in the gap is mapped.
std::vector<Block> blocks_of(const RegisterLayout& layout, std::vector<Location> locations, bool bridge) {
  std::sort(locations.begin(), locations.end(),
            [](const Location& a, const Location& b) { return a.address < b.address; });
  std::vector<Block> out;
  for (const Location& l : locations) {
    if (!out.empty()) {
      Block& b = out.back();
      const uint16_t end = static_cast<uint16_t>(b.start + b.count);
      const uint16_t new_end = std::max<uint16_t>(end, static_cast<uint16_t>(l.address + l.width));
      const bool joins = l.address <= end || (bridge && mapped_between(layout, l.table, end, l.address));
      if (joins && new_end - b.start <= kMaxReadRegisters) {
        b.count = static_cast<uint16_t>(new_end - b.start);
        continue;
      }
    }
    out.push_back(Block{l.table, l.address, l.width});
  }
  return out;
}

std::vector<timing::RtuExchange> exchanges(const TransactionPlan& plan) {
  std::vector<timing::RtuExchange> x;
  if (plan.read_write) {
    // FC 17h: request read start/qty, write start/qty, byte count, values;
    // response byte count + values. Address, function and CRC: 4 bytes.
    const uint16_t w = plan.writes[0].count;
    const uint16_t r = plan.reads[0].count;
    x.push_back(
        timing::RtuExchange{static_cast<uint16_t>(4 + 9 + 2 * w), static_cast<uint16_t>(4 + 1 + 2 * r)});
    return x;
  }
  for (const Block& b : plan.reads) x.push_back(timing::read_registers_exchange(b.count));
  for (const Block& b : plan.writes) {
    x.push_back(b.count == 1 ? timing::write_single_exchange() : timing::write_registers_exchange(b.count));
  }
  return x;
}
}  // namespace

Status plan_transactions(const RegisterLayout& layout, const std::vector<Field>& required,
                         const std::vector<Field>& optional, const std::vector<Field>& writes,
                         TransactionPlan& plan) {
  std::vector<Location> reads[2];
  for (Field f : required) {
    if (layout[f].table == RegTable::kNone) {
      const FieldSpec& s = field_spec(f);
      char od[16];
      std::snprintf(od, sizeof od, "%04Xh/%02X", s.index, s.sub);
      return Status::failure(std::string("the gateway's register map has no ") + s.name + " (" + od + ")");
    }
    reads[table_slot(layout[f].table)].push_back(layout[f]);
  }
  for (Field f : optional) {
    if (layout[f].table != RegTable::kNone) reads[table_slot(layout[f].table)].push_back(layout[f]);
  }
  std::vector<Location> out;
  for (Field f : writes) {
    const Location& l = layout[f];
    if (l.table != RegTable::kHolding || l.width != 1 || l.address >= layout.writable.size() ||
        !layout.writable[l.address]) {
      return Status::failure(std::string("the gateway's register map has no writable holding register for ") +
                             field_spec(f).name);
    }
    out.push_back(l);
  }
  TransactionPlan p;
  p.read_registers[0] = static_cast<uint16_t>(layout.mapped[0].size());
  p.read_registers[1] = static_cast<uint16_t>(layout.mapped[1].size());
  p.writes = blocks_of(layout, out, false);
  const std::vector<Block> holding = blocks_of(layout, reads[0], true);
  const std::vector<Block> input = blocks_of(layout, reads[1], true);
  p.read_write = input.empty() && holding.size() == 1 && p.writes.size() == 1 &&
                 p.writes[0].count <= kMaxReadWriteRegisters;
  p.reads = input;
  p.reads.insert(p.reads.end(), holding.begin(), holding.end());
  plan = p;
  return Status::ok();
}

std::string describe(const TransactionPlan& plan) {
  auto range = [](const Block& b) {
    const std::string t = b.table == RegTable::kHolding ? "HR " : "IR ";
    return b.count == 1 ? t + std::to_string(b.start)
                        : t + std::to_string(b.start) + "-" + std::to_string(b.start + b.count - 1);
  };
  if (plan.read_write) return "FC 17 write " + range(plan.writes[0]) + " read " + range(plan.reads[0]);
  std::string s;
  for (const Block& b : plan.reads) {
    s += (s.empty() ? "" : " + ") + std::string(b.table == RegTable::kHolding ? "FC 03 " : "FC 04 ") +
         range(b);
  }
  for (const Block& b : plan.writes) {
    s += (s.empty() ? "" : " + ") + std::string(b.count == 1 ? "FC 06 " : "FC 10 ") + range(b);
  }
  return s;
}

uint64_t plan_frame_time_ns(const TransactionPlan& plan, const timing::SerialFormat& format) {
  uint64_t ns = 0;
  for (const timing::RtuExchange& x : exchanges(plan)) {
    ns += timing::transaction_timing(format, x, 0, 0, 0).best_ns;
  }
  return ns;
}

uint64_t plan_wire_time_ns(const TransactionPlan& plan, const timing::SerialFormat& format) {
  return plan_frame_time_ns(plan, format) + transaction_count(plan) * timing::t35_ns(format);
}

size_t transaction_count(const TransactionPlan& plan) {
  return exchanges(plan).size();
}

int derived_timeout_ms(const TransactionPlan& plan, const timing::SerialFormat* format) {
  uint64_t exchange_ns = kGatewayReplyNs;  // Modbus/TCP: no wire time
  if (format != nullptr) {
    std::vector<timing::RtuExchange> all = exchanges(plan);
    all.push_back(kIdentificationExchange);
    for (const timing::RtuExchange& x : all) {
      const uint64_t t35 = timing::t35_ns(*format);
      exchange_ns =
          std::max(exchange_ns, timing::transaction_timing(*format, x, t35, 0, kGatewayReplyNs).worst_ns);
    }
  }
  return static_cast<int>((exchange_ns + kHostMarginNs + 999999u) / 1000000u);
}

}  // namespace pcapp
}  // namespace mb2co
