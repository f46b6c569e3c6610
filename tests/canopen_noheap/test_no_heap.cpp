// The core allocates nothing at run time: every allocation function is hooked
// (tests/support/alloc_hooks.h), and a full NMT / SDO (expedited +
// segmented) / PDO / SYNC / EMCY / heartbeat scenario must make zero calls.
#include <gtest/gtest.h>

#include "../canopen/frame_log.h"
#include "../support/alloc_hooks.h"
#include "ionode/io_node.h"

namespace mb2co {
namespace {

using test::F;

// A frame sink that stores into a fixed array: the test itself must not
// allocate while counting.
struct FixedSink {
  CanFrame frames[64];
  int count = 0;
  static bool send(void* ctx, const CanFrame& f) {
    FixedSink& s = *static_cast<FixedSink*>(ctx);
    s.frames[s.count % 64] = f;
    ++s.count;
    return true;
  }
};

TEST(NoHeap, FullScenarioMakesNoAllocation) {
  FixedSink sink;
  static ionode::IoNode node(CanSink{&FixedSink::send, &sink});
  const CanFrame script[] = {
      F(0x603, {0x40, 0x00, 0x10, 0x00, 0, 0, 0, 0}),              // read 1000h
      F(0x603, {0x22, 0x17, 0x10, 0x00, 0x64, 0x00, 0, 0}),        // 1017h = 100 ms
      F(0x603, {0x23, 0x16, 0x10, 0x01, 0x64, 0x00, 0x05, 0x00}),  // consume node 5
      F(0x603, {0x23, 0x05, 0x10, 0x00, 0x80, 0x00, 0x00, 0x40}),  // SYNC producer
      F(0x603, {0x23, 0x06, 0x10, 0x00, 0x10, 0x27, 0x00, 0x00}),  // 10 ms
      F(0x603, {0x40, 0x08, 0x10, 0x00, 0, 0, 0, 0}),              // segmented upload
      F(0x603, {0x60, 0, 0, 0, 0, 0, 0, 0}),
      F(0x603, {0x70, 0, 0, 0, 0, 0, 0, 0}),
      F(0x603, {0x21, 0x00, 0x20, 0x00, 0x03, 0, 0, 0}),  // segmented download
      F(0x603, {0x09, 'a', 'b', 'c', 0, 0, 0, 0}),
      F(0x000, {0x01, 0x00}),                 // start all
      F(0x705, {0x05}),                       // heartbeat of node 5
      F(0x203, {0x01, 0x02}),                 // RPDO1
      F(0x203, {0x01}),                       // short RPDO: EMCY
      F(0x080, {}),                           // SYNC
      F(0x603, {0xE0, 0, 0, 0, 0, 0, 0, 0}),  // unknown ccs: abort
      F(0x000, {0x02, 0x03}),                 // stop
      F(0x000, {0x82, 0x03}),                 // reset communication
  };
  g_calls = 0;
  g_counting = true;
  uint32_t t = 0;
  node.start(3, t);
  for (const CanFrame& f : script) {
    t += 3000;
    node.receive(f, t);
    node.set_input(0, static_cast<uint8_t>(t >> 12));
    for (int i = 0; i < 20; ++i) node.process(t += 1000);  // heartbeat lost, SYNCs, TPDOs
  }
  g_counting = false;
  EXPECT_EQ(g_calls.load(), 0);
  EXPECT_GT(sink.count, 30);  // the scenario really exercised the services
}

TEST(NoHeap, HookCountsAllocations) {
  // The hook itself works: an allocation while counting is seen.
  g_calls = 0;
  g_counting = true;
  int* p = new int(3);
  void* q = std::malloc(16);
  g_counting = false;
  delete p;
  std::free(q);
  EXPECT_EQ(g_calls.load(), 2);
}

}  // namespace
}  // namespace mb2co
