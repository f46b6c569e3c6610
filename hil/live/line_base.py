"""What both kinds of live run share: options, the temp directory, the
processes, the plants (mb2co-plant, one per station), the report lines."""
import os
import signal
import sys
import tempfile
import time

from line_views import PlantView
from live_procs import Failure, Pump

# The plant controller's states in which the belt runs (docs/plant.md).
RUNNING_STATES = r"^state (moving|approach|filling)$"
# A loaded machine (or user-mode Linux) must not make a plant lose its link
# (that would stop a station and change the scenario); a real Uno answers
# well within these too. The run checks the line, it is no control loop.
PLANT_OPTIONS = ["--timeout-ms", "500", "--retries", "3"]


class Run:
    """Options, processes, the report as it grows."""

    def __init__(self, a):
        self.a = a
        self.n = a.stations
        self.ring = a.topology == "ring"
        self.t0 = time.monotonic()
        self.tmp = tempfile.mkdtemp(prefix="mb2co-live-")
        self.pump = Pump(echo=self.echo if a.verbose else None)
        self.nodes = {}
        self.plants = {}

    def echo(self, proc, text):
        sys.stderr.write(f"{time.monotonic() - self.t0:8.3f} {proc.name}: {text}\n")

    def say(self, text):
        print(f"{time.monotonic() - self.t0:6.2f} s  {text}", flush=True)

    def wait(self, cond, what, timeout_s=None):
        self.pump.wait(cond, what, self.a.timeout if timeout_s is None else timeout_s)

    def wait_matching(self, mismatch, what):
        """Waits until `mismatch()` returns None; a failure also names the
        last difference it returned."""
        last = [None]

        def ok():
            last[0] = mismatch()
            return last[0] is None

        try:
            self.wait(ok, what)
        except Failure as f:
            raise Failure(f"{f} ({last[0]})") from None

    def save_logs(self):
        for proc in self.pump.procs:
            name = proc.name.replace(" ", "-")
            with open(os.path.join(self.tmp, name + ".log"), "w") as f:
                f.write("# " + " ".join(proc.argv) + "\n")
                f.writelines(f"{t - self.t0:.3f} {text}\n" for t, text in proc.lines)
                f.writelines(f"stderr: {text}\n" for text in proc.err)

    # --- plants (both modes) ---------------------------------------------

    def start_plants(self, ports, extra):
        for i, port in enumerate(ports, 1):
            view = PlantView(i)
            argv = [self.a.plant, "--port", port, "--plain", *extra(i)]
            view.proc = self.pump.start(f"mb2co-plant {i}", argv, view.on_line)
            self.plants[i] = view
        for i, view in self.plants.items():
            # The first read of the panel: from here on a press is an edge.
            self.wait(lambda: view.seen_since(0, r"^link up ") and view.seen_since(0, r"^buttons none$"),
                      f"plant {i}: link up to {ports[i - 1]} and first read of the panel")

    def stop_plants(self):
        """SIGTERM: each plant writes RUN=0, closes the port and exits 0."""
        for view in self.plants.values():
            view.proc.exit_expected = True
            view.proc.signal(signal.SIGTERM)
        for i, view in self.plants.items():
            code = self.pump.wait_exit(view.proc, self.a.timeout)
            if code != 0:
                raise Failure(f"plant {i}: exit code {code} after SIGTERM, want 0: {view.proc.last_words()}")
            if not view.seen_since(0, r"^SIGTERM: RUN=0 written, port closed$"):
                raise Failure(f"plant {i}: no 'SIGTERM: RUN=0 written, port closed' line")


