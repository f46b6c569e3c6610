"""Child processes of a live run and the one loop that reads them.

Every process's stdout and stderr are read line by line through one selector;
the run waits for conditions on what was read, each wait with a deadline that
only turns a hang into a failure (nothing here sleeps to synchronise).
Standard library only: this runs under /usr/bin/python3, also inside
user-mode Linux where every extra import costs time.
"""
import os
import selectors
import signal
import subprocess
import time


class Failure(Exception):
    """A failed check; str(self) is the one line that names it."""


class Proc:
    """One child process. `on_line(text)` is called for every stdout line;
    `lines` keeps them all (with the script's monotonic time), `err` the
    stderr lines. `exit_expected` is set before a deliberate stop: a process
    that ends without it fails the run."""

    def __init__(self, name, argv, on_line=None, stdin=False):
        self.name = name
        self.argv = argv
        self.on_line = on_line
        self.lines = []  # (monotonic_s, text)
        self.err = []
        self.exit_expected = False
        self.code = None
        try:
            self.p = subprocess.Popen(argv, stdin=subprocess.PIPE if stdin else subprocess.DEVNULL,
                                      stdout=subprocess.PIPE, stderr=subprocess.PIPE)
        except OSError as e:
            raise Failure(f"{name}: cannot start {argv[0]}: {e.strerror}") from None
        self._partial = {self.p.stdout.fileno(): b"", self.p.stderr.fileno(): b""}

    def send(self, text):
        """Writes `text` (whole lines) in one write: lines sent together reach
        the process together (a pipe write below PIPE_BUF is atomic)."""
        try:
            os.write(self.p.stdin.fileno(), text.encode())
        except OSError as e:
            raise Failure(f"{self.name}: cannot write '{text.strip()}': {e.strerror}") from None

    def signal(self, sig):
        if self.p.poll() is None:
            self.p.send_signal(sig)

    def last_words(self):
        """The last stderr line, or the last stdout line: why it ended."""
        if self.err:
            return self.err[-1]
        return self.lines[-1][1] if self.lines else "no output"

    def _feed(self, fd, data):
        """Splits `data` into lines; returns False at end of file."""
        if not data:
            return False
        buf = self._partial[fd] + data
        *whole, self._partial[fd] = buf.split(b"\n")
        for raw in whole:
            text = raw.decode(errors="replace")
            if fd == self.p.stdout.fileno():
                self.lines.append((time.monotonic(), text))
                if self.on_line:
                    self.on_line(text)
            else:
                self.err.append(text)
        return True


class Pump:
    """Reads every registered process; `wait` runs it until a condition holds."""

    def __init__(self, echo=None):
        self.sel = selectors.DefaultSelector()
        self.procs = []
        self.echo = echo  # callable(proc, text) for --verbose, or None

    def start(self, name, argv, on_line=None, stdin=False):
        proc = Proc(name, argv, on_line, stdin)
        self.procs.append(proc)
        for stream in (proc.p.stdout, proc.p.stderr):
            os.set_blocking(stream.fileno(), False)
            self.sel.register(stream.fileno(), selectors.EVENT_READ, proc)
        return proc

    def poll(self, timeout_s):
        for key, _ in self.sel.select(timeout_s):
            proc = key.data
            try:
                data = os.read(key.fd, 65536)
            except BlockingIOError:
                continue
            before = (len(proc.lines), len(proc.err))
            if not proc._feed(key.fd, data):
                self.sel.unregister(key.fd)
                if not any(k.data is proc for k in self.sel.get_map().values()):
                    proc.code = proc.p.wait()
            elif self.echo:
                for _, text in proc.lines[before[0]:]:
                    self.echo(proc, text)
                for text in proc.err[before[1]:]:
                    self.echo(proc, "stderr: " + text)

    def wait(self, cond, what, timeout_s):
        """Reads output until `cond()` holds; Failure naming `what` when
        `timeout_s` passes first or a process ends unasked."""
        deadline = time.monotonic() + timeout_s
        while True:
            if cond():
                return
            for proc in self.procs:
                if proc.code is not None and not proc.exit_expected:
                    raise Failure(f"{what}: {proc.name} ended (exit {proc.code}): {proc.last_words()}")
            left = deadline - time.monotonic()
            if left <= 0:
                raise Failure(f"{what}: not within {timeout_s:g} s")
            self.poll(min(left, 0.5))

    def wait_exit(self, proc, timeout_s):
        """The exit code of a process asked to end."""
        proc.exit_expected = True
        self.wait(lambda: proc.code is not None, f"{proc.name} exits", timeout_s)
        return proc.code

    def kill_all(self):
        """Ends whatever is still running: SIGTERM (a plant then writes
        RUN=0), SIGKILL after 2 s."""
        for proc in self.procs:
            proc.exit_expected = True
            proc.signal(signal.SIGTERM)
        deadline = time.monotonic() + 2.0
        for proc in self.procs:
            try:
                proc.p.wait(timeout=max(deadline - time.monotonic(), 0.01))
            except subprocess.TimeoutExpired:
                proc.p.kill()
                proc.p.wait()
