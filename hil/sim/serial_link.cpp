#include "sim/serial_link.h"

namespace mb2co {
namespace sim {

UartChannel::UartChannel(EventQueue& queue, uint32_t baud, uint8_t char_bits)
    : q_(queue), baud_(baud), char_bits_(char_bits) {}

void UartChannel::send(const uint8_t* data, size_t n, size_t gap_index, SimNs gap_ns) {
  const SimNs start = free_ns_ > q_.now() ? free_ns_ : q_.now();
  const bool split = gap_ns != 0 && gap_index != 0 && gap_index < n;
  free_ns_ = start + (split ? gap_ns : 0) + chars_ns(n);
  sent_ += n;
  if (!connected_) {
    lost_ += n;
    return;
  }
  if (n != 0 && line_.empty() && reader != nullptr) reader->floor_moved();
  for (size_t k = 0; k < n; ++k) {
    const SimNs gap = (split && k >= gap_index) ? gap_ns : 0;
    line_.push_back(SerialChar{data[k], start + gap + chars_ns(k + 1)});
  }
  if (n != 0 && on_sent) q_.at(free_ns_, this, 0);
}

void UartChannel::set_connected(bool connected) {
  if (!connected) {
    // Characters still on the wire never complete.
    while (!line_.empty() && line_.back().end_ns > q_.now()) {
      line_.pop_back();
      ++lost_;
    }
  }
  connected_ = connected;
}

bool UartChannel::take(SimNs until_ns, SerialChar* out) {
  if (line_.empty() || line_.front().end_ns > until_ns) return false;
  *out = line_.front();
  line_.pop_front();
  return true;
}

void UartChannel::on_event(uint32_t, uint64_t) {
  if (on_sent) on_sent();
}

}  // namespace sim
}  // namespace mb2co
