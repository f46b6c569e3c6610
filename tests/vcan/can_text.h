// Frames in the text notation of can-utils (candump -L, cansend) and of
// can_peer.py: 123#11223344, 01234567# (8 hex digits = extended), 7FF#R,
// 123#R8 (RTR with dlc 8). Lets tests compare our frames with what
// independent tools print and feed them.
#pragma once
#include <string>

#include "canopen/can_frame.h"

namespace mb2co {
namespace test {

std::string to_text(const CanFrame& frame);

/// False for text that is not a classic frame in this notation.
bool from_text(const std::string& text, CanFrame& frame);

/// The frame field of a `candump -L` line "(1.000000) vcan0 123#11", or "".
std::string candump_frame_field(const std::string& line);

/// Field-by-field equality (data only up to dlc, none for RTR).
bool same_frame(const CanFrame& a, const CanFrame& b);

/// A classic frame built in one expression (data bytes beyond `dlc` zero).
CanFrame make_frame(uint32_t id, uint8_t flags, uint8_t dlc, const char* hex_data = "");

}  // namespace test
}  // namespace mb2co
