// A client's byte stream cut into request lines (LF ends one; a CR before
// it is a blank to the parser). Memory stays bounded whatever comes: a line
// longer than `max_line` bytes is not kept: its first bytes are (for the
// [SEQ] of the answer), the rest is dropped up to its LF, and it comes out
// as one kOverlong item. Plain C++ without OS or Qt.
#pragma once
#include <stddef.h>
#include <stdint.h>

#include <deque>
#include <string>

namespace mb2co {
namespace master {
namespace ascii {

class LineFramer {
 public:
  /// How many first bytes of an overlong line are kept.
  static constexpr size_t kOverlongPrefix = 32;

  explicit LineFramer(size_t max_line) : max_line_(max_line) {}

  /// Takes bytes; complete lines become items.
  void append(const uint8_t* data, size_t n);

  enum class Item : uint8_t {
    kNothing,   ///< no complete line yet
    kLine,      ///< `text` is the line without its LF
    kOverlong,  ///< `text` holds the line's first kOverlongPrefix bytes
  };
  /// The oldest complete item.
  Item next(std::string* text);
  /// Complete items waiting.
  size_t ready() const { return items_.size(); }
  /// Bytes of an unfinished last line (0: the stream ends at a line's end).
  bool partial() const { return !partial_.empty() || discarding_; }
  /// The unfinished last line as an item (at end of input), then nothing.
  Item take_partial(std::string* text);

 private:
  struct Entry {
    Item item;
    std::string text;
  };
  void finish_line();

  size_t max_line_;
  std::deque<Entry> items_;
  std::string partial_;      ///< the unfinished line (at most max_line_ bytes)
  bool discarding_ = false;  ///< the unfinished line is overlong: its prefix is in partial_
};

}  // namespace ascii
}  // namespace master
}  // namespace mb2co
