// SDO server transfers (CiA 301 §7.2.4.3): expedited and segmented upload and
// download, byte for byte, on the I/O node (node id 3).
#include <gtest/gtest.h>

#include "test_fixture.h"

namespace mb2co {
namespace test {
namespace {

using SdoServer = IoNodeTest;

TEST_F(SdoServer, ExpeditedUploadStatesTheSizeOfShortValues) {
  EXPECT_EQ(to_string(h.sdo({0x40, 0x00, 0x10, 0x00})), "<583> 42 00 10 00 91 01 03 00");
  ASSERT_EQ(h.write_u16(0x1017, 0, 0x1234), 0u);
  EXPECT_EQ(to_string(h.sdo({0x40, 0x17, 0x10, 0x00})), "<583> 4B 17 10 00 34 12 00 00");
  EXPECT_EQ(to_string(h.sdo({0x40, 0x01, 0x10, 0x00})), "<583> 4F 01 10 00 00 00 00 00");
  // Bytes 4..7 of an upload request are reserved: whatever they hold, same answer.
  EXPECT_EQ(to_string(h.sdo({0x40, 0x18, 0x10, 0x02, 0xAA, 0xBB, 0xCC, 0xDD})),
            "<583> 42 18 10 02 01 04 00 00");
}

TEST_F(SdoServer, ExpeditedDownloadWithSizeIndicated) {
  EXPECT_EQ(to_string(h.sdo({0x2B, 0x01, 0x21, 0x00, 0x2A, 0x00, 0x00, 0x00})),
            "<583> 60 01 21 00 00 00 00 00");
  EXPECT_EQ(value(0x2101, 0), 42u);
  EXPECT_EQ(to_string(h.sdo({0x2F, 0x0D, 0x10, 0x00, 0x07, 0xEE, 0xEE, 0xEE})),
            "<583> 60 0D 10 00 00 00 00 00");
  EXPECT_EQ(value(0x100D, 0), 7u);  // the unused bytes were not taken
  EXPECT_EQ(to_string(h.sdo({0x23, 0x06, 0x10, 0x00, 0x10, 0x27, 0x00, 0x00})),
            "<583> 60 06 10 00 00 00 00 00");
  EXPECT_EQ(value(0x1006, 0), 10000u);
}

TEST_F(SdoServer, ExpeditedDownloadWithoutSizeTakesTheObjectsOwnSize) {
  // e = 1, s = 0: the size is unspecified; a U16 takes two bytes.
  EXPECT_EQ(to_string(h.sdo({0x22, 0x01, 0x21, 0x00, 0x64, 0x00, 0xFF, 0xFF})),
            "<583> 60 01 21 00 00 00 00 00");
  EXPECT_EQ(value(0x2101, 0), 100u);
  EXPECT_EQ(to_string(h.sdo({0x22, 0x06, 0x10, 0x00, 0x01, 0x02, 0x03, 0x04})),
            "<583> 60 06 10 00 00 00 00 00");
  EXPECT_EQ(value(0x1006, 0), 0x04030201u);
}

TEST_F(SdoServer, ExpeditedDownloadOfAShortString) {
  EXPECT_EQ(to_string(h.sdo({0x27, 0x00, 0x20, 0x00, 'a', 'b', 'c', 'X'})), "<583> 60 00 20 00 00 00 00 00");
  EXPECT_EQ(h.read_string(0x2000, 0), "abc");
  // Reads back expedited with 3 bytes indicated (0x47).
  EXPECT_EQ(to_string(h.sdo({0x40, 0x00, 0x20, 0x00})), "<583> 47 00 20 00 61 62 63 00");
}

TEST_F(SdoServer, SegmentedUploadOfTheDeviceName) {
  // 1008h "mb2co I/O node": 14 bytes, two full segments, the second one last.
  EXPECT_EQ(to_string(h.sdo({0x40, 0x08, 0x10, 0x00})), "<583> 41 08 10 00 0E 00 00 00");
  EXPECT_EQ(to_string(h.sdo({0x60})), "<583> 00 6D 62 32 63 6F 20 49");  // "mb2co I"
  EXPECT_EQ(to_string(h.sdo({0x70})), "<583> 11 2F 4F 20 6E 6F 64 65");  // "/O node", c = 1
  // The transfer is over: another segment request is out of sequence.
  EXPECT_EQ(to_string(h.sdo({0x60})), abort_frame(kId, 0x1008, 0, canopen::kAbortCommand));
}

TEST_F(SdoServer, SegmentedUploadMarksUnusedBytesOfTheLastSegment) {
  ASSERT_EQ(h.download_segmented(0x2000, 0, bytes_of("0123456789ABCDEFGHIJ"), true), 0u);  // 20
  EXPECT_EQ(to_string(h.sdo({0x40, 0x00, 0x20, 0x00})), "<583> 41 00 20 00 14 00 00 00");
  EXPECT_EQ(to_string(h.sdo({0x60})), "<583> 00 30 31 32 33 34 35 36");
  EXPECT_EQ(to_string(h.sdo({0x70})), "<583> 10 37 38 39 41 42 43 44");
  // 6 bytes left: n = 1 unused byte, c = 1, toggle 0.
  EXPECT_EQ(to_string(h.sdo({0x60})), "<583> 03 45 46 47 48 49 4A 00");
}

TEST_F(SdoServer, SegmentedUploadOfAnEmptyStringSendsOneEmptyLastSegment) {
  EXPECT_EQ(to_string(h.sdo({0x40, 0x00, 0x20, 0x00})), "<583> 41 00 20 00 00 00 00 00");
  EXPECT_EQ(to_string(h.sdo({0x60})), "<583> 0F 00 00 00 00 00 00 00");
}

TEST_F(SdoServer, SegmentedUploadIsASnapshot) {
  ASSERT_EQ(h.download(0x2000, 0, bytes_of("first value, 20 bytes")), 0u);
  EXPECT_EQ(to_string(h.sdo({0x40, 0x00, 0x20, 0x00})), "<583> 41 00 20 00 15 00 00 00");
  EXPECT_EQ(to_string(h.sdo({0x60})), "<583> 00 66 69 72 73 74 20 76");
  // The application changes the value in between (locally, no SDO).
  const uint16_t row = od().find(0x2000, 0);
  memcpy(od().ram(row), "XXXXXXXXXXXXXXXXXXXXX", 21);
  EXPECT_EQ(to_string(h.sdo({0x70})), "<583> 10 61 6C 75 65 2C 20 32");
  EXPECT_EQ(to_string(h.sdo({0x60})), "<583> 01 30 20 62 79 74 65 73");
}

TEST_F(SdoServer, SegmentedDownloadWithSizeIndicatedAndReadBack) {
  const std::string label = "Station 4: filler";  // 17 bytes: 7 + 7 + 3
  EXPECT_EQ(to_string(h.sdo({0x21, 0x00, 0x20, 0x00, 17, 0, 0, 0})), "<583> 60 00 20 00 00 00 00 00");
  EXPECT_EQ(to_string(h.sdo({0x00, 'S', 't', 'a', 't', 'i', 'o', 'n'})), "<583> 20 00 00 00 00 00 00 00");
  EXPECT_EQ(to_string(h.sdo({0x10, ' ', '4', ':', ' ', 'f', 'i', 'l'})), "<583> 30 00 00 00 00 00 00 00");
  EXPECT_EQ(text(0x2000, 0), "") << "nothing is stored before the last segment";
  EXPECT_EQ(to_string(h.sdo({0x09, 'l', 'e', 'r', 0, 0, 0, 0})), "<583> 20 00 00 00 00 00 00 00");
  EXPECT_EQ(h.read_string(0x2000, 0), label);
}

TEST_F(SdoServer, SegmentedDownloadWithoutSizeIndicationAndReadBack) {
  const std::string label = "a label of 24 characters";
  ASSERT_EQ(label.size(), 24u);
  EXPECT_EQ(h.download_segmented(0x2000, 0, bytes_of(label), false), 0u);
  EXPECT_EQ(h.read_string(0x2000, 0), label);
  // A shorter text replaces it completely (no tail of the old one).
  EXPECT_EQ(h.download_segmented(0x2000, 0, bytes_of("short one"), false), 0u);
  EXPECT_EQ(h.read_string(0x2000, 0), "short one");
  Bytes raw;
  ASSERT_EQ(h.upload(0x2000, 0, &raw), 0u);
  EXPECT_EQ(raw.size(), 9u);
}

TEST_F(SdoServer, SegmentedDownloadOfANumberWorks) {
  EXPECT_EQ(h.download_segmented(0x1006, 0, {0x40, 0x42, 0x0F, 0x00}, true), 0u);
  EXPECT_EQ(value(0x1006, 0), 1000000u);
  EXPECT_EQ(h.download_segmented(0x2101, 0, {0x05, 0x00}, false), 0u);
  EXPECT_EQ(value(0x2101, 0), 5u);
}

TEST_F(SdoServer, ANewInitiateReplacesATransferInProgress) {
  EXPECT_EQ(to_string(h.sdo({0x21, 0x00, 0x20, 0x00, 10, 0, 0, 0})), "<583> 60 00 20 00 00 00 00 00");
  EXPECT_EQ(to_string(h.sdo({0x00, '1', '2', '3', '4', '5', '6', '7'})), "<583> 20 00 00 00 00 00 00 00");
  // The client starts over with an upload: served normally.
  EXPECT_EQ(to_string(h.sdo({0x40, 0x00, 0x10, 0x00})), "<583> 42 00 10 00 91 01 03 00");
  // The old download is gone.
  EXPECT_EQ(to_string(h.sdo({0x11, '8', '9', 'A', 0, 0, 0, 0})),
            abort_frame(kId, 0x1000, 0, canopen::kAbortCommand));
  EXPECT_EQ(h.read_string(0x2000, 0), "");
}

TEST_F(SdoServer, ClientAbortEndsTheTransferSilently) {
  EXPECT_EQ(to_string(h.sdo({0x21, 0x00, 0x20, 0x00, 10, 0, 0, 0})), "<583> 60 00 20 00 00 00 00 00");
  EXPECT_TRUE(h.sdo_exchange({0x80, 0x00, 0x20, 0x00, 0x00, 0x00, 0x04, 0x05}).empty());
  EXPECT_FALSE(io.node().nmt_state() == canopen::kNmtInitialising);
  // No timeout abort follows, and the next segment is out of sequence.
  h.run_us(3000000, 10000);
  EXPECT_EQ(h.take(), Frames({}));
  EXPECT_EQ(to_string(h.sdo({0x00, '1', '2', '3', '4', '5', '6', '7'})),
            abort_frame(kId, 0x2000, 0, canopen::kAbortCommand));
  EXPECT_EQ(h.read_string(0x2000, 0), "");
}

TEST_F(SdoServer, FramesThatAreNotEightBytesOrRtrAreIgnored) {
  const std::vector<Bytes> before = od_snapshot(od());
  for (uint8_t dlc = 0; dlc < 8; ++dlc) {
    CanFrame f = F(0x603, {0x23, 0x01, 0x21, 0x00, 0x05, 0x00, 0x00, 0x00});
    f.dlc = dlc;
    h.rx(f);
    f.data[0] = 0x40;
    h.rx(f);
  }
  h.rx(Rtr(0x603, 8));
  h.rx(Rtr(0x603, 0));
  EXPECT_EQ(h.take(), Frames({}));
  EXPECT_TRUE(od_snapshot(od()) == before);
  // Ignored frames do not disturb a transfer in progress.
  EXPECT_EQ(to_string(h.sdo({0x40, 0x08, 0x10, 0x00})), "<583> 41 08 10 00 0E 00 00 00");
  CanFrame shortseg = F(0x603, {0x70});
  h.rx(shortseg);
  EXPECT_EQ(to_string(h.sdo({0x60})), "<583> 00 6D 62 32 63 6F 20 49");
}

TEST_F(SdoServer, ExtendedFramesWithTheSdoIdAreNotOurs) {
  CanFrame f = F(0x603, {0x40, 0x00, 0x10, 0x00, 0, 0, 0, 0});
  f.flags = CanFrame::kExtended;
  h.rx(f);
  EXPECT_EQ(h.take(), Frames({}));
}

TEST_F(SdoServer, AnsweredInOperationalToo) {
  operational();
  EXPECT_EQ(to_string(h.sdo({0x40, 0x00, 0x10, 0x00})), "<583> 42 00 10 00 91 01 03 00");
  EXPECT_EQ(h.read_string(0x1008, 0), "mb2co I/O node");
}

TEST_F(SdoServer, SegmentedTransfersBeforeTheTimeoutSucceed) {
  // Each segment restarts the server timeout (1 s): 0.9 s gaps are fine.
  EXPECT_EQ(to_string(h.sdo({0x40, 0x08, 0x10, 0x00})), "<583> 41 08 10 00 0E 00 00 00");
  h.run_us(900000, 10000);
  EXPECT_EQ(to_string(h.sdo({0x60})), "<583> 00 6D 62 32 63 6F 20 49");
  h.run_us(900000, 10000);
  EXPECT_EQ(to_string(h.sdo({0x70})), "<583> 11 2F 4F 20 6E 6F 64 65");
  h.run_us(2000000, 10000);
  EXPECT_EQ(h.take(), Frames({}));
}

TEST_F(SdoServer, ReadsOfTheIdentityAndCommunicationDefaults) {
  EXPECT_EQ(h.read(0x1018, 0), 4u);
  EXPECT_EQ(h.read(0x1018, 1), 0u);
  EXPECT_EQ(h.read(0x1018, 2), 0x401u);
  EXPECT_EQ(h.read(0x1018, 3), 1u);
  EXPECT_EQ(h.read(0x1200, 1), 0x603u);
  EXPECT_EQ(h.read(0x1200, 2), 0x583u);
  EXPECT_EQ(h.read(0x1014, 0), 0x83u);
  EXPECT_EQ(h.read(0x1005, 0), 0x80u);
  EXPECT_EQ(h.read_string(0x1009, 0), "1.0");
  EXPECT_EQ(h.read_string(0x100A, 0), "0.1.0");
  EXPECT_EQ(h.read(0x0007, 0), 32u);  // data type entries hold their bit length
  EXPECT_EQ(h.read(0x0001, 0), 1u);
}

}  // namespace
}  // namespace test
}  // namespace mb2co
