#!/usr/bin/env python3
"""hil/uml/run-with-vcan.sh --shell typed at as a user would (docs/labs.md,
"Setup"): through a pseudo-terminal, one line at a time, each answer read
from the screen before the next line is typed; `exit` must end the session
with the shell's status and give the terminal back as it was.

Usage: run_with_vcan_shell_test.py RUN_WITH_VCAN BUILD_DIR [--shell-arg ...]
"""
import os
import re
import select
import subprocess
import sys
import termios
import time

ANSWER_DEADLINE_S = 120  # bounds a failure only (a UML boot on a loaded host)


class Screen:
    """What the program behind the pty's master has written so far."""

    def __init__(self, fd):
        self.fd = fd
        self.text = ""
        self.seen = 0  # text before it was matched by an earlier expect()

    def expect(self, pattern, what):
        rx = re.compile(pattern)
        end = time.monotonic() + ANSWER_DEADLINE_S
        while True:
            m = rx.search(self.text, self.seen)
            if m:
                self.seen = m.end()
                return m
            left = end - time.monotonic()
            if left <= 0:
                raise SystemExit(f"FAIL: no {what} within {ANSWER_DEADLINE_S} s; the screen ends with:\n"
                                 + self.text[-1500:])
            ready, _, _ = select.select([self.fd], [], [], left)
            if ready:
                try:
                    chunk = os.read(self.fd, 4096)
                except OSError:  # EIO: every writer of the slave is gone
                    chunk = b""
                if not chunk:
                    raise SystemExit(f"FAIL: the terminal closed before {what}; the screen:\n" + self.text[-1500:])
                self.text += chunk.decode("utf-8", "replace")

    def type(self, line):
        os.write(self.fd, (line + "\r").encode())


def main():
    run, build = sys.argv[1], sys.argv[2]
    master, slave = os.openpty()
    before = termios.tcgetattr(slave)
    # No command and a terminal on stdin: the shell is the default.
    proc = subprocess.Popen([run, "--build", build], stdin=slave, stdout=slave, stderr=slave,
                            start_new_session=True)
    screen = Screen(master)
    prompt = r"\(vcan\) [^\r\n]*[$#] $"
    screen.expect(r"a shell with vcan0 up; 'exit' ends it", "greeting naming vcan0")
    screen.expect(prompt, "first prompt")

    screen.type("ip link show vcan0")
    screen.expect(r"vcan0: <NOARP,UP,LOWER_UP> mtu 72 [^\n]*\n\s+link/can", "vcan0 up in `ip link`")
    screen.expect(prompt, "prompt after ip")

    # The build's programs are on PATH: found by name, no path typed.
    screen.type("mb2co-node --version")
    screen.expect(r"mb2co-node \d+\.\d+\.\d+", "mb2co-node's version")
    screen.expect(prompt, "prompt after --version")
    screen.type("mb2co-node --help | head -n 1")
    screen.expect(r"usage: mb2co-node ", "mb2co-node's usage line")
    screen.expect(prompt, "prompt after --help")

    # The guest's tty does the line editing: a line erased with Ctrl-U is not run.
    os.write(master, b"echo wrong\x15")
    screen.type("echo typed-$((6 * 7))")
    screen.expect(r"typed-42\r?\n", "the edited line's answer")
    if "wrong" in screen.text[screen.seen:]:
        raise SystemExit("FAIL: the erased line was run")
    screen.expect(prompt, "prompt after echo")

    screen.type("exit 3")
    try:
        rc = proc.wait(timeout=ANSWER_DEADLINE_S)
    except subprocess.TimeoutExpired:
        proc.kill()
        raise SystemExit("FAIL: `exit` did not end the session; the screen:\n" + screen.text[-1500:])
    if rc != 3:
        raise SystemExit(f"FAIL: exit status {rc}, want the shell's 3")
    after = termios.tcgetattr(slave)
    if after != before:
        raise SystemExit(f"FAIL: terminal modes not restored: {before} -> {after}")
    print("PASS: shell on the terminal, vcan0 up, the build's programs on PATH, exit status passed on")
    return 0


if __name__ == "__main__":
    sys.exit(main())
