"""Independent peer: mbpoll (Debian) reads and writes our slave on a pty.

Usage: mbpoll_peer_test.py PTY_SLAVE MBPOLL
"""
import re
import subprocess
import sys
import unittest

from slave_runner import SlaveRunner

PTY_SLAVE, MBPOLL = sys.argv[1], sys.argv[2]


class MbpollPeer(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.slave = SlaveRunner(PTY_SLAVE)

    @classmethod
    def tearDownClass(cls):
        cls.slave.__exit__(None, None, None)

    def mbpoll(self, *args):
        cmd = [MBPOLL, "-m", "rtu", "-b", "115200", "-P", "none", "-a", "1", "-0",
               "-1", "-o", "1", *args[:-1], self.slave.device, *args[-1]]
        return subprocess.run(cmd, capture_output=True, text=True, timeout=30)

    def read(self, table, ref, count):
        r = self.mbpoll("-t", table, "-r", str(ref), "-c", str(count), [])
        self.assertEqual(r.returncode, 0, r.stderr)
        values = re.findall(r"^\[(\d+)\]:\s+(\S+)", r.stdout, re.M)
        self.assertEqual([int(a) for a, _ in values], list(range(ref, ref + count)))
        return [v for _, v in values]

    def write(self, table, ref, *values):
        r = self.mbpoll("-t", table, "-r", str(ref), [str(v) for v in values])
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("Written %d references" % len(values), r.stdout)

    def test_holding_registers_written_and_read_back(self):
        self.write("4", 10, 1234, 5678)    # FC 10
        self.write("4", 12, 42)            # one value
        self.assertEqual(self.read("4", 10, 3), ["1234", "5678", "42"])

    def test_coils_written_and_read_back(self):
        self.write("0", 5, 1, 0, 1)
        self.assertEqual(self.read("0", 5, 3), ["1", "0", "1"])

    def test_inputs(self):
        self.assertEqual(self.read("1", 0, 6), ["1", "0", "0", "1", "0", "0"])
        self.assertEqual(self.read("3:hex", 5, 2), ["0x1005", "0x1006"])

    def test_exceptions_reported(self):
        r = self.mbpoll("-t", "4", "-r", "100", ["1"])  # read-only register
        self.assertNotEqual(r.returncode, 0)
        self.assertIn("Illegal data address", r.stderr)
        r = self.mbpoll("-t", "3", "-r", "200", "-c", "1", [])
        self.assertNotEqual(r.returncode, 0)
        self.assertIn("Slave device or server failure", r.stderr)
        r = self.mbpoll("-t", "4", "-r", "110", ["1001"])  # above the limit
        self.assertIn("Slave device or server failure", r.stderr)
        r = self.mbpoll("-u", [])  # FC 11 report slave id: not supported
        self.assertIn("Illegal function", r.stderr)


if __name__ == "__main__":
    unittest.main(argv=[sys.argv[0]], verbosity=2)
