"""Starts tests/modbus/pty_slave and waits for its "ready <path>" line.

Register layout served (tests/modbus/support/test_layout.h):
  slave address 1; coils 0..2047 (all 0); discrete inputs 0..2047 (i % 3 == 0);
  input registers 0..255 (0x1000 + i); holding registers 0..255 (0), of which
  100..109 read-only (0xA000 + i, write -> exception 02), 110..119 accept
  values <= 1000 (else 04); input register 200 fails to read (04);
  coil 2047 rejects ON (04).
"""
import selectors
import subprocess
import sys

READY_TIMEOUT_S = 10


class SlaveRunner:
    def __init__(self, program, *args):
        self.proc = subprocess.Popen([program, *args], stdin=subprocess.PIPE,
                                     stdout=subprocess.PIPE, text=True)
        sel = selectors.DefaultSelector()
        sel.register(self.proc.stdout, selectors.EVENT_READ)
        if not sel.select(READY_TIMEOUT_S):
            self.proc.kill()
            sys.exit("pty_slave printed no ready line")
        words = self.proc.stdout.readline().split()
        if len(words) != 2 or words[0] != "ready":
            self.proc.kill()
            sys.exit("pty_slave: unexpected first line %r" % words)
        self.device = words[1]

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.proc.stdin.close()  # end of stdin: the slave exits
        rc = self.proc.wait(timeout=10)
        self.proc.stdout.close()
        if rc != 0 and exc[0] is None:
            raise AssertionError("pty_slave exited with %d" % rc)
