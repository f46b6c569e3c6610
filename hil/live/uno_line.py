"""The line of simulated Unos: N mb2co-uno (the very image flashed onto the
Arduino, in simavr) on a CAN interface, each given its place exactly as
docs/mini-project.md tells a student (mbpoll on its serial line, alone: node
id, topology, stations, save, reset node) and then powered on from its EEPROM
file, and N mb2co-plant on the ptys (the run's PLANT_OPTIONS, or with
--plant-defaults their documented defaults). What the
run checks is what a student looks at: the boards' RUN LEDs (`leds` lines)
and the PCs' logs. mb2co-uno has no `state` lines: the RUN state is the
RUN-self LED, the stop cause the plant's log."""
import os
import re
import signal
import subprocess

from line_base import RUNNING_STATES
from line_views import NodeView, expected_leds, neighbours
from live_procs import Failure
from sim_line import SimulatedLine

# docs/mini-project.md, "Give each Uno its place": P="mbpoll ... -o 3 -t 4".
MBPOLL = ["mbpoll", "-m", "rtu", "-b", "115200", "-P", "none", "-a", "1", "-0", "-1", "-o", "3"]
SAVE = ["0x6576", "0x6173"]  # HR 11-12 = 1010h/1 "save"
MBPOLL_VALUE_RX = re.compile(r"^\[(\d+)\]:\s+(-?\d+)", re.M)


class UnoLine(SimulatedLine):
    """N mb2co-uno given their places over Modbus, N mb2co-plant (defaults)."""

    def eeprom(self, i):
        return os.path.join(self.tmp, f"uno{i}.eep")

    def mbpoll(self, tty, table, reg, values=(), count=None):
        """One mbpoll run as the guide writes it; its stdout. A non-zero exit
        fails the run with mbpoll's own words."""
        argv = MBPOLL + ["-t", str(table), "-r", str(reg)] + (["-c", str(count)] if count else []) + [tty]
        argv += [str(v) for v in values]
        try:
            r = subprocess.run(argv, stdin=subprocess.DEVNULL, capture_output=True, text=True,
                               timeout=self.a.timeout)
        except subprocess.TimeoutExpired:
            raise Failure(f"{' '.join(argv)}: no end within {self.a.timeout:g} s") from None
        if r.returncode != 0:
            words = (r.stderr.strip() or r.stdout.strip()).splitlines()
            raise Failure(f"{' '.join(argv)}: exit {r.returncode}: {words[-1] if words else ''}")
        return r.stdout

    def start_uno(self, i, name, can, tty):
        view = NodeView(i)
        argv = [self.a.uno, "--can", can, "--pty", tty, "--eeprom", self.eeprom(i)]
        view.proc = self.pump.start(name, argv, view.on_line, stdin=True)
        self.wait(lambda: view.ready is not None, f"{name}: ready line")
        return view

    def give_place(self, i):
        """Station i's board alone on its serial line (no CAN): the guide's
        mbpoll lines, then input registers 20 and 21 name its neighbours."""
        tty = os.path.join(self.tmp, f"alone{i}")
        view = self.start_uno(i, f"mb2co-uno {i} alone", "none", tty)
        if view.ready["node"] != 1:
            raise Failure(f"station {i}: a fresh board is node {view.ready['node']}, want 1")
        self.mbpoll(tty, 4, 2, [i])                                              # HR 2: node id
        self.mbpoll(tty, 4, 4, [int(self.ring), self.n])                         # HR 4, 5: topology, stations
        self.mbpoll(tty, 4, 11, SAVE)                                            # HR 11-12: save
        self.mbpoll(tty, 4, 13, [2])                                             # HR 13: reset node
        prev, nxt = neighbours(i, self.n, self.ring)
        want = {20: prev or 0, 21: nxt or 0}
        last = {}

        def named():
            last.update({int(r): int(v) for r, v in MBPOLL_VALUE_RX.findall(self.mbpoll(tty, 3, 20, count=2))})
            return last == want

        self.wait(named, f"station {i}: input registers 20, 21 = {want[20]}, {want[21]} after the reset "
                         f"(read {last})")
        view.proc.exit_expected = True
        view.proc.send("quit\n")
        code = self.pump.wait_exit(view.proc, self.a.timeout)
        if code != 0:
            raise Failure(f"station {i}: mb2co-uno exit {code} after quit, want 0: {view.proc.last_words()}")

    def power_on(self, i):
        view = self.start_uno(i, f"mb2co-uno {i}", self.a.can, os.path.join(self.tmp, f"st{i}"))
        if view.ready["node"] != i:
            raise Failure(f"station {i}: powered on as node {view.ready['node']}, want {i} (the saved id)")
        view.proc.send("leds?\n")  # the LEDs as they are, before the first change
        self.nodes[i] = view
        return view

    def start_nodes(self):
        for i in range(1, self.n + 1):
            self.give_place(i)
        self.say(f"{self.n} boards given their places over Modbus (mbpoll: id, {self.a.topology}, "
                 f"{self.n} stations, save, reset node)")
        for i in range(1, self.n + 1):
            self.power_on(i)

    # --- conditions: what the boards' LEDs show -----------------------------

    def mismatch(self, running, causes=None):
        """None when every board's RUN LEDs show exactly `running`; else the
        first difference. (Stop causes are the plants' log's: see run().)"""
        for i, v in self.nodes.items():
            if v.leds is None:
                return f"station {i} has not shown its LEDs"
            want = expected_leds(i, self.n, self.ring, running)
            got = (v.leds["self"], v.leds["prev"], v.leds["next"])
            if got != want:
                return f"station {i} LEDs self/prev/next={'/'.join(map(str, got))}, want {'/'.join(map(str, want))}"
        return None

    def click(self, stations, button, plant_sees):
        """As SimulatedLine.click, but an operator's way with a link that
        drops: a simulated Uno on a loaded host can answer later than the
        plant's 25 ms default, the plant then goes safe and reconnects, and a
        button held across that is no press for it (its first read after
        "link up" is the baseline). Then the button is released, and pressed
        again once the plant reads the panel empty: at most 5 times."""
        for i in stations:
            plant = self.plants[i]
            for attempt in range(6):
                mark = len(plant.events)
                self.press(i, button)
                self.wait(lambda: plant.seen_since(mark, plant_sees) or plant.seen_since(mark, r"^link lost"),
                          f"plant {i}: /{plant_sees}/ after {button} pressed at station {i}")
                if plant.seen_since(mark, plant_sees):
                    break
                if attempt == 5:
                    raise Failure(f"plant {i}: the link dropped at each of 6 presses of {button}")
                self.command(i, f"release {button}")
                self.wait(lambda: self.empty_panel_after_link_up(i, mark),
                          f"plant {i}: link up again, panel empty, after {button} released at station {i}")
        marks = {i: len(self.plants[i].events) for i in stations}
        for i in stations:
            self.command(i, f"release {button}")
        for i in stations:
            self.wait(lambda: self.plants[i].seen_since(marks[i], r"^buttons none$"),
                      f"plant {i}: panel empty after {button} released at station {i}")

    def empty_panel_after_link_up(self, i, mark):
        events = self.plants[i].events[mark:]
        ups = [j for j, e in enumerate(events) if e.startswith("link up ")]
        return bool(ups) and any(e == "buttons none" for e in events[ups[-1]:])

    def blinking_since(self, i, mark, led):
        """Board i's `led` read "blink" after its event `mark` (mb2co-uno
        says so once the LED has toggled twice within 300 ms, as mb2co-node
        says it from the neighbour's status: docs/uno-sim.md)."""
        return self.nodes[i].first_event_since(mark, lambda kind, f: kind == "leds" and f[led] == "blink")

    def ran_since(self, i, mark):
        return self.nodes[i].first_event_since(mark, lambda kind, f: kind == "leds" and f["self"] == 1)

    # --- the scenario -----------------------------------------------------

    def run(self):
        n, k = self.n, self.a.stop2_at
        every = list(range(1, n + 1))
        self.start_nodes()
        self.say(f"{n} mb2co-uno powered on on {self.a.can} ({self.a.topology}), each on its saved id")
        options = self.start_station_plants()
        self.say(f"{n} mb2co-plant ({options}) linked, panels read")

        # 1. START everywhere.
        self.click(every, "START", RUNNING_STATES)
        self.wait_line(set(every), "after START everywhere, every board's RUN LEDs self/prev/next on")
        self.say("[ok] START at every station: all run, every RUN LED as the guide says")

        # 2. STOP2 at k: k and the next stop, the PCs say why; the rest runs on.
        _, nxt = neighbours(k, n, self.ring)
        stopped = {k} | ({nxt} if nxt else set())
        marks = {i: len(self.nodes[i].events) for i in every}
        plant_marks = {i: len(self.plants[i].events) for i in every}
        self.click([k], "STOP2", r"^buttons STOP2$")
        self.wait_stop2_logged(k, nxt, plant_marks)
        running = set(every) - stopped
        self.wait_line(running, f"after STOP2 at station {k}, {sorted(stopped)} stopped, {sorted(running)} run on")
        self.never_stopped(sorted(running), marks, plant_marks, f"STOP2 at station {k}")
        self.say(f"[ok] STOP2 at station {k}: {', '.join(map(str, sorted(stopped)))} stopped "
                 f"(the PCs: local_stop2{', prev_stop2' if nxt else ''}); "
                 f"{', '.join(map(str, sorted(running))) or 'no other'} run on")

        # 3. START at the stopped ones.
        self.click(sorted(stopped), "START", RUNNING_STATES)
        self.wait_line(set(every), f"after START at {sorted(stopped)}, every station runs again")
        self.say(f"[ok] START at {', '.join(map(str, sorted(stopped)))}: every station runs again")

        # 4. Station p loses its power and gets it back: its PC goes safe and
        # reconnects by itself; the board starts stopped and stays stopped
        # (the RUN command is never saved) until a START; the others never stop.
        p = n
        others = [i for i in every if i != p]
        marks = {i: len(self.nodes[i].events) for i in every}
        plant_marks = {i: len(self.plants[i].events) for i in every}
        view = self.nodes[p]
        view.proc.exit_expected = True
        view.proc.signal(signal.SIGKILL)
        self.pump.wait_exit(view.proc, self.a.timeout)
        self.wait(lambda: self.plants[p].seen_since(plant_marks[p], r"^link lost"),
                  f"plant {p}: 'link lost' after station {p}'s power went off")
        watchers = [i for i in others if p in neighbours(i, n, self.ring)]
        for i in watchers:
            side = "prev" if neighbours(i, n, self.ring)[0] == p else "next"
            self.wait(lambda: self.blinking_since(i, marks[i], side),
                      f"station {i}: RUN-{side} LED blinking (station {p} unknown) after its power went off")
        plant_up = len(self.plants[p].events)
        view = self.power_on(p)
        # Its first read of the panel after "link up" is the baseline: a press
        # before it is no edge for the plant (a clean-clone CI run pressed
        # START 35 ms too early and the station never started).
        self.wait(lambda: self.empty_panel_after_link_up(p, plant_up),
                  f"plant {p}: 'link up' again and the panel read after station {p}'s power came back")
        self.wait_line(set(others), f"after station {p}'s power came back: it stands still, the others run")
        # It has been heard (its neighbours show it alive and stopped) and its
        # PC has polled it since: had it run by itself, its RUN-self LED would
        # have been lit by now.
        if self.ran_since(p, 0):
            raise Failure(f"station {p} ran by itself after its power came back")
        self.never_stopped(others, marks, plant_marks, f"station {p}'s power cycle")
        self.click([p], "START", RUNNING_STATES)
        self.wait_line(set(every), f"after START at station {p}, every station runs again")
        self.say(f"[ok] power off and on at station {p}: its PC went safe and reconnected, the board "
                 f"stayed stopped until START; the others ran on")

        # 5. The PCs leave: RUN=0 written, every RUN-self LED goes off.
        self.stop_plants()
        self.wait_line(set(), "after SIGTERM of every plant, every board's RUN LEDs off")
        self.quit_stations()
        self.say("[ok] SIGTERM to every plant: RUN=0 written, exit 0; every RUN LED off; boards off")
