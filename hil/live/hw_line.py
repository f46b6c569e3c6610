"""The line with real gateways: one mb2co-plant per serial port (port i is
station i, node id i), the operator presses the buttons when asked. What the
stations show is read from each plant's per-cycle log (--log FILE.jsonl:
RUN state, stop cause and the LEDs as the firmware drives them, 2200h), so
every check of the simulated run is made, except the timings: the PCs read
the panel once per cycle (20 ms) and have no common clock with the gateways
(the latency mode measures on the gateway's clock: mb2co-plant latency)."""
import json
import os

from line_base import PLANT_OPTIONS, RUNNING_STATES, Run
from line_views import CAUSE_STOP2_HERE, CAUSE_STOP2_PREVIOUS, expected_leds, led_bits, neighbours
from live_procs import Failure


class LogTail:
    """The rows of a plant's JSONL log as far as they are written. The plant
    writes the file through stdio buffers, so rows arrive in blocks (about
    every 12 cycles, ~0.25 s at 20 ms), in order."""

    def __init__(self, path):
        self.path = path
        self.offset = 0
        self.partial = b""
        self.rows = []

    def refresh(self):
        try:
            with open(self.path, "rb") as f:
                f.seek(self.offset)
                data = f.read()
        except FileNotFoundError:
            return
        self.offset += len(data)
        *whole, self.partial = (self.partial + data).split(b"\n")
        for raw in whole:
            try:
                self.rows.append(json.loads(raw))
            except ValueError:
                raise Failure(f"{self.path}: not a JSON row: {raw[:80]!r}") from None

    def last(self):
        self.refresh()
        return self.rows[-1] if self.rows else None


class HardwareLine(Run):
    def prompt(self, button, stations):
        """The operator's instruction; one line, the same words every time
        (hil/live/operator_test.py reads them). Asked only once the plants of
        those stations saw their panel empty: a button still held from the
        last instruction (the line may answer faster than a finger lets go)
        pressed again would be no new press, and the run would wait for a
        START that never comes."""
        for i in stations:
            self.wait(lambda: self.plants[i].last("buttons") in (None, "buttons none"),
                      f"plant {i}: panel empty before '{button}' is asked")
        self.say(f">>> press {button} at station {', '.join(map(str, stations))}")

    def mismatch(self, running, causes, mark):
        """None when the newest row of every plant's log, written after row
        `mark[i]`, shows `running` (RUN state, stop causes, RUN LEDs)."""
        for i, tail in self.tails.items():
            tail.refresh()
            if len(tail.rows) <= mark[i]:
                return f"no new log row of station {i} yet"
            row = tail.rows[-1]
            if row["run_state"] != int(i in running):
                return f"station {i} run_state={row['run_state']}, want {int(i in running)}"
            if i in causes and row["stop_cause"] != causes[i]:
                return f"station {i} stop_cause={row['stop_cause']}, want {causes[i]}"
            want = led_bits(expected_leds(i, self.n, self.ring, running))
            if row["leds"] & 7 != want:
                return f"station {i} LED bits (self 1, prev 2, next 4)={row['leds'] & 7}, want {want}"
        return None

    def wait_line(self, running, causes, what):
        mark = {i: len(t.rows) for i, t in self.tails.items()}
        self.wait_matching(lambda: self.mismatch(running, causes, mark), what)

    def wait_plants(self, stations, marks, pattern, what):
        for i in stations:
            self.wait(lambda: self.plants[i].seen_since(marks[i], pattern), f"plant {i}: {what}")

    def run(self):
        n, k = self.n, self.a.stop2_at
        every = list(range(1, n + 1))
        self.tails = {i: LogTail(os.path.join(self.tmp, f"plant{i}.jsonl")) for i in every}
        options = [] if self.a.plant_defaults else PLANT_OPTIONS
        self.start_plants(self.a.ports, lambda i: options + ["--log", self.tails[i].path])
        self.say(f"{n} mb2co-plant linked to {', '.join(self.a.ports)} (station 1 first), panels read")

        marks = {i: len(self.plants[i].events) for i in every}
        self.prompt("START", every)
        self.wait_plants(every, marks, RUNNING_STATES, "running after START")
        self.wait_line(set(every), {}, "after START everywhere, every station runs with its RUN LEDs on")
        self.say("[ok] START at every station: all run, RUN LEDs on")

        _, nxt = neighbours(k, n, self.ring)
        stopped = {k} | ({nxt} if nxt else set())
        causes = {k: CAUSE_STOP2_HERE}
        if nxt:
            causes[nxt] = CAUSE_STOP2_PREVIOUS
        running = set(every) - stopped
        marks = {i: len(self.plants[i].events) for i in every}
        self.prompt("STOP2", [k])
        self.wait_plants([k], marks, r"^state stopped cause=local_stop2$", f"stopped by STOP2 at station {k}")
        if nxt:
            self.wait_plants([nxt], marks, r"^state stopped cause=prev_stop2$", f"stopped by STOP2 at station {k}")
        self.wait_line(running, causes, f"after STOP2 at station {k}, stations {sorted(stopped)} stopped, "
                       f"{sorted(running)} run on, LEDs show it")
        self.say(f"[ok] STOP2 at station {k}: " +
                 ", ".join(f"station {i} stopped (cause {causes[i]})" for i in sorted(stopped)) +
                 (f"; {', '.join(map(str, sorted(running)))} run on" if running else "") + "; every LED shows it")

        restart = {i: len(self.plants[i].events) for i in every}
        self.prompt("START", sorted(stopped))
        self.wait_plants(sorted(stopped), restart, RUNNING_STATES, "running after START")
        self.wait_line(set(every), {}, f"after START at {sorted(stopped)}, every station runs again")
        for i in sorted(running):
            if self.plants[i].seen_since(marks[i], r"^state stopped"):
                raise Failure(f"STOP2 at station {k}: plant {i} stopped too")
        self.say(f"[ok] START at {', '.join(map(str, sorted(stopped)))}: every station runs again")

        self.stop_plants()
        self.say("[ok] SIGTERM to every plant: RUN=0 written, exit 0")
