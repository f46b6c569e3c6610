// 1F50h "program data" (CiA 302 style): a DOMAIN the SDO server serves from
// RAM, outside the OD table (canopen::SdoDomain), so that segmented and block
// transfers of large objects can be tried against mb2co-node by any peer.
//   1F50h/0  UNSIGNED8, read-only: 1 (the highest sub-index)
//   1F50h/1  DOMAIN, read-write, 0..1 MiB. Starts as 131,072 bytes with
//            byte i = i mod 251 (a peer can check an upload without a copy;
//            251 is prime, so a shifted or repeated segment shows). A
//            download replaces it only when it completes (staging buffer):
//            an aborted or timed-out download leaves the old content whole.
// The content lives in RAM only: it is back to the pattern at every start.
#pragma once
#include <stdint.h>

#include <vector>

#include "canopen/sdo_domain.h"

namespace mb2co {
namespace node {

class ProgramData {
 public:
  static const uint16_t kIndex = 0x1F50;
  static const uint32_t kMaxBytes = 1u << 20;
  static const uint32_t kInitialBytes = 131072;

  ProgramData();
  /// The table for canopen::SdoServer::set_domain; `this` must outlive its use.
  canopen::SdoDomain table();
  const std::vector<uint8_t>& content() const { return content_; }

 private:
  static bool owns(void* ctx, uint16_t index, uint8_t sub);
  static uint32_t size(void* ctx, uint16_t index, uint8_t sub);
  static canopen::SdoAbort read(void* ctx, uint16_t index, uint8_t sub, uint32_t offset, uint8_t* buf,
                                uint16_t n);
  static canopen::SdoAbort begin(void* ctx, uint16_t index, uint8_t sub, uint32_t size, bool indicated);
  static canopen::SdoAbort write(void* ctx, uint16_t index, uint8_t sub, uint32_t offset, const uint8_t* data,
                                 uint16_t n);
  static canopen::SdoAbort commit(void* ctx, uint16_t index, uint8_t sub, uint32_t size);

  std::vector<uint8_t> content_;
  std::vector<uint8_t> staging_;  ///< the download in progress
};

}  // namespace node
}  // namespace mb2co
