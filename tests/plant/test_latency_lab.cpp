// The latency-lab control process (seed 000 §11): LED follows the button.
#include <gtest/gtest.h>

#include "plant/latency_lab.h"

namespace mb2co {
namespace plant {
namespace {

TEST(ButtonToLed, LedFollowsTheButtonInTheSameCycle) {
  ButtonToLed lab;
  EXPECT_FALSE(lab.led());
  EXPECT_FALSE(lab.step(false));
  EXPECT_TRUE(lab.step(true));
  EXPECT_TRUE(lab.step(true));
  EXPECT_FALSE(lab.step(false));
  EXPECT_TRUE(lab.step(true));
  EXPECT_EQ(lab.presses(), 2u);
  EXPECT_EQ(lab.releases(), 1u);
  EXPECT_TRUE(lab.led());
}

}  // namespace
}  // namespace plant
}  // namespace mb2co
