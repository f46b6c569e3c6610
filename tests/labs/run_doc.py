#!/usr/bin/env python3
"""Runs every command of a markdown walk-through and checks what it prints.

The convention (docs/labs.md, "How this page is tested"):

* A fenced block ```console holds commands and their output. A line starting
  with "$ " is a command; the lines after it, up to the next command or the
  end of the block, are what it prints (stdout and stderr together).
  Expected output: a line "..." stands for any number of lines; "<...>"
  inside a line stands for any text (times, process ids, pty names).
  Every command must exit with 0 (a refusal is shown with "|| echo ...").
* A command ending in " &" starts a background job, as in an interactive
  shell: its first expected line may be bash's "[N] <...>" (job number and
  process id); the other expected lines are lines the job prints, waited
  for in order, other lines in between being skipped.
* A fenced block ```output %N shows more lines of job N's output, matched
  the same way, continuing after the last line matched for that job.
* Named jobs, which no later step finds by bash's job number: a command
  "COMMAND & echo $! > DIR/NAME.pid" starts job NAME (its first expected
  line may be "[<...>] <...>"), and ```output NAME shows more of the job
  last started as NAME.

All commands run in ONE bash, in the source directory, with the build's
tool directories first on PATH, so that `kill %2`, shell variables and
files in /tmp work as they would for a student. Waits are for output only;
the deadlines bound a failure. A mismatch prints a diff naming the doc line
and the run goes on; the exit status is 1 if anything failed.

Usage: run_doc.py DOC.md --build BUILD_DIR [--record | --verbose] [--job-deadline S]
  --record: print each command with what it really printed (no checking),
            for writing the doc.
  --verbose: check, and print what each command printed.
"""
import argparse
import difflib
import os
import re
import select
import signal
import subprocess
import sys
import tempfile
import time

COMMAND_DEADLINE_S = 90
# "COMMAND & echo $! > DIR/NAME.pid": a background job named NAME.
NAMED_JOB = re.compile(r"^(.*?)\s*&\s*echo \$! >\s*(\S*?([A-Za-z][\w-]*)\.pid)$")
JOB_DEADLINE_S = 60
TOOL_DIRS = [
    "pcapp/master", "firmware/linux/node", "firmware/linux/bridge", "hil/uno", "pcapp/timing", "hil/lab",
    "pcapp/plant", "pcapp/odtool", "hil/demo"
]


class Step:
    def __init__(self, kind, line_no, text, expected):
        self.kind = kind  # "command" or "output"
        self.line_no = line_no
        self.text = text  # the command, or the job spec "%N" or NAME
        self.expected = expected


def parse(path):
    steps = []
    block = None  # "console" or a job spec
    with open(path, encoding="utf-8") as f:
        lines = f.read().split("\n")
    for no, line in enumerate(lines, 1):
        if block is None:
            m = re.match(r"^```(console|output (?:%\d+|[A-Za-z][\w-]*))\s*$", line)
            if m:
                block = m.group(1)
                if block.startswith("output"):
                    steps.append(Step("output", no, block.split()[1], []))
            continue
        if line.startswith("```"):
            block = None
            continue
        if block == "console" and line.startswith("$ "):
            steps.append(Step("command", no, line[2:], []))
        elif steps and (block != "console" or steps[-1].kind == "command"):
            steps[-1].expected.append(line)
        else:
            raise SystemExit(f"{path}:{no}: output before any command in a console block")
    if block is not None:
        raise SystemExit(f"{path}: unterminated code block")
    return steps


def line_regex(expected):
    parts = expected.split("<...>")
    return re.compile("^" + ".*".join(re.escape(p) for p in parts) + "$")


def lines_match(expected, actual):
    """Expected lines (with "..." lines and <...>) against all actual lines."""
    if not expected:
        return not actual
    if expected[0] == "...":
        return any(lines_match(expected[1:], actual[i:]) for i in range(len(actual) + 1))
    return bool(actual) and line_regex(expected[0]).match(actual[0]) is not None and lines_match(
        expected[1:], actual[1:])


class Shell:
    """One bash; commands written to its stdin, their output read to a marker."""

    MARK = "@@labs-doc-rc="

    def __init__(self, cwd, env):
        self.proc = subprocess.Popen(["bash", "--norc", "--noprofile"], cwd=cwd, env=env, stdin=subprocess.PIPE,
                                     stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True, bufsize=1)
        self.buf = ""

    def send(self, text):
        self.proc.stdin.write(text + "\n")
        self.proc.stdin.flush()

    def run(self, command, deadline_s=COMMAND_DEADLINE_S):
        """Returns (exit code or None on timeout, printed lines)."""
        self.send("{ %s\n} </dev/null 2>&1; echo \"%s$?\"" % (command, self.MARK))
        out = []
        end = time.monotonic() + deadline_s
        fd = self.proc.stdout.fileno()
        while True:
            while "\n" in self.buf:
                line, self.buf = self.buf.split("\n", 1)
                if self.MARK in line:
                    before, rc = line.split(self.MARK, 1)
                    if before:
                        out.append(before)
                    return int(rc), out
                out.append(line)
            left = end - time.monotonic()
            if left <= 0:
                return None, out
            ready, _, _ = select.select([fd], [], [], left)
            if ready:
                chunk = os.read(fd, 65536).decode("utf-8", "replace")
                if not chunk:
                    return None, out
                self.buf += chunk


class Job:
    """A background job's output, read from its log file as it grows."""

    def __init__(self, log):
        self.log = log
        self.lines = []
        self.partial = ""
        self.pos = 0
        self.cursor = 0  # lines before it are consumed by earlier checks

    def poll(self):
        try:
            with open(self.log, encoding="utf-8", errors="replace") as f:
                f.seek(self.pos)
                data = f.read()
                self.pos = f.tell()
        except FileNotFoundError:
            return
        data = self.partial + data
        *complete, self.partial = data.split("\n")
        self.lines.extend(complete)

    def wait_for(self, expected, deadline_s=JOB_DEADLINE_S):
        """Each expected line in order; returns the unmatched one or None."""
        end = time.monotonic() + deadline_s
        for e in expected:
            rx = line_regex(e)
            while True:
                while self.cursor < len(self.lines):
                    self.cursor += 1
                    if rx.match(self.lines[self.cursor - 1]):
                        break
                else:
                    if time.monotonic() > end:
                        return e
                    self.poll()
                    time.sleep(0.02)  # polls a growing file; not a synchronisation
                    continue
                break
        return None


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("doc")
    ap.add_argument("--build", required=True)
    ap.add_argument("--record", action="store_true")
    ap.add_argument("--verbose", action="store_true", help="also print what each checked command printed")
    ap.add_argument("--job-deadline", type=float, default=JOB_DEADLINE_S,
                    help="seconds to wait for a line of a background job (bounds a failure)")
    args = ap.parse_args()
    doc = os.path.abspath(args.doc)
    source = os.path.dirname(os.path.dirname(doc))
    build = os.path.abspath(args.build)
    steps = parse(doc)
    env = dict(os.environ)
    env["PATH"] = ":".join([os.path.join(build, d) for d in TOOL_DIRS] + [env.get("PATH", "/usr/bin:/bin")])
    env["LC_ALL"] = "C"
    logs = tempfile.mkdtemp(prefix="labs-doc-")
    shell = Shell(source, env)
    jobs = {}
    failures = 0
    started = time.monotonic()

    def fail(step, title, expected, actual):
        nonlocal failures
        failures += 1
        print(f"{doc}:{step.line_no}: {title}")
        for d in difflib.unified_diff(expected, actual, "doc", "printed", lineterm="", n=50):
            print("    " + d)
        sys.stdout.flush()

    for n, step in enumerate(steps):
        named = NAMED_JOB.match(step.text) if step.kind == "command" else None
        if step.kind == "command" and (named or step.text.endswith("&")):
            log = os.path.join(logs, f"job{n}.log")
            command = named.group(1) if named else step.text[:-1].rstrip()
            shell.send(f"{command} >{log} 2>&1 &")
            rc, out = shell.run((f"echo $! > {named.group(2)}; " if named else "") + "jobs -l %+")
            m = re.match(r"^\[(\d+)\]\+\s+(\d+)", out[0] if out else "")
            if rc != 0 or not m:
                fail(step, f"background job did not start: {step.text}", [], out)
                continue
            jobs["%" + m.group(1)] = Job(log)
            if named:
                jobs[named.group(3)] = jobs["%" + m.group(1)]
            announced = f"[{m.group(1)}] {m.group(2)}"
            expected = list(step.expected)
            if args.record:
                print(f"$ {step.text}\n{announced}")
                time.sleep(3)
                jobs["%" + m.group(1)].poll()
                print("\n".join(jobs["%" + m.group(1)].lines[:12]))
                continue
            if expected and re.match(r"^\[(\d+|<\.\.\.>)\] ", expected[0]):
                if not line_regex(expected[0]).match(announced):
                    fail(step, f"job number: {step.text}", expected[:1], [announced])
                expected = expected[1:]
            missing = jobs["%" + m.group(1)].wait_for(expected, args.job_deadline)
            if missing is not None:
                fail(step, f"job [{m.group(1)}] never printed a line like the doc's: {step.text}", [missing],
                     jobs["%" + m.group(1)].lines[-20:])
        elif step.kind == "command":
            rc, out = shell.run(step.text)
            if args.record:
                print(f"$ {step.text}\n" + "\n".join(out) + ("" if rc == 0 else f"\n[exit {rc}]"))
                continue
            if args.verbose:
                print(f"$ {step.text}\n" + "\n".join(out))
            if rc is None:
                fail(step, f"no end within {COMMAND_DEADLINE_S} s: {step.text}", step.expected, out)
                break
            if rc != 0:
                fail(step, f"exit status {rc}: {step.text}", step.expected, out)
            elif not lines_match(step.expected, out):
                fail(step, f"printed differs from the doc: {step.text}", step.expected, out)
        else:
            job = jobs.get(step.text)
            if job is None:
                fail(step, f"no background job {step.text}", step.expected, [])
                continue
            if args.record:
                time.sleep(2)
                job.poll()
                print(f"--- output {step.text}\n" + "\n".join(job.lines[job.cursor:][-40:]))
                job.cursor = len(job.lines)
                continue
            missing = job.wait_for(step.expected, args.job_deadline)
            if missing is not None:
                fail(step, f"job {step.text} never printed a line like the doc's", [missing],
                     job.lines[max(job.cursor - 20, 0):])
    # The jobs still running (nodes, watch, candump) end with the run, also
    # outside a sandbox: every process of every job, by its pid.
    rc, out = shell.run("jobs -l")
    for line in out if rc == 0 else []:
        m = re.match(r"^\s*(?:\[\d+\][+-]?\s+)?(\d+)\s", line)
        if m:
            try:
                os.kill(int(m.group(1)), signal.SIGTERM)
            except ProcessLookupError:
                pass
    shell.proc.stdin.close()
    shell.proc.wait()
    print(f"{len(steps)} steps of {doc}, {failures} failed, {time.monotonic() - started:.1f} s")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
