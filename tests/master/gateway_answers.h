// What a scripted gateway answers in the --via-modbus tests, built with the
// shared codec (modbus/network_pdu.h): the serial and the TCP link tests
// frame the same PDUs their own way.
#pragma once
#include <gtest/gtest.h>
#include <stdint.h>

#include <vector>

#include "modbus/network_pdu.h"

namespace mb2co {
namespace master {

/// The PDU of the gateway's normal answer to `request` (an RTU ADU of
/// `length` bytes) with `data` (an upload window, the whole object).
inline std::vector<uint8_t> upload_answer_pdu(const uint8_t* request, uint16_t length,
                                              const std::vector<uint8_t>& data) {
  modbus::NetMessage m{};
  EXPECT_TRUE(modbus::parse_net_request(request + 1, static_cast<uint16_t>(length - 3), m));
  m.count = static_cast<uint16_t>(data.size());
  m.object_size = static_cast<uint32_t>(data.size());
  m.data = data.data();
  m.data_length = static_cast<uint16_t>(data.size());
  uint8_t pdu[256];
  return std::vector<uint8_t>(pdu, pdu + modbus::build_net_response(pdu, sizeof pdu, m));
}

}  // namespace master
}  // namespace mb2co
