#!/usr/bin/python3
"""The line, live: N stations of mb2co-node + mb2co-plant (or N real gateways
behind serial ports), the stop2 scenario of seed 000 §10, checked from the
stations' own reports. docs/mini-project.md explains it for students.

usage: run-line.sh [--stations N] [--can IFACE] [--topology ring|chain]
                   [--stop2-at K] [--serial DEV1,DEV2,...] [--bin DIR]
                   [--node PATH] [--plant PATH] [--uno [PATH]] [--timeout S] [--keep] [--verbose]

Exit status: 0 every check passed; 1 a check failed (one line on stderr naming
it; the processes' output is kept in a directory named there); 2 bad command
line (one line on stderr).
"""
import argparse
import os
import shutil
import signal
import sys
import time

from hw_line import HardwareLine
from live_procs import Failure
from sim_line import SimulatedLine
from uno_line import UnoLine

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


class OneLineParser(argparse.ArgumentParser):
    """A bad command line is one line on stderr and exit 2."""

    def error(self, message):
        sys.stderr.write(f"run-line: {message} (try --help)\n")
        sys.exit(2)


def parse_args(argv):
    p = OneLineParser(prog="run-line.sh", description="The line live: stop2 scenario, checked.")
    p.add_argument("--stations", type=int, default=None, help="stations (2..127; default 3, or one per --serial port)")
    p.add_argument("--can", default=None, help="CAN interface of the simulated stations (default vcan0)")
    p.add_argument("--topology", choices=("ring", "chain"), default="ring")
    p.add_argument("--stop2-at", type=int, default=1, metavar="K", help="station whose STOP2 is pressed (default 1)")
    p.add_argument("--serial", default=None, metavar="DEV1,DEV2,...",
                   help="real gateways on these ports, in station order: only the plants run here")
    p.add_argument("--bin", default=os.path.join(ROOT, "build"), metavar="DIR", help="build directory (default build/)")
    p.add_argument("--node", default=None, help="mb2co-node (default DIR/firmware/linux/node/mb2co-node)")
    p.add_argument("--plant", default=None, help="mb2co-plant (default DIR/pcapp/plant/mb2co-plant)")
    p.add_argument("--uno", nargs="?", const="", default=None, metavar="PATH",
                   help="simulated Unos (mb2co-uno, default DIR/hil/uno/mb2co-uno) instead of mb2co-node, each "
                        "given its place over Modbus as docs/mini-project.md says, the plants at their defaults")
    p.add_argument("--plant-defaults", action="store_true",
                   help="the plants at their documented defaults (25 ms timeout, 2 retries) instead of "
                        "500 ms and 3 retries, which keep a loaded machine from losing a link")
    p.add_argument("--timeout", type=float, default=None, metavar="S",
                   help="limit of each wait (default 10 s; 30 s with --uno, 60 s with --serial)")
    p.add_argument("--keep", action="store_true", help="keep the directory with ptys and logs")
    p.add_argument("--verbose", action="store_true", help="echo every line of every process on stderr")
    a = p.parse_args(argv)

    def bad(msg):
        sys.stderr.write(f"run-line: {msg}\n")
        sys.exit(2)

    if a.uno is not None and a.serial is not None:
        bad("--uno and --serial exclude each other (--uno simulates the boards that --serial reaches)")
    if a.serial is not None:
        if a.can is not None:
            bad("--can and --serial exclude each other (with --serial the gateways are on the ports)")
        a.ports = [s for s in a.serial.split(",") if s]
        if not a.ports:
            bad("--serial wants a comma-separated list of ports")
        if a.stations is not None and a.stations != len(a.ports):
            bad(f"--stations {a.stations} but {len(a.ports)} ports")
        a.stations = len(a.ports)
    if a.stations is None:
        a.stations = 3
    if a.can is None:
        a.can = "vcan0"
    if a.can == "none":
        bad("--can none: the line needs a CAN interface")
    if not 2 <= a.stations <= 127:
        bad(f"--stations {a.stations}: want 2..127")
    if not 1 <= a.stop2_at <= a.stations:
        bad(f"--stop2-at {a.stop2_at}: want 1..{a.stations}")
    if a.timeout is None:
        # Simulated Unos run at most at real time, slower on a loaded host.
        a.timeout = 60.0 if a.serial is not None else 30.0 if a.uno is not None else 10.0
    if not a.timeout > 0:
        bad(f"--timeout {a.timeout:g}: want > 0")
    if a.uno is not None:
        a.uno = a.uno or os.path.join(a.bin, "hil", "uno", "mb2co-uno")
        if not shutil.which("mbpoll"):
            bad("--uno gives each board its place with mbpoll: install it (scripts/deps.sh)")
    a.node = a.node or os.path.join(a.bin, "firmware", "linux", "node", "mb2co-node")
    a.plant = a.plant or os.path.join(a.bin, "pcapp", "plant", "mb2co-plant")
    programs = [a.plant] if a.serial is not None else [a.uno, a.plant] if a.uno is not None else [a.node, a.plant]
    for path in programs:
        if not os.access(path, os.X_OK):
            bad(f"{path}: no such program (build it: scripts/build.sh, or give --bin DIR)")
    return a


def main(argv):
    a = parse_args(argv)
    run = HardwareLine(a) if a.serial is not None else UnoLine(a) if a.uno is not None else SimulatedLine(a)
    # SIGTERM/SIGINT end the run through the cleanup below.
    signal.signal(signal.SIGTERM, lambda *_: sys.exit(143))
    ok = False
    try:
        run.run()
        ok = True
        print(f"PASS in {time.monotonic() - run.t0:.1f} s", flush=True)
    except Failure as f:
        sys.stdout.flush()
        sys.stderr.write(f"run-line: FAIL: {f} (output of every process in {run.tmp})\n")
    except KeyboardInterrupt:
        sys.stderr.write(f"run-line: interrupted (output of every process in {run.tmp})\n")
    finally:
        run.pump.kill_all()
        run.save_logs()
        if ok and not a.keep:
            shutil.rmtree(run.tmp, ignore_errors=True)
        elif ok:
            print(f"kept {run.tmp}")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
