#include "program_data.h"

#include <string.h>

namespace mb2co {
namespace node {

namespace {
const uint8_t kHighestSub = 1;  ///< 1F50h/0
}  // namespace

ProgramData::ProgramData() : content_(kInitialBytes) {
  for (uint32_t i = 0; i < kInitialBytes; ++i) content_[i] = static_cast<uint8_t>(i % 251u);
}

canopen::SdoDomain ProgramData::table() {
  return canopen::SdoDomain{&ProgramData::owns,
                            &ProgramData::size,
                            &ProgramData::read,
                            &ProgramData::begin,
                            &ProgramData::write,
                            &ProgramData::commit,
                            this};
}

bool ProgramData::owns(void*, uint16_t index, uint8_t sub) {
  return index == kIndex && sub <= kHighestSub;
}

uint32_t ProgramData::size(void* ctx, uint16_t, uint8_t sub) {
  if (sub == 0) return 1;
  return static_cast<uint32_t>(static_cast<ProgramData*>(ctx)->content_.size());
}

canopen::SdoAbort ProgramData::read(void* ctx, uint16_t, uint8_t sub, uint32_t offset, uint8_t* buf,
                                    uint16_t n) {
  if (sub == 0) {
    if (offset != 0 || n > 1) return canopen::kAbortGeneral;
    if (n == 1) buf[0] = kHighestSub;
    return canopen::kSdoOk;
  }
  const std::vector<uint8_t>& c = static_cast<ProgramData*>(ctx)->content_;
  if (offset > c.size() || n > c.size() - offset) return canopen::kAbortGeneral;
  memcpy(buf, c.data() + offset, n);
  return canopen::kSdoOk;
}

canopen::SdoAbort ProgramData::begin(void* ctx, uint16_t, uint8_t sub, uint32_t size, bool indicated) {
  if (sub == 0) return canopen::kAbortReadOnly;
  if (indicated && size > kMaxBytes) return canopen::kAbortTooLong;
  ProgramData& p = *static_cast<ProgramData*>(ctx);
  p.staging_.clear();
  if (indicated) p.staging_.reserve(size);
  return canopen::kSdoOk;
}

canopen::SdoAbort ProgramData::write(void* ctx, uint16_t, uint8_t, uint32_t offset, const uint8_t* data,
                                     uint16_t n) {
  ProgramData& p = *static_cast<ProgramData*>(ctx);
  // The server hands the bytes over in order; anything else is a bug there.
  if (offset != p.staging_.size()) return canopen::kAbortGeneral;
  if (n > kMaxBytes - offset) return canopen::kAbortTooLong;
  p.staging_.insert(p.staging_.end(), data, data + n);
  return canopen::kSdoOk;
}

canopen::SdoAbort ProgramData::commit(void* ctx, uint16_t, uint8_t, uint32_t size) {
  ProgramData& p = *static_cast<ProgramData*>(ctx);
  if (size != p.staging_.size()) return canopen::kAbortGeneral;
  p.content_.swap(p.staging_);
  p.staging_.clear();
  p.staging_.shrink_to_fit();
  return canopen::kSdoOk;
}

}  // namespace node
}  // namespace mb2co
