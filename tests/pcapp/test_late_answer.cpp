// mb2co-plant (the program, with its default timeout, 36 ms at 115200 baud
// (derived_timeout_ms), and 2 retries)
// against a gateway whose answers come late: the real firmware (mb2co-node
// on a pty) behind a fault injector on a second pty that holds the answers
// back. The injector models the simulated Uno on a loaded machine: it did not
// run for a while, so it answers nothing at first and then every request it
// had queued at once (late answers read together with the last retry's),
// then each answer 55 ms late (past the timeout) for a few more, then on
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
#include "modbus_link.h"
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
    /// last one's. At most stall_at_most after the first (when two answers
    /// came in one read here, fewer are counted).
    int stall_answers = 3;
    std::chrono::milliseconds stall_at_most{90};  // three attempts of the 36 ms default: 72 ms
    /// The next late_count answers (reads from the gateway): each late_ms
    /// after the gateway gave it, in order.
    int late_count = 4;
    std::chrono::milliseconds late{55};  // 1.5 timeouts of the 36 ms default: read with the retry
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
      if (!stalled.empty() &&
          (stalled_answers == faults_.stall_answers || now - first_stalled > faults_.stall_at_most)) {
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

  /// Waits for an app line containing one of `parts` (into `got`); on
  /// failure says whether the app ended, and shows all it said.
  void expect_any(const std::vector<std::string>& parts, std::chrono::milliseconds timeout,
                  std::string* got) {
    std::string line;
    const bool seen = plant.wait_line(
        [&](const std::string& l) {
          transcript_ += "  | " + l + "\n";
          for (const std::string& part : parts) {
            if (contains(l, part)) return true;
          }
          return false;
        },
        timeout, &line);
    if (seen) {
      if (got != nullptr) *got = line;
      return;
    }
    const int code = plant.wait_exit(0ms);
    FAIL() << "no line with '" << parts.front() << "' from mb2co-plant"
           << (code >= 0 ? ", which exited with " + std::to_string(code) : std::string(", still running"))
           << "; stdout:\n"
           << transcript_ << "stderr: " << plant.stderr_text();
  }
  void expect_line(const std::string& part, std::chrono::milliseconds timeout = 10s,
                   std::string* got = nullptr) {
    expect_any({part}, timeout, got);
  }

  /// START from the panel until the station runs. Pressed until the app
  /// reports the state, so a starved app cannot miss it; a link lost
  /// meanwhile (a timeout is short on a loaded machine) makes the app safe and
  /// ignores a button held across the reconnection, so then it is released
  /// and pressed again.
  void start_station() {
    for (int tries = 0; tries < 5; ++tries) {
      ASSERT_TRUE(node.child.send_line("press START"));
      std::string line;
      ASSERT_NO_FATAL_FAILURE(expect_any({" state moving", " link lost"}, 10s, &line));
      ASSERT_TRUE(node.child.send_line("release START"));
      // The first read after a reconnection shows the panel too.
      ASSERT_NO_FATAL_FAILURE(expect_line(" buttons none"));
      if (contains(line, " state moving")) return;
    }
    FAIL() << "the link was lost at every START:\n" << transcript_;
  }

 private:
  std::string transcript_;  ///< every app line seen, for a failure message
};

// The answers to the three FC 2B/0E attempts all arrive together, after the
// last attempt began; the next answers are 55 ms late. With the defaults (36 ms,
// 2 retries) the app verifies the gateway, runs its cycle (a START from the
// panel starts the station: the RUN command it writes lights the gateway's
// RUN LED) and stops cleanly.
TEST_F(PlantLateAnswer, LateAnswersAtStartAreNotFatal) {
  ASSERT_TRUE(injector.start(dir.path("gw"), dir.path("app"), LateAnswerInjector::Faults{}));
  ASSERT_TRUE(plant.start({MB2CO_PLANT, "--port", dir.path("app"), "--plain"})) << plant.error();

  ASSERT_NO_FATAL_FAILURE(expect_line(" link up " + dir.path("app") + " slave 1: mb2co mb2co gateway"));
  ASSERT_NO_FATAL_FAILURE(expect_line(" buttons none"));
  // Meant: all three; on a loaded machine the injector may release early.
  EXPECT_GE(injector.most_in_one_write(), 2) << "no late answer came with another one";

  // The normal cycle: the panel's START is read, the controller runs, the RUN
  // command it writes reaches the gateway.
  ASSERT_NO_FATAL_FAILURE(start_station());
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
  // The late answers cost attempts (counted, not hidden).
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

/// A slave on a pty of its own (`link`) that answers every 7-byte request (an
/// FC 2B/0E) with `answer`, `delay` after it.
class ScriptedSlave {
 public:
  ~ScriptedSlave() {
    done_ = true;
    if (thread_.joinable()) thread_.join();
    if (master_ >= 0) ::close(master_);
  }
  bool start(const std::string& link, mb2co::test::Bytes answer, std::chrono::milliseconds delay) {
    master_ = posix_openpt(O_RDWR | O_NOCTTY);
    if (master_ < 0 || grantpt(master_) != 0 || unlockpt(master_) != 0) return false;
    if (::symlink(ptsname(master_), link.c_str()) != 0) return false;
    thread_ = std::thread([this, answer, delay] {
      uint8_t request[7];
      while (!done_) {
        if (!mb2co::test::read_exact(master_, request, sizeof request, 100ms)) continue;
        std::this_thread::sleep_for(delay);  // the fault: an answer this late
        if (::write(master_, answer.data(), answer.size()) < 0) break;
      }
    });
    return true;
  }

 private:
  int master_ = -1;
  std::thread thread_;
  std::atomic<bool> done_{false};
};

/// An FC 2B/0E answer of slave 1 with this vendor.
mb2co::test::Bytes device_id_answer(const std::string& vendor) {
  mb2co::test::Bytes adu = {0x01, 0x2B, 0x0E, 0x01, 0x01,
                            0x00, 0x00, 0x03, 0x00, static_cast<uint8_t>(vendor.size())};
  adu.insert(adu.end(), vendor.begin(), vendor.end());
  for (const uint8_t b : mb2co::test::Bytes{0x01, 0x01, 'x', 0x02, 0x01, '1'}) adu.push_back(b);
  return mb2co::test::with_crc(adu);
}

// A slave that answers FC 2B/0E as another vendor's device is definitely not
// a gateway: one line on stderr, exit 1, at the first connection.
TEST(PlantIdentification, AnotherVendorEndsTheProgram) {
  mb2co::test::TempDir dir;
  ScriptedSlave slave;
  ASSERT_TRUE(slave.start(dir.path("app"), device_id_answer("acme"), 0ms));
  mb2co::test::LineChild plant;
  ASSERT_TRUE(plant.start({MB2CO_PLANT, "--port", dir.path("app"), "--plain"})) << plant.error();
  EXPECT_EQ(plant.wait_exit(10s), 1);
  EXPECT_EQ(plant.stderr_text(),
            "mb2co-plant: " + dir.path("app") + ": slave 1 is not an mb2co gateway (vendor 'acme')\n");
}

// Answers later than every attempt (150 ms, timeout 100 ms, no retry): silence
// in the attempts, but the late answer is heard, so the supervisor retries
// instead of taking the port for empty.
TEST(PlantIdentification, AnswerLaterThanEveryAttemptIsHeard) {
  mb2co::test::TempDir dir;
  ScriptedSlave slave;
  ASSERT_TRUE(slave.start(dir.path("app"), device_id_answer("mb2co"), 150ms));
  mb2co::pcapp::ModbusLink link;
  mb2co::pcapp::LinkSettings settings;
  settings.path = dir.path("app");
  settings.timeout_ms = 100;
  settings.retries = 0;
  ASSERT_TRUE(link.open(settings));
  std::string identity;
  const mb2co::pcapp::LinkResult r = link.identify(identity);
  EXPECT_EQ(r.outcome, mb2co::pcapp::LinkStatus::kFailed);
  EXPECT_TRUE(r.heard);
  EXPECT_EQ(r.status.message(), "FC 2B/0E: answer later than 100 ms");
  // The late answer was dropped, not left for the next request.
  EXPECT_GT(link.stale_bytes_dropped(), 0u);
  settings.timeout_ms = 1000;  // now in time
  ASSERT_TRUE(link.open(settings));
  EXPECT_TRUE(link.identify(identity).ok());
  EXPECT_EQ(identity, "mb2co x 1");
}

}  // namespace
