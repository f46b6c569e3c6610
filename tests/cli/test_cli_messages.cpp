// The wording of usage errors (shared/host/cli_messages.h): the edit
// distance behind "did you mean", which words are near enough, and the
// shapes docs/cli.md lists.
#include <gtest/gtest.h>

#include "host/cli_messages.h"

namespace {

using namespace mb2co::cli;

TEST(CliMessages, EditDistanceCountsInsertDeleteChangeAndSwap) {
  EXPECT_EQ(edit_distance("--bitrate", "--bitrate"), 0u);
  EXPECT_EQ(edit_distance("--bitrate", "--bitrates"), 1u) << "insert";
  EXPECT_EQ(edit_distance("--bitrates", "--bitrate"), 1u) << "delete";
  EXPECT_EQ(edit_distance("--node", "--mode"), 1u) << "change";
  EXPECT_EQ(edit_distance("--hlep", "--help"), 1u) << "two neighbours swapped";
  EXPECT_EQ(edit_distance("", "abc"), 3u);
  EXPECT_EQ(edit_distance("kitten", "sitting"), 3u);
}

TEST(CliMessages, NearestWordIsATypingSlipNotAGuess) {
  const std::vector<std::string> lab = {"--scenario", "--stations", "--seed", "--bitrates", "--presses"};
  EXPECT_EQ(nearest_word("--bitrate", lab), "--bitrates");
  EXPECT_EQ(nearest_word("--statoins", lab), "--stations");
  EXPECT_EQ(nearest_word("--scen", lab), "--scenario") << "a prefix of one option";
  EXPECT_EQ(nearest_word("--bogus", lab), "") << "nothing within a third of its letters";
  EXPECT_EQ(nearest_word("--sed", lab), "--seed");
  EXPECT_EQ(nearest_word("--s", lab), "") << "too short to be a prefix of anything";
  EXPECT_EQ(nearest_word("--cycle", {"--cycles", "--cycle-ms"}), "") << "two equally near: no guess";
}

TEST(CliMessages, TheShapesOfDocsCli) {
  EXPECT_EQ(unknown_option("mb2co-lab", "", "--bitrate", {"--bitrates", "--stations"}),
            "unknown option --bitrate, did you mean --bitrates? (try mb2co-lab --help)");
  EXPECT_EQ(unknown_option("mb2co-timing", "rta", "--bogus", {"--bitrate"}),
            "unknown option --bogus (try mb2co-timing rta --help)");
  EXPECT_EQ(missing_operand("mb2co-master", "read", "NODE INDEX SUB [TYPE]"),
            "missing operand: read NODE INDEX SUB [TYPE] (try mb2co-master read --help)");
  EXPECT_EQ(bad_value("--button", "START, STOP or STOP2", "GO"),
            "--button must be START, STOP or STOP2, got \"GO\"");
}

}  // namespace
