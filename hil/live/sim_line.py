"""The simulated line: N mb2co-node (the gateway firmware on Linux) on a CAN
interface, each with a pty, and N mb2co-plant on those ptys. Buttons are
pressed through the nodes' control channels; what the stations show is read
from the nodes' `state`/`leds` lines, stamped by their own clocks."""
import os

from line_base import PLANT_OPTIONS, RUNNING_STATES, Run
from line_views import (CAUSE_STOP2_HERE, CAUSE_STOP2_PREVIOUS, STATUS_ALIVE, STATUS_NONE, NodeView,
                        expected_leds, neighbours, wrap_delta_us)
from live_procs import Failure


class SimulatedLine(Run):
    """N mb2co-node on a CAN interface, each with a pty, N mb2co-plant on
    those ptys; buttons through the nodes' control channels."""

    def start_nodes(self):
        for i in range(1, self.n + 1):
            view = NodeView(i)
            argv = [self.a.node, "--can", self.a.can, "--node-id", str(i), "--stations", str(self.n),
                    "--topology", self.a.topology, "--pty", os.path.join(self.tmp, f"st{i}")]
            view.proc = self.pump.start(f"mb2co-node {i}", argv, view.on_line, stdin=True)
            self.nodes[i] = view
        for i, view in self.nodes.items():
            self.wait(lambda: view.ready is not None, f"node {i}: ready line")
            if view.ready["node"] != i:
                raise Failure(f"node {i}: ready as node {view.ready['node']}, want {i}")

    # --- the control channel ---------------------------------------------

    def command(self, i, text):
        """Sends one command to node i, waits for its 'ok'."""
        view = self.nodes[i]
        start = len(view.proc.lines)
        view.proc.send(text + "\n")
        self.wait(lambda: view.replies_since(start), f"node {i}: reply to '{text}'")
        reply = view.replies_since(start)[0][1]
        if reply != "ok":
            raise Failure(f"node {i}: '{text}' answered '{reply}'")

    def press(self, i, button):
        """Presses a button; returns the node's clock at the press: the
        'leds?' sent in the same write is handled in the same loop pass and
        its reply, the line after the press's 'ok', carries that pass's time."""
        view = self.nodes[i]
        start = len(view.proc.lines)
        view.proc.send(f"press {button}\nleds?\n")
        lines = view.proc.lines

        def stamp():
            replies = view.replies_since(start)
            if not replies or replies[0][0] + 1 >= len(lines):
                return None
            if replies[0][1] != "ok":
                raise Failure(f"node {i}: 'press {button}' answered '{replies[0][1]}'")
            return int(lines[replies[0][0] + 1][1].rsplit("at_us=", 1)[1])

        self.wait(lambda: stamp() is not None, f"node {i}: reply to 'press {button}'")
        return stamp()

    def click(self, stations, button, plant_sees):
        """Presses `button` at every station in `stations` until its plant
        reports `plant_sees` (a starved plant cannot miss the press), then
        releases it until the plant reports the panel empty again. Returns
        {station: press time on the node's clock}."""
        marks = {i: len(self.plants[i].events) for i in stations}
        at = {i: self.press(i, button) for i in stations}
        for i in stations:
            self.wait(lambda: self.plants[i].seen_since(marks[i], plant_sees),
                      f"plant {i}: /{plant_sees}/ after {button} pressed at station {i}")
        marks = {i: len(self.plants[i].events) for i in stations}
        for i in stations:
            self.command(i, f"release {button}")
        for i in stations:
            self.wait(lambda: self.plants[i].seen_since(marks[i], r"^buttons none$"),
                      f"plant {i}: panel empty after {button} released at station {i}")
        return at

    # --- conditions on the whole line --------------------------------------

    def mismatch(self, running, causes=None):
        """None when every node shows exactly `running` (RUN state, neighbours
        alive with their RUN states, RUN LEDs) and the stop causes `causes`;
        otherwise the first difference, in words."""
        for i, v in self.nodes.items():
            if v.state is None or v.leds is None:
                return f"station {i} has not reported its state and LEDs"
            s = v.state
            if s["run"] != int(i in running):
                return f"station {i} run={s['run']}, want {int(i in running)}"
            if causes and i in causes and s["cause"] != causes[i]:
                return f"station {i} cause={s['cause']}, want {causes[i]}"
            for side, nb in zip(("prev", "next"), neighbours(i, self.n, self.ring)):
                want = (nb, STATUS_ALIVE, int(nb in running)) if nb else (0, STATUS_NONE, 0)
                if s[side] != want:
                    return f"station {i} {side}={':'.join(map(str, s[side]))}, want {':'.join(map(str, want))}"
            want = expected_leds(i, self.n, self.ring, running)
            got = (v.leds["self"], v.leds["prev"], v.leds["next"])
            if got != want:
                return f"station {i} LEDs self/prev/next={'/'.join(map(str, got))}, want {'/'.join(map(str, want))}"
        return None

    def wait_line(self, running, what, causes=None):
        self.wait_matching(lambda: self.mismatch(running, causes), what)

    def never_stopped(self, stations, node_marks, plant_marks, what):
        """Fails when a station in `stations` stopped after its marks: a
        `state` with run=0 or a RUN-self LED off at the node, a stop at the PC."""
        for i in stations:
            ev = self.nodes[i].first_event_since(
                node_marks[i], lambda kind, f: (kind == "state" and f["run"] == 0) or (kind == "leds" and f["self"] == 0))
            if ev:
                raise Failure(f"{what}: station {i} stopped too ({ev[0]} at_us={ev[1]['at_us']})")
            if self.plants[i].seen_since(plant_marks[i], r"^state stopped"):
                raise Failure(f"{what}: plant {i} stopped too")

    def led_changes(self, marks, since_us):
        """Per station, every RUN LED that changed after `marks`, with its
        time from `since_us` (ms), in order."""
        names = {"self": "RUN-self", "prev": "RUN-prev", "next": "RUN-next"}
        out = {}
        for i, v in self.nodes.items():
            before = None
            for kind, f in v.events[:marks[i]]:
                if kind == "leds":
                    before = f
            changes = []
            for kind, f in v.events[marks[i]:]:
                if kind != "leds":
                    continue
                for key, name in names.items():
                    if before is not None and f[key] != before[key]:
                        changes.append((wrap_delta_us(f["at_us"], since_us) / 1000.0, name, f[key]))
                before = f
            out[i] = changes
        return out

    def first_change_ms(self, changes, i, led, value):
        for ms, name, v in changes.get(i, []):
            if name == led and v == value:
                return ms
        return None

    def start_station_plants(self):
        """A plant on each station's pty (PLANT_OPTIONS, or with
        --plant-defaults none); returns the options in words."""
        options = [] if self.a.plant_defaults else PLANT_OPTIONS
        self.start_plants([self.nodes[i].ready["link"] for i in range(1, self.n + 1)], lambda i: options)
        return " ".join(options) or "default options"

    def quit_stations(self):
        """`quit` to every station's program (mb2co-node, mb2co-uno): each exits 0."""
        for view in self.nodes.values():
            view.proc.exit_expected = True
            view.proc.send("quit\n")
        for i, view in self.nodes.items():
            code = self.pump.wait_exit(view.proc, self.a.timeout)
            if code != 0:
                raise Failure(f"station {i}: {view.proc.name} exit {code} after quit, want 0")

    def wait_stop2_logged(self, k, nxt, plant_marks):
        """After STOP2 at station k: its PC and the next station's log why
        they stopped (local_stop2, prev_stop2), after their `plant_marks`."""
        self.wait(lambda: self.plants[k].seen_since(plant_marks[k], r"^state stopped cause=local_stop2$"),
                  f"plant {k}: 'state stopped cause=local_stop2' after STOP2 at station {k}")
        if nxt:
            self.wait(lambda: self.plants[nxt].seen_since(plant_marks[nxt], r"^state stopped cause=prev_stop2$"),
                      f"plant {nxt}: 'state stopped cause=prev_stop2' after STOP2 at station {k}")

    # --- the scenario -----------------------------------------------------

    def run(self):
        n, k = self.n, self.a.stop2_at
        every = list(range(1, n + 1))
        self.start_nodes()
        self.say(f"{n} mb2co-node on {self.a.can} ({self.a.topology}), ptys in {self.tmp}")
        self.start_station_plants()
        self.say(f"{n} mb2co-plant linked, panels read")

        # 1. START everywhere: each PC sees it and writes RUN command 1.
        start_at = self.click(every, "START", RUNNING_STATES)
        self.wait_line(set(every), "after START everywhere, every station runs with LEDs self/prev/next on")
        start_ms = [wrap_delta_us(self.nodes[i].first_event_since(
            0, lambda kind, f: kind == "leds" and f["self"] == 1)[1]["at_us"], start_at[i]) / 1000.0 for i in every]
        self.say(f"[ok] START at every station: all run, RUN LEDs on "
                 f"(press -> own RUN-self LED {min(start_ms):.1f}..{max(start_ms):.1f} ms, through the PC)")

        # 2. STOP2 at k: k stops (cause 2), k+1 stops (cause 3), the rest runs on.
        _, nxt = neighbours(k, n, self.ring)
        stopped = {k} | ({nxt} if nxt else set())
        causes = {k: CAUSE_STOP2_HERE}
        if nxt:
            causes[nxt] = CAUSE_STOP2_PREVIOUS
        marks = {i: len(self.nodes[i].events) for i in every}
        plant_marks = {i: len(self.plants[i].events) for i in every}
        stop2_at = self.click([k], "STOP2", r"^buttons STOP2$")[k]
        self.wait_stop2_logged(k, nxt, plant_marks)
        running = set(every) - stopped
        self.wait_line(running, f"after STOP2 at station {k}, stations {sorted(stopped)} stopped, "
                       f"{sorted(running)} run on, LEDs show it", causes)
        others = sorted(running)
        self.never_stopped(others, marks, plant_marks, f"STOP2 at station {k}")
        changes = self.led_changes(marks, stop2_at)
        self.say(f"[ok] STOP2 at station {k}: " + ", ".join(
            f"station {i} stopped (cause {causes[i]})" for i in sorted(stopped)) +
            (f"; {', '.join(map(str, others))} run on" if others else "") + "; every LED shows it")

        # 3. START at the stopped stations: the whole line runs again.
        self.click(sorted(stopped), "START", RUNNING_STATES)
        self.wait_line(set(every), f"after START at {sorted(stopped)}, every station runs again")
        self.never_stopped(others, marks, plant_marks, "the restart")
        self.say(f"[ok] START at {', '.join(map(str, sorted(stopped)))}: every station runs again")

        # 4. The PCs leave: RUN=0 written, so every gateway shows RUN 0.
        self.stop_plants()
        self.wait(lambda: all(v.state["run"] == 0 for v in self.nodes.values()),
                  "after SIGTERM of every plant, every node shows run=0")
        self.quit_stations()
        self.say("[ok] SIGTERM to every plant: RUN=0 written, exit 0; every node shows run=0; nodes quit")

        self.report_stop2(k, nxt, stop2_at, changes)

    def report_stop2(self, k, nxt, stop2_at, changes):
        own = self.first_change_ms(changes, k, "RUN-self", 0)
        print(f"STOP2 pressed at station {k}, times from the press (nodes' at_us, one CLOCK_MONOTONIC):")
        print(f"  press -> RUN-self LED off at station {k} (own):  {own:7.1f} ms  (includes the 20 ms debounce)")
        if nxt:
            other = self.first_change_ms(changes, nxt, "RUN-self", 0)
            print(f"  press -> RUN-self LED off at station {nxt} (next): {other:7.1f} ms  (+ TPDO1 over CAN)")
        for i, ch in sorted(changes.items()):
            text = ", ".join(f"{name} {'on' if v else 'off'} {ms:+.1f} ms" for ms, name, v in ch)
            print(f"  station {i}: {text or 'no LED changed'}")


