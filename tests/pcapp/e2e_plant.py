#!/usr/bin/env python3
"""End-to-end tests of mb2co-plant against mb2co-node (the gateway firmware on
Linux) over a pty pair, without hardware and without CAN (--can none).

Every step waits for something observable (a line of the node or of the
app); the per-step time limits only turn a hang into a failure.

usage: e2e_plant.py --plant BIN --node BIN SCENARIO
"""
import argparse
import csv
import json
import os
import queue
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import threading
import time

STEP_TIMEOUT_S = 10.0
# Generous: on a loaded machine the app may be descheduled for a while, and a
# spurious link loss would change the scenario.
PLANT_TIMEOUT = ("--timeout-ms", "500", "--retries", "3")


class Proc:
    """A child process whose stdout (and stderr) lines are collected by a thread."""

    def __init__(self, name, argv, stdin=True):
        self.name = name
        self.argv = argv
        self.p = subprocess.Popen(argv, stdin=subprocess.PIPE if stdin else subprocess.DEVNULL,
                                  stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, bufsize=1)
        self.lines = queue.Queue()
        self.seen = []
        self.err = []
        threading.Thread(target=self._pump, args=(self.p.stdout, self.lines), daemon=True).start()
        threading.Thread(target=self._collect_err, daemon=True).start()

    @staticmethod
    def _pump(stream, q):
        for line in stream:
            q.put(line.rstrip("\n"))
        q.put(None)

    def _collect_err(self):
        for line in self.p.stderr:
            self.err.append(line.rstrip("\n"))

    def send(self, line):
        self.p.stdin.write(line + "\n")
        self.p.stdin.flush()

    def expect(self, pattern, what=None):
        """Returns the match of the first new stdout line matching `pattern`."""
        rx = re.compile(pattern)
        deadline = time.monotonic() + STEP_TIMEOUT_S
        while True:
            left = deadline - time.monotonic()
            try:
                line = self.lines.get(timeout=max(left, 0.01))
            except queue.Empty:
                line = ""
                if time.monotonic() >= deadline:
                    fail(f"{self.name}: no line matching /{pattern}/ ({what or ''})")
                continue
            if line is None:
                fail(f"{self.name} ended before /{pattern}/ ({what or ''})")
            self.seen.append(line)
            m = rx.search(line)
            if m:
                return m

    def wait_exit(self):
        try:
            return self.p.wait(timeout=STEP_TIMEOUT_S)
        except subprocess.TimeoutExpired:
            fail(f"{self.name} did not exit")

    def kill(self, sig=signal.SIGKILL):
        if self.p.poll() is None:
            self.p.send_signal(sig)
            self.p.wait()

    def rest(self):
        """Every stdout line after the process ended."""
        out = []
        while True:
            line = self.lines.get(timeout=STEP_TIMEOUT_S)
            if line is None:
                return out
            self.seen.append(line)
            out.append(line)


PROCS = []


def fail(message):
    for proc in PROCS:
        proc.kill()
        while True:  # everything the process printed, also lines no step waited for
            try:
                line = proc.lines.get(timeout=1.0)
            except queue.Empty:
                break
            if line is None:
                break
            proc.seen.append(line)
        sys.stderr.write(f"--- {proc.name}: {' '.join(proc.argv)}\n")
        for line in proc.seen[-60:]:
            sys.stderr.write(f"  out| {line}\n")
        for line in proc.err[-20:]:
            sys.stderr.write(f"  err| {line}\n")
    sys.stderr.write(f"FAIL: {message}\n")
    sys.exit(1)


def check(condition, message):
    if not condition:
        fail(message)


class Setup:
    def __init__(self, args):
        self.args = args
        self.dir = tempfile.mkdtemp(prefix="mb2co-pcapp-e2e-")
        self.tty = os.path.join(self.dir, "ttyGW")
        self.node = None

    def start_node(self):
        self.node = Proc("mb2co-node", [self.args.node, "--can", "none", "--pty", self.tty])
        PROCS.append(self.node)
        self.node.expect(r"^ready node=1 .* link=" + re.escape(self.tty), "node ready")
        return self.node

    def start_plant(self, *extra):
        # A generous response timeout: a loaded test machine must not lose the link.
        plant = Proc("mb2co-plant", [self.args.plant, "--port", self.tty, "--plain", *PLANT_TIMEOUT, *extra],
                     stdin=False)
        PROCS.append(plant)
        plant.expect(r" link up " + re.escape(self.tty) + r" slave 1: mb2co mb2co gateway", "first link up")
        # The first read: from here on a press is an edge (a button already
        # held at the first sample is, by design, no press).
        plant.expect(r" buttons none$", "first read of the panel")
        return plant

    def node_run_led(self, on):
        # Ask as well: the LED's own event line may have come before a line the
        # test waited for (the node prints leds before state in one pass).
        self.node.send("leds?")
        self.node.expect(r"^leds self=%d" % (1 if on else 0), "RUN-self LED %s" % ("on" if on else "off"))

    def node_state(self):
        self.node.send("state?")
        return self.node.expect(r"^state node=1 nmt=\d+ run=(\d) cause=(\d)")

    def stop_plant(self, plant, sig=signal.SIGTERM):
        plant.p.send_signal(sig)
        rc = plant.wait_exit()
        check(rc == 0, f"mb2co-plant exit code {rc} after {sig.name}, want 0")
        rest = plant.rest()
        check(any(re.search(sig.name + r": RUN=0 written, port closed", l) for l in rest),
              "no 'RUN=0 written, port closed' line")
        return rest

    def cleanup(self):
        for proc in PROCS:
            proc.kill()
        shutil.rmtree(self.dir, ignore_errors=True)


def click(s, plant, button, state):
    """Presses a panel button until the app has seen it, then releases it; a
    timed click could fall between two polls of a starved app."""
    s.node.send(f"press {button}")
    plant.expect(r" buttons .*\b%s\b" % button, f"{button} seen pressed")
    plant.expect(r" state %s$" % state, f"{button} gives {state}")
    s.node.send(f"release {button}")
    plant.expect(r" buttons none$", f"{button} seen released")


def start_station(s, plant):
    click(s, plant, "START", "moving")
    s.node_run_led(True)


def scenario_start_stop2(s):
    """A virtual START runs the station, STOP2 stops it; SIGTERM leaves RUN=0; JSONL log."""
    s.start_node()
    log = os.path.join(s.dir, "cycles.jsonl")
    plant = s.start_plant("--log", log)
    start_station(s, plant)
    click(s, plant, "STOP2", "stopped cause=local_stop2")
    s.node_run_led(False)
    # A restart needs a fresh START: the firmware's latch was acknowledged.
    start_station(s, plant)
    s.stop_plant(plant, signal.SIGTERM)
    s.node_run_led(False)
    run, _ = s.node_state().groups()
    check(run == "0", "the gateway's RUN state is not 0 after the app ended")
    rows = [json.loads(line) for line in open(log)]
    check(len(rows) > 10, "too few log rows")
    check(all(r["link"] == 1 for r in rows), "a cycle without the link")
    states = [r["state"] for r in rows]
    check("moving" in states and "stopped" in states, "log misses the states")
    check([r["cycle"] for r in rows] == list(range(1, len(rows) + 1)), "log rows not one per cycle")


def scenario_short_stop(s):
    """A STOP click shorter than a cycle is latched by the firmware and still stops."""
    s.start_node()
    plant = s.start_plant("--cycle-ms", "100")
    start_station(s, plant)
    # Released as soon as the firmware latched it (after its 20 ms debounce):
    # a press mostly shorter than one 100 ms cycle. Whether or not the app
    # samples the level, the firmware's latch stops the station.
    s.node.send("press STOP")
    s.node.expect(r"^state node=1 nmt=\d+ run=0 cause=1 ", "the firmware latched STOP")
    s.node.send("release STOP")
    plant.expect(r" state stopped cause=stop_button$", "a short STOP stops the station")
    s.node_run_led(False)
    s.stop_plant(plant, signal.SIGINT)


def scenario_link_loss(s):
    """Killing the node: plant safe, clear message; a new node: reconnected by itself."""
    s.start_node()
    log = os.path.join(s.dir, "cycles.csv")
    plant = s.start_plant("--log", log, "--reconnect-max-ms", "400")
    start_station(s, plant)
    s.node.kill(signal.SIGKILL)
    plant.expect(r" link lost: .* plant safe, reconnecting$", "link loss is reported")
    plant.expect(r" state stopped cause=link_lost$", "link loss makes the station safe")
    s.start_node()  # same pty symlink, a fresh gateway
    plant.expect(r" link up " + re.escape(s.tty), "reconnected without a restart")
    plant.expect(r" buttons none$", "first read of the new gateway's panel")
    # Safe after the outage: stopped until a fresh START, which works again.
    run, _ = s.node_state().groups()
    check(run == "0", "the new gateway runs before a START")
    start_station(s, plant)
    s.stop_plant(plant, signal.SIGTERM)
    with open(log) as f:
        rows = list(csv.DictReader(f))
    down = [r for r in rows if r["link"] == "0"]
    check(down, "no cycle logged without the link")
    check(all(r["motor"] == "0" and r["valve"] == "0" for r in down), "plant not safe while the link was down")


def scenario_stop_without_link(s):
    """Stopped while the gateway is gone: RUN=0 cannot be written, exit 3, not 0."""
    s.start_node()
    plant = s.start_plant("--reconnect-max-ms", "400")
    start_station(s, plant)
    s.node.kill(signal.SIGKILL)
    plant.expect(r" link lost: .* plant safe, reconnecting$", "link loss is reported")
    plant.p.send_signal(signal.SIGINT)
    rc = plant.wait_exit()
    check(rc == 3, f"mb2co-plant exit code {rc} after SIGINT without the gateway, want 3")
    check(any(re.search(r"SIGINT: RUN=0 not written \(no link\), port closed", l) for l in plant.rest()),
          "no 'RUN=0 not written (no link)' line")


def scenario_bad_port(s):
    """A bad --port: one line on stderr, nothing on stdout, exit code != 0."""
    p = subprocess.run([s.args.plant, "--port", os.path.join(s.dir, "no-such-tty")], capture_output=True,
                       text=True, timeout=STEP_TIMEOUT_S)
    check(p.returncode != 0, "exit code 0 for a bad --port")
    check(p.stdout == "", f"stdout not empty: {p.stdout!r}")
    lines = p.stderr.splitlines()
    check(len(lines) == 1 and "no-such-tty" in lines[0], f"want one line naming the port, got {lines!r}")
    p = subprocess.run([s.args.plant, "--cycle-ms", "0"], capture_output=True, text=True, timeout=STEP_TIMEOUT_S)
    check(p.returncode == 2 and len(p.stderr.splitlines()) == 1, "bad --cycle-ms: want one line, exit 2")
    conf = os.path.join(s.dir, "station.conf")
    with open(conf, "w") as f:
        f.write("step_ms = 10\nbelt_speed = 3\n")
    p = subprocess.run([s.args.plant, "--config", conf], capture_output=True, text=True, timeout=STEP_TIMEOUT_S)
    check(p.returncode == 2 and p.stderr == f"mb2co-plant: {conf}:2:1: unknown key 'belt_speed'\n",
          f"bad config: {p.returncode} {p.stderr!r}")


def scenario_no_slave(s):
    """A port with no gateway behind it: verification fails, one line, exit != 0."""
    os.mkfifo(os.path.join(s.dir, "fifo"))  # not a tty: the open itself fails
    silent = os.path.join(s.dir, "silent")
    # The slave side of a pty nobody answers on: opened fine, no FC 2B/0E answer.
    master, slave = os.openpty()
    os.symlink(os.ttyname(slave), silent)
    p = subprocess.run([s.args.plant, "--port", silent, "--timeout-ms", "20", "--retries", "1"],
                       capture_output=True, text=True, timeout=STEP_TIMEOUT_S)
    os.close(master)
    os.close(slave)
    check(p.returncode == 1, f"exit code {p.returncode} without a slave, want 1")
    lines = p.stderr.splitlines()
    check(len(lines) == 1 and "FC 2B/0E" in lines[0], f"want one line about the verification, got {lines!r}")
    p = subprocess.run([s.args.plant, "--port", os.path.join(s.dir, "fifo"), "--timeout-ms", "20"],
                       capture_output=True, text=True, timeout=STEP_TIMEOUT_S)
    check(p.returncode == 1 and len(p.stderr.splitlines()) == 1, f"fifo as port: {p.stderr!r}")


def scenario_latency(s):
    """Latency lab: START mirrored to the lab LED; delay per press from the firmware stamps."""
    s.start_node()
    out = os.path.join(s.dir, "presses.csv")
    plant = Proc("mb2co-plant", [s.args.plant, "latency", "--port", s.tty, "--plain", *PLANT_TIMEOUT, "--presses", "3",
                                 "--csv", out], stdin=False)
    PROCS.append(plant)
    plant.expect(r" link up ", "latency link up")
    for n in (1, 2, 3):
        s.node.send("press START")
        plant.expect(r" press %d delay_us=\d+$" % n, f"press {n} measured")
        s.node.expect(r"^leds .* lab=1\b", "lab LED on")
        s.node.send("release START")
        s.node.expect(r"^leds .* lab=0\b", "lab LED off after the release")
    rc = plant.wait_exit()
    check(rc == 0, f"latency exit code {rc}")
    rest = plant.rest()
    check(any(re.search(r"presses 3 +min [\d.]+ ms +mean [\d.]+ ms +p99 [\d.]+ ms +max", l) for l in rest),
          "no statistics line")
    check(any(re.search(r"^\s+\[ *[\d.]+, *[\d.]+\) ms +\d+ +#+$", l) for l in rest), "no histogram")
    with open(out) as f:
        rows = list(csv.DictReader(f))
    check(len(rows) == 3, f"{len(rows)} CSV rows, want 3")
    for r in rows:
        delay = int(r["delay_us"])
        check(delay == (int(r["led_us"]) - int(r["edge_us"])) % 2**32, "delay is not led_us - edge_us")
        # The firmware debounces 20 ms (2000h/6) before it acts on the edge.
        check(20000 <= delay < 1000000, f"implausible delay {delay} us")


SCENARIOS = {name[len("scenario_"):]: fn for name, fn in globals().items() if name.startswith("scenario_")}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--plant", required=True)
    ap.add_argument("--node", required=True)
    ap.add_argument("scenario", choices=sorted(SCENARIOS))
    args = ap.parse_args()
    s = Setup(args)
    try:
        SCENARIOS[args.scenario](s)
    finally:
        s.cleanup()
    print(f"ok {args.scenario}")


if __name__ == "__main__":
    main()
