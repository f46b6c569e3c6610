// A bounded, always NUL-terminated text builder for error messages: the
// portable core has no snprintf it may rely on, and messages must never
// overrun their fixed buffer (they are truncated instead).
#pragma once
#include <stddef.h>
#include <stdint.h>

namespace mb2co {
namespace plant {

/// Writes into a caller-owned buffer of `capacity` bytes (capacity >= 1).
/// Invariant: buf[length()] == '\0' and length() < capacity at all times.
class TextBuffer {
 public:
  TextBuffer(char* buf, size_t capacity);

  TextBuffer& add(const char* text);
  /// Appends at most `count` bytes of `text`; bytes outside printable ASCII
  /// become '?' so a hostile config file cannot put control codes on a terminal.
  TextBuffer& add_quoted(const char* text, size_t count);
  TextBuffer& add_u32(uint32_t value);

  size_t length() const { return length_; }

 private:
  void put(char c);

  char* buf_;
  size_t capacity_;
  size_t length_;
};

}  // namespace plant
}  // namespace mb2co
