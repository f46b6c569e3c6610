// The result line of `upload` and `download`: text or JSON, with the
// transfer's size, duration and rate.
#pragma once
#include <string>

#include "transfer_network.h"

namespace mb2co {
namespace master {

/// "uploaded 131072 bytes from node 3 1F50h/1 in 1.234 s (106.2 KiB/s, block
/// with CRC)" (download: "downloaded ... to node ...").
std::string transfer_summary(const Transfer& t);
/// {"node":3,"file":"PATH","bytes":131072,"seconds":1.234,"block":true,"crc":true}
std::string transfer_json(const Transfer& t, const std::string& path);

}  // namespace master
}  // namespace mb2co
