#include "plant/text_buffer.h"

namespace mb2co {
namespace plant {

TextBuffer::TextBuffer(char* buf, size_t capacity) : buf_(buf), capacity_(capacity), length_(0) {
  buf_[0] = '\0';
}

void TextBuffer::put(char c) {
  if (length_ + 1 >= capacity_) return;  // truncate, keep the terminator
  buf_[length_++] = c;
  buf_[length_] = '\0';
}

TextBuffer& TextBuffer::add(const char* text) {
  while (*text != '\0') put(*text++);
  return *this;
}

TextBuffer& TextBuffer::add_quoted(const char* text, size_t count) {
  put('\'');
  for (size_t i = 0; i < count; ++i) {
    const char c = text[i];
    put(c >= ' ' && c <= '~' ? c : '?');
  }
  put('\'');
  return *this;
}

TextBuffer& TextBuffer::add_u32(uint32_t value) {
  char digits[10];
  uint8_t n = 0;
  do {
    digits[n++] = static_cast<char>('0' + value % 10u);
    value /= 10u;
  } while (value != 0u);
  while (n > 0) put(digits[--n]);
  return *this;
}

}  // namespace plant
}  // namespace mb2co
