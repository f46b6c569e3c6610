// A built program run once to its end, as a user would from a shell: its exit
// status and everything it printed. For tests of command lines (tests/cli,
// tests/timing). Host-only (POSIX); header-only.
#pragma once
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>

namespace mb2co {
namespace test {

struct ProgramResult {
  int status = -1;  ///< exit status; -1 when killed by a signal
  std::string out;
  std::string err;
};

/// The whole file ("" when it cannot be read).
inline std::string slurp(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  std::ostringstream s;
  s << f.rdbuf();
  return s.str();
}

/// A fixture with a fresh temporary directory (dir_, removed afterwards) and
/// run(): `exe args` through sh, stdin /dev/null.
class ProgramTest : public ::testing::Test {
 protected:
  void SetUp() override {
    char dir[] = "/tmp/mb2co_program_test_XXXXXX";
    ASSERT_NE(mkdtemp(dir), nullptr);
    dir_ = dir;
  }
  void TearDown() override { std::system(("rm -rf '" + dir_ + "'").c_str()); }

  ProgramResult run_program(const std::string& exe, const std::string& args) {
    const std::string out = dir_ + "/.out", err = dir_ + "/.err";
    const int raw = std::system((exe + " " + args + " >" + out + " 2>" + err + " </dev/null").c_str());
    ProgramResult r;
    r.status = WIFEXITED(raw) ? WEXITSTATUS(raw) : -1;
    r.out = slurp(out);
    r.err = slurp(err);
    return r;
  }

  std::string dir_;
};

}  // namespace test
}  // namespace mb2co
