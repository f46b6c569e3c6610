// ModbusLink against the real gateway firmware (mb2co-node on a pty), and
// the signal self-pipe.
#include <gtest/gtest.h>
#include <signal.h>

#include <QCoreApplication>
#include <QElapsedTimer>

#include "modbus_link.h"
#include "node_harness.h"
#include "signal_pipe.h"

using mb2co::Status;
using namespace mb2co::pcapp;

namespace {
struct LinkTest : ::testing::Test {
  mb2co::test::TempDir dir;
  mb2co::test::NodeProcess node;  // mb2co-node --can none on a pty in `dir`
  ModbusLink link;
  RegisterLayout layout = default_layout();
  TransactionPlan plan;
  RegisterImage in, out;
  std::string error;  ///< why the last transaction passed to outcome() failed

  LinkStatus outcome(const LinkResult& result) {
    error = result.status.message();
    return result.outcome;
  }

  void SetUp() override {
    ASSERT_TRUE(node.start({"--can", "none", "--pty", dir.path("tty")})) << node.error();
    LinkSettings s;
    s.path = dir.path("tty");
    s.timeout_ms = 500;  // generous: a loaded test machine must not fail the link
    s.retries = 2;
    const Status opened = link.open(s);
    ASSERT_TRUE(opened) << opened.message();
    ASSERT_TRUE(
        plan_transactions(layout, {Field::kRunState, Field::kNmtState}, {}, {Field::kRunCommand}, plan));
    in.resize(plan);
    out.resize(plan);
  }
};
}  // namespace

TEST_F(LinkTest, IdentifiesTheGateway) {
  std::string id;
  ASSERT_EQ(outcome(link.identify(id)), LinkStatus::kOk) << error;
  EXPECT_EQ(id, "mb2co mb2co gateway 0.1.0");
}

TEST_F(LinkTest, WriteThenReadTheFirmwareRunState) {
  ASSERT_EQ(outcome(link.read(plan, out, in)), LinkStatus::kOk) << error;
  EXPECT_EQ(in.get(layout, Field::kRunState), 0u);
  const uint32_t nmt = in.get(layout, Field::kNmtState);
  EXPECT_TRUE(nmt == 127 || nmt == 5) << nmt;  // pre-operational, operational by itself soon (2000h/8)
  out.put(layout, Field::kRunCommand, 1);
  ASSERT_EQ(outcome(link.write(plan, out)), LinkStatus::kOk) << error;
  ASSERT_EQ(outcome(link.read(plan, out, in)), LinkStatus::kOk) << error;
  EXPECT_EQ(in.get(layout, Field::kRunState), 1u);
}

TEST_F(LinkTest, ReadWriteInOneTransaction) {
  TransactionPlan rw = plan;
  rw.read_write = true;
  rw.reads = {Block{RegTable::kHolding, 0, 2}};
  rw.writes = {Block{RegTable::kHolding, 0, 1}};
  out.put(layout, Field::kRunCommand, 1);
  ASSERT_EQ(outcome(link.read(rw, out, in)), LinkStatus::kOk) << error;
  EXPECT_EQ(in.regs[0][0], 1);  // FC 17h writes before it reads
  out.put(layout, Field::kRunCommand, 0);
  ASSERT_EQ(outcome(link.read(rw, out, in)), LinkStatus::kOk) << error;
  EXPECT_EQ(in.regs[0][0], 0);
}

TEST_F(LinkTest, RefusedValueIsAnExceptionNotALostLink) {
  out.put(layout, Field::kRunCommand, 2);  // 2100h/1 accepts 0..1
  EXPECT_EQ(outcome(link.write(plan, out)), LinkStatus::kException);
  EXPECT_NE(error.find("FC 06"), std::string::npos);
  out.put(layout, Field::kRunCommand, 0);
  EXPECT_EQ(outcome(link.write(plan, out)), LinkStatus::kOk) << error;
}

TEST_F(LinkTest, DeadGatewayIsALostLinkWithinTheRetries) {
  node.stop(SIGKILL);
  QElapsedTimer t;
  t.start();
  EXPECT_EQ(outcome(link.read(plan, out, in)), LinkStatus::kFailed);
  EXPECT_LE(t.elapsed(), 3 * 500 + 500);  // (retries + 1) x timeout, plus slack
  std::string id;
  EXPECT_EQ(outcome(link.identify(id)), LinkStatus::kFailed);
}

TEST(SignalPipe, SignalArrivesInTheEventLoop) {
  int argc = 1;
  char name[] = "test";
  char* argv[] = {name, nullptr};
  QCoreApplication app(argc, argv);
  SignalPipe pipe({SIGUSR1});
  ASSERT_TRUE(pipe.ok());
  int got = 0;
  QObject::connect(&pipe, &SignalPipe::received, [&](int s) { got = s; });
  ::raise(SIGUSR1);
  QElapsedTimer t;
  t.start();
  while (got == 0 && t.elapsed() < 10000) QCoreApplication::processEvents(QEventLoop::WaitForMoreEvents, 100);
  EXPECT_EQ(got, SIGUSR1);
  signal(SIGUSR1, SIG_DFL);
}
