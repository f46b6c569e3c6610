// mb2co-plant --tcp HOST:PORT (a station's PC over Modbus/TCP): the address
// is read, the unit id is 255 unless --slave says otherwise, and the serial
// line's options are refused with it, one line each.
#include <gtest/gtest.h>

#include "options.h"

namespace mb2co {
namespace pcapp {
namespace {

Status parse(QStringList args, AppOptions& o) {
  args.prepend("mb2co-plant");
  return parse_options(args, o);
}

TEST(PlantTcpOptions, TheAddressAndTheUnitId) {
  AppOptions o;
  ASSERT_TRUE(parse({"--tcp", "192.0.2.5:1502"}, o));
  EXPECT_TRUE(o.on_tcp);
  EXPECT_EQ(o.tcp.text(), "192.0.2.5:1502");
  EXPECT_EQ(o.slave, 255) << "a server addressed by its IP address";
  AppOptions bare;
  ASSERT_TRUE(parse({"latency", "--tcp", "1502", "--slave", "3"}, bare));
  EXPECT_EQ(bare.tcp.text(), "127.0.0.1:1502") << "localhost unless told";
  EXPECT_EQ(bare.slave, 3);
  AppOptions serial;
  ASSERT_TRUE(parse({"--port", "/dev/ttyACM0"}, serial));
  EXPECT_FALSE(serial.on_tcp);
  EXPECT_EQ(serial.slave, 1);
}

TEST(PlantTcpOptions, TheSerialLinesOptionsAreRefusedWithIt) {
  const struct {
    QStringList args;
    const char* says;
  } cases[] = {
      {{"--tcp", "1502", "--port", "/dev/ttyACM0"}, "--port is the serial line's: not with --tcp"},
      {{"--tcp", "1502", "--baud", "9600"}, "--baud is the serial line's: not with --tcp"},
      {{"--tcp", "1502", "--parity", "E"}, "--parity is the serial line's: not with --tcp"},
      {{"--tcp", "1502", "--list-ports"}, "--list-ports is the serial line's: not with --tcp"},
      {{"--tcp", "host:0"}, "--tcp host:0: port 0 is outside 1..65535"},
      {{"--tcp", "host:"}, "--tcp host:: want HOST:PORT, [IPV6]:PORT or PORT"},
  };
  for (const auto& c : cases) {
    AppOptions o;
    const Status s = parse(c.args, o);
    EXPECT_FALSE(s) << c.args.join(' ').toStdString();
    EXPECT_EQ(s.message(), c.says);
  }
}

}  // namespace
}  // namespace pcapp
}  // namespace mb2co
