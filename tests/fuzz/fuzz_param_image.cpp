// libFuzzer target: the parameter-image loader. The input is the content of
// the storage (the Uno's 1 KiB EEPROM; bytes beyond the input read as FFh,
// erased) under a gateway that starts from it.
// Invariants (violations abort): whatever the image holds, every stored
// value after the start is one its entry's type and limits allow, and the
// const entries hold their defaults; a save over passes (ParamSave) from
// that state completes, after it params_load finds a set, and a second
// gateway started from the saved image holds the same saved values.
#include <stdint.h>
#include <string.h>

#include <vector>

#include "canopen/param_storage.h"
#include "fuzz_support.h"
#include "gateway/gateway.h"

namespace {

using namespace mb2co;

constexpr uint16_t kImageBytes = 1024;

struct Image {
  uint8_t bytes[kImageBytes];
};

bool image_read(void* ctx, uint16_t offset, uint8_t* data, uint16_t len) {
  Image& im = *static_cast<Image*>(ctx);
  if (offset > kImageBytes || len > kImageBytes - offset) return false;
  memcpy(data, im.bytes + offset, len);
  return true;
}
bool image_write(void* ctx, uint16_t offset, const uint8_t* data, uint16_t len) {
  Image& im = *static_cast<Image*>(ctx);
  if (offset > kImageBytes || len > kImageBytes - offset) return false;
  memcpy(im.bytes + offset, data, len);
  return true;
}
std::vector<uint8_t> saved_values(const canopen::ObjectDictionary& od) {
  std::vector<uint8_t> out;
  for (uint16_t r = 0; r < od.row_count(); ++r) {
    if (!canopen::param_is_saved(od, r)) continue;
    uint8_t buf[64];
    const uint16_t n = od.copy_out(r, buf, sizeof buf);
    out.insert(out.end(), buf, buf + n);
  }
  return out;
}

// The const entries of a gateway started without storage: the same for
// every input, so found once (a third Gateway::start per input was a
// seventh of an execution).
const std::vector<uint8_t>& default_consts(const gateway::GatewayPorts& ports) {
  static const std::vector<uint8_t> consts = [&ports] {
    gateway::Gateway defaults(gateway::GatewayPorts{ports.can, ports.serial, nullptr, 115200});
    defaults.start(1000);
    return fuzz::const_values(defaults.od());
  }();
  return consts;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static Image image;
  memset(image.bytes, 0xFF, sizeof image.bytes);
  memcpy(image.bytes, data, size < kImageBytes ? size : kImageBytes);
  const canopen::ParamStorage storage{&image_read, &image_write, nullptr, &image, nullptr};
  const gateway::GatewayPorts ports{CanSink{&fuzz::drop_frame, nullptr},
                                    modbus::ByteSink{&fuzz::drop_bytes, nullptr}, &storage, 115200};
  std::vector<uint8_t> before;
  {
    gateway::Gateway g(ports);
    g.start(1000);
    fuzz::require_all_allowed(g.od(), "a loaded value beyond its entry's limits");
    fuzz::require(fuzz::const_values(g.od()) == default_consts(ports),
                  "a const entry differs from its default after a load");
    before = saved_values(g.od());
    canopen::ParamSave save{};
    save.start(g.od(), storage);
    canopen::ParamSave::Result r = canopen::ParamSave::kRunning;
    for (int pass = 0; pass < 1000 && r == canopen::ParamSave::kRunning; ++pass)
      r = save.step(g.od(), storage);
    fuzz::require(r == canopen::ParamSave::kDone, "a save from a started gateway did not complete");
  }
  gateway::Gateway again(ports);
  again.start(1000);
  fuzz::require(saved_values(again.od()) == before, "the saved values did not come back after a restart");
  return 0;
}
