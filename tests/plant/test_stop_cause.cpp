// One list of stop causes on the line (gateway::StopCause, the values of
// 2100h/4) and the controller's counters mapped onto it (reported_cause).
#include <gtest/gtest.h>

#include "plant/controller.h"

namespace mb2co {
namespace plant {
namespace {

TEST(StopCause, EveryControllerCauseIsOneTheFirmwareReports) {
  EXPECT_EQ(reported_cause(StopCause::kStopButton), gateway::kCauseStopButton);
  EXPECT_EQ(reported_cause(StopCause::kLocalStop2), gateway::kCauseStop2Here);
  EXPECT_EQ(reported_cause(StopCause::kPrevStop2), gateway::kCauseStop2Previous);
  EXPECT_EQ(reported_cause(StopCause::kLinkLost), gateway::kCausePcSilent);
  EXPECT_EQ(reported_cause(StopCause::kFault), gateway::kCauseNone);  // the PC's own decision
}

TEST(StopCause, EachFirmwareStopIsCountedUnderExactlyOneControllerCause) {
  int seen[gateway::kCausePcSilent + 1] = {};
  for (uint8_t c = 0; c < kStopCauseCount; ++c) ++seen[reported_cause(static_cast<StopCause>(c))];
  for (int cause = gateway::kCauseStopButton; cause <= gateway::kCausePcSilent; ++cause) {
    EXPECT_EQ(seen[cause], 1) << "2100h/4 = " << cause;
  }
}

}  // namespace
}  // namespace plant
}  // namespace mb2co
