#include "ascii_lines.h"

#include <string.h>

namespace mb2co {
namespace master {
namespace ascii {

void LineFramer::finish_line() {
  items_.push_back(Entry{discarding_ ? Item::kOverlong : Item::kLine, std::move(partial_)});
  partial_.clear();
  discarding_ = false;
}

void LineFramer::append(const uint8_t* data, size_t n) {
  const char* p = reinterpret_cast<const char*>(data);
  while (n > 0) {
    const char* lf = static_cast<const char*>(memchr(p, '\n', n));
    const size_t take = lf ? static_cast<size_t>(lf - p) : n;
    if (!discarding_) {
      if (partial_.size() + take <= max_line_) {
        partial_.append(p, take);
      } else {
        // Too long: keep what the answer needs, drop the rest up to the LF.
        partial_.append(p, take < kOverlongPrefix ? take : kOverlongPrefix);
        partial_.resize(kOverlongPrefix < partial_.size() ? kOverlongPrefix : partial_.size());
        discarding_ = true;
      }
    }
    if (!lf) return;
    finish_line();
    p += take + 1;
    n -= take + 1;
  }
}

LineFramer::Item LineFramer::next(std::string* text) {
  if (items_.empty()) return Item::kNothing;
  Entry e = std::move(items_.front());
  items_.pop_front();
  *text = std::move(e.text);
  return e.item;
}

LineFramer::Item LineFramer::take_partial(std::string* text) {
  if (!partial()) return Item::kNothing;
  const Item item = discarding_ ? Item::kOverlong : Item::kLine;
  *text = std::move(partial_);
  partial_.clear();
  discarding_ = false;
  return item;
}

}  // namespace ascii
}  // namespace master
}  // namespace mb2co
