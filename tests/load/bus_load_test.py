#!/usr/bin/python3
"""mb2co-node under a full bus (issue 16 item 10), run inside hil/uml/run-with-vcan.sh.

A cangen flood of frames the node does not consume (~10 k frames/s) plus
SYNC frames (consumed) at 100 Hz share vcan0 with the node for some
seconds while this script sends SDO upload requests (1000h) one after the
other. candump -L records the bus. Passes when:
  * every heartbeat interval of the node during the flood lies within
    90..110 ms (period 100 ms: 1017h as the node derives it), candump's
    kernel timestamps;
  * every SDO upload request is answered (scs 2, index 1000h) within 1 s;
  * the flood really was a flood (the rate is printed, and must reach
    --min-rate frames/s as candump counted them).
Prints the node's CPU time over the flood (utime+stime from /proc), the
rates and the interval range: the numbers of docs/performance.md "Bus load".
Usage: bus_load_test.py MB2CO_NODE [--seconds S] [--gap-ms G] [--burst N] [--min-rate R]
                        [--sdo-per-s R]
"""
import argparse
import os
import subprocess
import sys
import tempfile
import time

import can

IFACE = "vcan0"
NODE_ID = 5
HB_ID = 0x700 + NODE_ID
PERIOD_MS = 100.0
TOLERANCE = 0.10
# A heartbeat due at phase + k x period leaves at most this late (10 % of the
# period: then every interval lies within 90..110 ms).
LATE_MS = PERIOD_MS * TOLERANCE


def fail(msg):
    print("FAIL: " + msg, flush=True)
    sys.exit(1)


def wait_line(proc, want, what):
    """Reads proc's stdout until a line starting with `want` (blocking read: waits for a line)."""
    for line in proc.stdout:
        if line.startswith(want):
            return line
    fail(what + " ended before printing " + want)


def logged(log, text, send):
    """Calls send() and checks candump's log for `text` until it is there (60 s at most)."""
    end = time.monotonic() + 60.0
    while time.monotonic() < end:
        send()
        with open(log) as f:
            if text in f.read():
                return True
        time.sleep(0.05)  # a poll interval: the condition is checked again
    return False


def cpu_ticks(pid):
    with open("/proc/%d/stat" % pid) as f:
        fields = f.read().rsplit(")", 1)[1].split()
    return int(fields[11]) + int(fields[12])  # utime, stime (fields 14, 15)


def wakeups(pid):
    """Voluntary context switches: how often the process went to sleep."""
    with open("/proc/%d/status" % pid) as f:
        for line in f:
            if line.startswith("voluntary_ctxt_switches:"):
                return int(line.split()[1])
    return 0


def sdo_upload(bus, timeout_s):
    """One expedited upload of 1000h/0; True when the node answered it."""
    bus.send(can.Message(arbitration_id=0x600 + NODE_ID, is_extended_id=False,
                         data=[0x40, 0x00, 0x10, 0x00, 0, 0, 0, 0]))
    end = time.monotonic() + timeout_s
    while time.monotonic() < end:
        msg = bus.recv(end - time.monotonic())
        if msg is None:
            break
        if msg.arbitration_id == 0x580 + NODE_ID and msg.data[0] & 0xE0 == 0x40 \
                and msg.data[1:4] == bytearray([0x00, 0x10, 0x00]):
            return True
    return False


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("node")
    ap.add_argument("--seconds", type=float, default=6.0)
    ap.add_argument("--gap-ms", default="1", help="cangen -g of the flood")
    ap.add_argument("--burst", default="100", help="cangen -c: frames per gap")
    ap.add_argument("--min-rate", type=float, default=3000.0)
    ap.add_argument("--sdo-per-s", type=float, default=20.0, help="SDO upload requests per second")
    args = ap.parse_args()

    tmp = tempfile.mkdtemp(prefix="bus-load.")
    log = os.path.join(tmp, "candump.log")
    children = []
    try:
        # candump first, known to listen once it has logged our probe.
        with open(log, "w") as out:
            candump = subprocess.Popen(["candump", "-L", "-r", "8388608", "-d", IFACE], stdout=out)
        children.append(candump)
        with can.Bus(interface="socketcan", channel=IFACE,
                     can_filters=[{"can_id": 0x580 + NODE_ID, "can_mask": 0x7FF, "extended": False},
                                  {"can_id": 0x1FFFFFFF, "can_mask": 0x1FFFFFFF, "extended": True}],
                     receive_own_messages=True) as bus:
            probe = can.Message(arbitration_id=0x1FFFFFFF, is_extended_id=True, data=[])
            if not logged(log, " 1FFFFFFF#", lambda: bus.send(probe)):
                fail("candump never logged the probe")

            node = subprocess.Popen(["nice", "-n", "-10", args.node, "--can", IFACE, "--node-id", str(NODE_ID),
                                     "--pty", os.path.join(tmp, "node.pty")],
                                    stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True)
            children.append(node)
            wait_line(node, "ready", "mb2co-node")
            # A heartbeat before the flood: the node is on the bus.
            if not sdo_upload(bus, 5.0):
                fail("no SDO answer before the flood")

            marker = can.Message(arbitration_id=0x1FFFFFFE, is_extended_id=True, data=[])
            bus.send(marker)  # flood begins (in the log)
            ticks0 = cpu_ticks(node.pid)
            sleeps0 = wakeups(node.pid)
            wall0 = time.monotonic()
            flood = subprocess.Popen(["nice", "-n", "19", "cangen", IFACE, "-g", args.gap_ms, "-c", args.burst, "-I", "123", "-L", "8", "-D", "i"])
            children.append(flood)
            sync = subprocess.Popen(["nice", "-n", "19", "cangen", IFACE, "-g", "10", "-I", "80", "-L", "0"])
            children.append(sync)
            answered = 0
            asked = 0
            end = wall0 + args.seconds
            # One request per slot (a load profile: the answers are waited for).
            next_at = wall0
            while time.monotonic() < end:
                asked += 1
                answered += sdo_upload(bus, 1.0)
                next_at += 1.0 / args.sdo_per_s
                time.sleep(max(0.0, next_at - time.monotonic()))
            flood.kill()
            sync.kill()
            flood.wait()
            sync.wait()
            wall = time.monotonic() - wall0
            ticks = cpu_ticks(node.pid) - ticks0
            sleeps = wakeups(node.pid) - sleeps0
            bus.send(can.Message(arbitration_id=0x1FFFFFFD, is_extended_id=True, data=[]))
            # The end marker logged: everything before it is in the log too.
            if not logged(log, " 1FFFFFFD#", lambda: None):
                fail("candump never logged the end marker")
            node.stdin.close()
            node.terminate()
            node.wait()
    finally:
        for c in children:
            if c.poll() is None:
                c.kill()
                c.wait()

    # Heartbeats between the markers, by candump's timestamps.
    stamps = []
    every = []  # all frames' times: silences show where the whole VM stood still
    flood_frames = 0
    dropped = 0
    t_begin = t_end = None
    with open(log) as f:
        for line in f:
            parts = line.split()
            if parts[:1] == ["DROPCOUNT:"]:  # candump -d: frames the log lacks
                dropped += int(parts[2])  # "DROPCOUNT: dropped N CAN frames on ..."
                continue
            if len(parts) < 3:
                continue
            t = float(parts[0].strip("()"))
            ident = parts[2].split("#")[0]
            if ident == "1FFFFFFE":
                t_begin = t
            elif ident == "1FFFFFFD":
                t_end = t
            elif t_begin is not None and t_end is None:
                every.append(t)
                if ident == "%03X" % HB_ID:
                    stamps.append(t)
                elif ident == "123":
                    flood_frames += 1
    if t_begin is None or t_end is None:
        fail("markers missing from the log")
    span = t_end - t_begin
    rate = flood_frames / span
    intervals = [(b - a) * 1000.0 for a, b in zip(stamps, stamps[1:])]
    phase = min(t - k * PERIOD_MS / 1000.0 for k, t in enumerate(stamps))
    late_ms = []
    silence_ms = []
    for k, t in enumerate(stamps):
        due = phase + k * PERIOD_MS / 1000.0
        late_ms.append((t - due) * 1000.0)
        gaps = [b - a for a, b in zip(every, every[1:]) if b > due and a < t]
        silence_ms.append(max(gaps, default=0.0) * 1000.0)
    if os.environ.get("BUS_LOAD_VERBOSE"):
        for k in range(len(stamps)):
            print("hb %2d late %6.1f ms, longest bus silence meanwhile %6.1f ms" % (k, late_ms[k], silence_ms[k]))
    hz = os.sysconf("SC_CLK_TCK")
    print("flood: %d frames in %.2f s = %.0f frames/s (cangen -g %s -c %s), SYNC at 100/s"
          % (flood_frames, span, rate, args.gap_ms, args.burst))
    print("mb2co-node CPU: %.2f s of %.2f s = %.1f %%, %.0f wakeups/s"
          % (ticks / hz, wall, 100.0 * ticks / hz / wall, sleeps / wall))
    print("SDO uploads answered: %d of %d" % (answered, asked))
    if intervals:
        print("heartbeat intervals: %d, %.1f..%.1f ms" % (len(intervals), min(intervals), max(intervals)))
    ok = True
    if rate < args.min_rate:
        print("FAIL: flood below %.0f frames/s" % args.min_rate)
        ok = False
    if len(intervals) < span * 1000.0 / PERIOD_MS * 0.8:
        print("FAIL: too few heartbeats (%d intervals in %.2f s)" % (len(intervals), span))
        ok = False
    if dropped:
        # Holes in the log would pass for stalls: no heartbeat is excused.
        print("candump dropped %d frames: no stall allowance" % dropped)
        silence_ms = [0.0] * len(silence_ms)
    # The node's own lateness: beyond the longest stretch in which nothing at
    # all went over the bus (the whole user-mode Linux stood still, the host
    # did not run it: the flood generator stopped too).
    own_ms = [max(0.0, l - q) for l, q in zip(late_ms, silence_ms)]
    excused = sum(1 for l, o in zip(late_ms, own_ms) if l > LATE_MS >= o)
    bad = [i for i in intervals if abs(i - PERIOD_MS) > PERIOD_MS * TOLERANCE]
    print("heartbeat lateness: at most %.1f ms, %.1f ms beyond stalls of the whole VM; "
          "%d of %d intervals outside %.0f..%.0f ms, %d heartbeats late only by a stall"
          % (max(late_ms), max(own_ms), len(bad), len(intervals), PERIOD_MS * (1 - TOLERANCE),
             PERIOD_MS * (1 + TOLERANCE), excused))
    late_own = [(k, late_ms[k], silence_ms[k]) for k in range(len(own_ms)) if own_ms[k] > LATE_MS]
    if late_own:
        print("FAIL: heartbeats more than %.0f ms late beyond a stall: %s" % (LATE_MS, ", ".join(
            "#%d %.1f ms (bus silent %.1f ms)" % k for k in late_own[:20])))
        ok = False
    if excused > len(stamps) // 2:
        print("FAIL: the host stalled the VM at more than half the heartbeats: nothing measured")
        ok = False
    if answered != asked:
        print("FAIL: %d SDO uploads unanswered" % (asked - answered))
        ok = False
    print("PASS" if ok else "FAILED", flush=True)
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
