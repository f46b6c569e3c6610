// mb2co-plant (the program, with its default 25 ms timeout and 2 retries)
// against a gateway whose answers come late: the real firmware (mb2co-node
// on a pty) behind a fault injector on a second pty that holds the answers
// back. The injector models the simulated Uno on a loaded machine: it did not
// run for a while, so it answers nothing at first and then every request it
// had queued at once (late answers read together with the last retry's),
// then each answer 40 ms late (the timeout is 25 ms) for a few more, then on
// time. The app must not exit,
// must verify the gateway and reach its normal cycle.
//
// The delays are the fault being injected, not synchronisation: every step
// of the test waits for a line of the app or of the node, with a deadline
// that only bounds a failure.
#include <fcntl.h>
#include <gtest/gtest.h>
#include <poll.h>
#include <signal.h>
#include <stdlib.h>
#include <termios.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "line_child.h"
#include "node_harness.h"
#include "rtu_frames.h"

namespace {

using namespace std::chrono_literals;
using Clock = std::chrono::steady_clock;

bool contains(const std::string& line, const std::string& part) {
  return line.find(part) != std::string::npos;
}

/// Sits between the app (on a pty of its own, `path()`) and the gateway's pty:
/// requests pass at once, answers are held back.
class LateAnswerInjector {
 public:
  struct Faults {
    /// The first stall_answers answers are held until the gateway has given
    /// them all (so until the app sent that many attempts), then go out in one
    /// write: the first ones late by whole attempts, read together with the
    /// last one's. At most a second: a slave that catches up eventually.
    int stall_answers = 3;
    /// The next late_count answers (reads from the gateway): each late_ms
    /// after the gateway gave it, in order.
    int late_count = 4;
    std::chrono::milliseconds late{40};
    /// The first corrupt_answers answers get a wrong CRC (on time).
    int corrupt_answers = 0;
  };

  ~LateAnswerInjector() {
    stop_ = true;
    if (thread_.joinable()) thread_.join();
    for (int fd : {app_master_, app_slave_, gateway_}) {
      if (fd >= 0) ::close(fd);
    }
  }

  /// Opens both sides; `link` is the app's path (a symlink to the new pty).
  bool start(const std::string& gateway_path, const std::string& link, const Faults& faults) {
    faults_ = faults;
    gateway_ = ::open(gateway_path.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK);
    app_master_ = posix_openpt(O_RDWR | O_NOCTTY | O_NONBLOCK);
    if (gateway_ < 0 || app_master_ < 0 || grantpt(app_master_) != 0 || unlockpt(app_master_) != 0)
      return false;
    const char* name = ptsname(app_master_);
    if (name == nullptr) return false;
    // Held open so that the master never reads EIO while the app has the
    // port closed (reconnection).
    app_slave_ = ::open(name, O_RDWR | O_NOCTTY);
    if (app_slave_ < 0 || !make_raw(app_slave_) || !make_raw(gateway_)) return false;
    if (::symlink(name, link.c_str()) != 0) return false;
    thread_ = std::thread([this] { run(); });
    return true;
  }

  /// Answers held back in all, and the most sent in one write.
  int late_answers() const { return late_answers_; }
  int most_in_one_write() const { return most_in_one_write_; }

 private:
  struct Held {
    Clock::time_point due;
    std::vector<uint8_t> bytes;
    int answers;
  };

  static bool make_raw(int fd) {
    termios t;
    if (tcgetattr(fd, &t) != 0) return false;
    cfmakeraw(&t);
    return tcsetattr(fd, TCSANOW, &t) == 0;
  }

  void run() {
    std::vector<uint8_t> stalled;
    int stalled_answers = 0;
    Clock::time_point first_stalled;
    int late_left = faults_.late_count;
    int corrupt_left = faults_.corrupt_answers;
    std::vector<Held> held;
    uint8_t buf[512];
    while (!stop_) {
      int wait_ms = 10;  // also how soon stop_ is noticed
      if (!held.empty()) {
        const auto left =
            std::chrono::duration_cast<std::chrono::milliseconds>(held.front().due - Clock::now());
        wait_ms = std::max(0, std::min(wait_ms, static_cast<int>(left.count()) + 1));
      }
      pollfd p[2] = {{app_master_, POLLIN, 0}, {gateway_, POLLIN, 0}};
      ::poll(p, 2, wait_ms);
      const Clock::time_point now = Clock::now();
      if (p[0].revents & POLLIN) {
        const ssize_t n = ::read(app_master_, buf, sizeof buf);
        if (n > 0) write_all(gateway_, buf, static_cast<size_t>(n));
      }
      if (p[1].revents & POLLIN) {
        const ssize_t n = ::read(gateway_, buf, sizeof buf);
        if (n > 0 && corrupt_left > 0) {
          --corrupt_left;
          buf[n - 1] = static_cast<uint8_t>(buf[n - 1] ^ 0xFF);
        }
        if (n > 0 && stalled_answers < faults_.stall_answers) {
          if (stalled_answers == 0) first_stalled = now;
          stalled.insert(stalled.end(), buf, buf + n);
          ++stalled_answers;
          ++late_answers_;
        } else if (n > 0) {
          Clock::time_point due = now;
          if (late_left > 0) {
            --late_left;
            due = now + faults_.late;
            ++late_answers_;
          }
          // Never overtakes an answer held before it.
          if (!held.empty() && due < held.back().due) due = held.back().due;
          held.push_back(Held{due, std::vector<uint8_t>(buf, buf + n), 1});
        }
      }
      if (!stalled.empty() && (stalled_answers == faults_.stall_answers || now - first_stalled > 1s)) {
        held.insert(held.begin(), Held{now, stalled, stalled_answers});
        stalled.clear();
        stalled_answers = faults_.stall_answers;
      }
      // Everything due goes out in one write: a slave catching up.
      std::vector<uint8_t> out;
      int answers = 0;
      while (!held.empty() && held.front().due <= Clock::now()) {
        out.insert(out.end(), held.front().bytes.begin(), held.front().bytes.end());
        answers += held.front().answers;
        held.erase(held.begin());
      }
      if (!out.empty()) {
        write_all(app_master_, out.data(), out.size());
        if (answers > most_in_one_write_) most_in_one_write_ = answers;
      }
    }
  }

  static void write_all(int fd, const uint8_t* data, size_t n) {
    while (n > 0) {
      const ssize_t w = ::write(fd, data, n);
      if (w < 0 && errno == EAGAIN) {
        pollfd p{fd, POLLOUT, 0};
        ::poll(&p, 1, 10);
        continue;
      }
      if (w <= 0) return;
      data += w;
      n -= static_cast<size_t>(w);
    }
  }

  Faults faults_;
  int app_master_ = -1;
  int app_slave_ = -1;
  int gateway_ = -1;
  std::thread thread_;
  std::atomic<bool> stop_{false};
  std::atomic<int> late_answers_{0};
  std::atomic<int> most_in_one_write_{0};
};

struct PlantLateAnswer : ::testing::Test {
  mb2co::test::TempDir dir;
  mb2co::test::NodeProcess node;
  LateAnswerInjector injector;
  mb2co::test::LineChild plant;

  void SetUp() override {
    ASSERT_TRUE(node.start({"--can", "none", "--pty", dir.path("gw")})) << node.error();
  }

  /// Waits for an app line containing `part`; on failure says whether the app
  /// ended (and what it said on stderr).
  void expect_line(const std::string& part, std::chrono::milliseconds timeout = 10s,
                   std::string* got = nullptr) {
    std::string line;
    if (plant.wait_line([&](const std::string& l) { return contains(l, part); }, timeout, &line)) {
      if (got != nullptr) *got = line;
      return;
    }
    const int code = plant.wait_exit(0ms);
    FAIL() << "no line with '" << part << "' from mb2co-plant"
           << (code >= 0 ? ", which exited with " + std::to_string(code) : std::string(", still running"))
           << "; stderr: " << plant.stderr_text();
  }
};

// The answers to the three FC 2B/0E attempts all arrive together, after the
// last attempt began; the next answers are 40 ms late. With the defaults (25 ms,
// 2 retries) the app verifies the gateway, runs its cycle (a START from the
// panel starts the station: the RUN command it writes lights the gateway's
// RUN LED) and stops cleanly.
TEST_F(PlantLateAnswer, LateAnswersAtStartAreNotFatal) {
  ASSERT_TRUE(injector.start(dir.path("gw"), dir.path("app"), LateAnswerInjector::Faults{}));
  ASSERT_TRUE(plant.start({MB2CO_PLANT, "--port", dir.path("app"), "--plain"})) << plant.error();

  ASSERT_NO_FATAL_FAILURE(expect_line(" link up " + dir.path("app") + " slave 1: mb2co mb2co gateway"));
  ASSERT_NO_FATAL_FAILURE(expect_line(" buttons none"));
  EXPECT_EQ(injector.most_in_one_write(), 3) << "the fault was not injected as meant";

  // The normal cycle: the panel's START is read, the controller runs, the RUN
  // command it writes reaches the gateway. Pressed until seen, so a starved
  // app cannot miss it.
  ASSERT_TRUE(node.child.send_line("press START"));
  ASSERT_NO_FATAL_FAILURE(expect_line(" buttons START"));
  ASSERT_NO_FATAL_FAILURE(expect_line(" state moving"));
  ASSERT_TRUE(node.child.send_line("release START"));
  ASSERT_NO_FATAL_FAILURE(expect_line(" buttons none"));
  std::string leds;
  const auto until = Clock::now() + 10s;
  while (!contains(leds, "self=1") && Clock::now() < until) leds = node.ask("leds?", "leds ");
  EXPECT_TRUE(contains(leds, "self=1")) << "the gateway's RUN LED: " << leds;

  ASSERT_TRUE(plant.signal(SIGTERM));
  ASSERT_NO_FATAL_FAILURE(expect_line("SIGTERM: RUN=0 written, port closed"));
  std::string summary;
  ASSERT_NO_FATAL_FAILURE(expect_line(" summary cycles=", 10s, &summary));
  EXPECT_EQ(plant.wait_exit(10s), 0) << plant.stderr_text();
  EXPECT_EQ(plant.stderr_text(), "");
  // The late answers cost attempts, and were dropped before a request.
  EXPECT_NE(mb2co::test::field_of(summary, "retries"), "0") << summary;
  std::printf("%s\n", summary.c_str());
  RecordProperty("late_answers", injector.late_answers());
  RecordProperty("most_answers_in_one_write", injector.most_in_one_write());
}

// Every FC 2B/0E attempt of the first connection gets a corrupt answer: a
// slave is there, so the app keeps trying with one line per attempt (not
// exit 1 as for silence), and is up as soon as an answer is intact.
TEST_F(PlantLateAnswer, CorruptAnswersAtStartAreRetried) {
  LateAnswerInjector::Faults faults;
  faults.stall_answers = 0;
  faults.late_count = 0;
  faults.corrupt_answers = 3;  // the three attempts of the first verification
  ASSERT_TRUE(injector.start(dir.path("gw"), dir.path("app"), faults));
  ASSERT_TRUE(plant.start({MB2CO_PLANT, "--port", dir.path("app"), "--plain"})) << plant.error();

  std::string line;
  ASSERT_NO_FATAL_FAILURE(
      expect_line(" connect failed: " + dir.path("app") + ": FC 2B/0E: bad answer", 10s, &line));
  EXPECT_TRUE(contains(line, "late or corrupt")) << line;
  EXPECT_TRUE(contains(line, "| next attempt in 100 ms")) << line;
  ASSERT_NO_FATAL_FAILURE(expect_line(" link up " + dir.path("app") + " slave 1: mb2co mb2co gateway"));
  ASSERT_NO_FATAL_FAILURE(expect_line(" buttons none"));
  ASSERT_TRUE(plant.signal(SIGINT));
  ASSERT_NO_FATAL_FAILURE(expect_line("SIGINT: RUN=0 written, port closed"));
  EXPECT_EQ(plant.wait_exit(10s), 0) << plant.stderr_text();
  EXPECT_EQ(plant.stderr_text(), "");
}

// A slave that answers FC 2B/0E as another vendor's device is definitely not
// a gateway: one line on stderr, exit 1, at the first connection.
TEST(PlantIdentification, AnotherVendorEndsTheProgram) {
  mb2co::test::TempDir dir;
  const int master = posix_openpt(O_RDWR | O_NOCTTY);
  ASSERT_GE(master, 0);
  ASSERT_EQ(grantpt(master), 0);
  ASSERT_EQ(unlockpt(master), 0);
  ASSERT_EQ(::symlink(ptsname(master), dir.path("app").c_str()), 0);
  // The vendor's answer, to whatever is asked (only FC 2B/0E will be).
  const mb2co::test::Bytes answer = mb2co::test::with_crc({0x01, 0x2B, 0x0E, 0x01, 0x01, 0x00, 0x00, 0x03,  //
                                                           0x00, 0x04, 'a',  'c',  'm',  'e',               //
                                                           0x01, 0x01, 'x',  0x02, 0x01, '1'});
  std::atomic<bool> done{false};
  std::thread slave([&] {
    uint8_t request[7];
    while (!done) {
      if (!mb2co::test::read_exact(master, request, sizeof request, 100ms)) continue;
      if (::write(master, answer.data(), answer.size()) < 0) break;
    }
  });
  mb2co::test::LineChild plant;
  ASSERT_TRUE(plant.start({MB2CO_PLANT, "--port", dir.path("app"), "--plain"})) << plant.error();
  EXPECT_EQ(plant.wait_exit(10s), 1);
  done = true;
  slave.join();
  ::close(master);
  EXPECT_EQ(plant.stderr_text(),
            "mb2co-plant: " + dir.path("app") + ": slave 1 is not an mb2co gateway (vendor 'acme')\n");
}

}  // namespace
