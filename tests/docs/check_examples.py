#!/usr/bin/env python3
"""Every example in README.md and docs/*.md runs, or says why it does not.

A code block (fenced or indented by four spaces) that holds a command line is
either

* a ```console block of a page that a ctest runs through tests/labs/run_doc.py
  (the command and what it prints are checked there), or
* preceded by a marker this check knows, on the line before the block:

  <!-- example: needs hardware (WHAT) -->       a Uno, a CAN adapter, ...
  <!-- example: synopsis -->                     usage lines: every option they
                                                 name is in `PROGRAM --help`
                                                 (or `PROGRAM COMMAND --help`)
  <!-- example: output, ctest NAME -->           output only; ctest NAME
                                                 produces it (it must exist)
  <!-- example: run by ctest NAME -->            these commands are what
                                                 ctest NAME runs (it must exist)
  <!-- example: benchmark, PAGE -->              measured figures, with how
                                                 they are measured on PAGE
  <!-- example: build -->                        building or installing

For every marked block, the scripts it names by a source path (hil/...,
scripts/..., tests/..., firmware/...) must exist. A block without a marker
fails with its page and line.

Usage: check_examples.py --source DIR --build DIR
"""
import argparse
import glob
import os
import re
import shlex
import subprocess
import sys

# First words that make a line a command (after "$ ", VAR=value and sudo).
COMMANDS = {
    "bash", "candump", "cangen", "cansend", "cat", "clang++", "cmake", "cocomm", "ctest", "echo", "export",
    "ip", "kill", "mbpoll", "mkdir", "modprobe", "nc", "python3", "slcand", "socat", "source", "ssh",
    "strace", "stty", "tail", "touch", "valgrind",
}
SOURCE_DIRS = ("hil/", "scripts/", "tests/", "firmware/")
PROGRAM_DIRS = ("build/", "build-perf/", "./", "/usr/bin/")
MARKER = re.compile(r"^<!--\s*example:\s*(.*?)\s*-->\s*$")
KINDS = ("needs hardware", "synopsis", "output", "run by ctest", "benchmark", "build")


class Block:
    def __init__(self, page, line_no, info, lines, marker):
        self.page = page
        self.line_no = line_no  # 1-based line of the block's first line (the fence for a fenced one)
        self.info = info  # the fence's info string ("console", "" ...), None when indented
        self.lines = lines
        self.marker = marker  # the marker's text after "example:", or None

    def where(self):
        return f"{self.page}:{self.line_no}"


def blocks_of(page, text):
    """The code blocks of a markdown page, each with the marker before it."""
    lines = text.split("\n")
    out = []
    i = 0
    in_list = False

    def marker_before(k):
        j = k - 1
        while j >= 0 and not lines[j].strip():
            j -= 1
        m = MARKER.match(lines[j].strip()) if j >= 0 else None
        return m.group(1) if m else None

    while i < len(lines):
        line = lines[i]
        fence = re.match(r"^ {0,3}(```+|~~~+)\s*([^`\s]*)", line)
        if fence:
            start = i
            body = []
            i += 1
            while i < len(lines) and not lines[i].lstrip().startswith(fence.group(1)):
                body.append(lines[i])
                i += 1
            out.append(Block(page, start + 1, fence.group(2), body, marker_before(start)))
            i += 1
            continue
        if re.match(r"^\s*([*+-]|\d+\.)\s", line):
            in_list = True  # an indented paragraph after a list item continues the item
        elif line.strip() and not line.startswith(" "):
            in_list = False
        if line.startswith("    ") and line.strip() and not in_list and (i == 0 or not lines[i - 1].strip()):
            start = i
            body = []
            while i < len(lines) and (lines[i].startswith("    ") or not lines[i].strip()):
                body.append(lines[i][4:])
                i += 1
            while body and not body[-1].strip():
                body.pop()
            out.append(Block(page, start + 1, None, body, marker_before(start)))
            continue
        i += 1
    return out


def command_words(line):
    """The program a line runs (its first word, after a prompt, VAR=, sudo), or None."""
    text = line.strip()
    if text.startswith("$ "):
        text = text[2:].strip()
    try:
        words = shlex.split(text, comments=True)
    except ValueError:
        words = text.split()
    while words and (re.match(r"^[A-Za-z_]\w*=", words[0]) or words[0] == "sudo"):
        words = words[1:]
    if not words:
        return None
    first = words[0]
    if first in COMMANDS or first.startswith("mb2co-") or first.startswith("$"):
        return words
    if first.startswith(SOURCE_DIRS) or first.startswith(PROGRAM_DIRS):
        return words
    return None


def holds_command(block):
    if block.info is not None and block.info not in ("", "console", "sh", "bash", "shell"):
        return False  # ```cpp, ```ini, ```output ...: no command lines
    if block.info == "console":
        return True
    # Continuation lines (indented) belong to the command above them.
    return any(command_words(line) for line in block.lines if not line.startswith((" ", "\t")))


def source_paths(block):
    """The source-tree scripts a block's commands name."""
    paths = []
    for line in block.lines:
        words = command_words(line) or []
        for w in words:
            if w.startswith(SOURCE_DIRS) and not any(c in w for c in "*$<["):
                paths.append(w)
    return paths


def options_named(line):
    return re.findall(r"(?<![\w\-/.:])(--?[A-Za-z][\w-]*)", line)


def synopsis_problems(block, help_of):
    """Options a synopsis names that its program's --help does not."""
    problems = []
    program = None
    command = None
    for line in block.lines:
        if line.startswith(" ") and program:
            words = line.split()
        else:
            words = command_words(line)
            if not words:
                continue
            program = words[0]
            # A command (`serve`, `rta`): the first bare word that has a --help of its own.
            command = next((w for w in words[1:4] if re.match(r"^[a-z][a-z-]*$", w) and help_of(program, w)), None)
            words = words[1:]
        text = help_of(program, None)
        if text is None:
            problems.append(f"{program}: no such program in the build (synopsis)")
            continue
        if command:
            text += help_of(program, command) or ""
        for opt in options_named(" ".join(words)):
            if opt in ("--help", "-h") and ("--help" in text):
                continue
            if not re.search(r"(?<![\w-])" + re.escape(opt) + r"(?![\w-])", text):
                problems.append(f"{opt} is not in `{program}{' ' + command if command else ''} --help`")
    return problems


def check(source, run_pages, ctest_names, help_of):
    """All failures as 'page:line: text' lines."""
    failures = []
    pages = [os.path.join(source, "README.md")] + sorted(glob.glob(os.path.join(source, "docs", "*.md")))
    for path in pages:
        page = os.path.relpath(path, source)
        with open(path, encoding="utf-8") as f:
            blocks = blocks_of(page, f.read())
        for b in blocks:
            if b.marker is None:
                if b.info == "console":
                    if page not in run_pages:
                        failures.append(f"{b.where()}: a console block, but no ctest runs {page} through run_doc.py")
                elif holds_command(b):
                    failures.append(f"{b.where()}: a command no test runs: a ```console block of a page a ctest "
                                    f"runs, or a marker (<!-- example: KIND -->, KIND one of {', '.join(KINDS)})")
                continue
            kind = next((k for k in KINDS if b.marker.startswith(k)), None)
            rest = b.marker[len(kind):].strip(" ,") if kind else ""
            if kind is None:
                failures.append(f"{b.where()}: unknown example marker '{b.marker}' (known: {', '.join(KINDS)})")
                continue
            if kind == "needs hardware" and not re.match(r"^\(.+\)$", rest):
                failures.append(f"{b.where()}: say which hardware: <!-- example: needs hardware (a Uno on ...) -->")
            if kind in ("output", "run by ctest"):
                name = re.sub(r"^ctest\s+", "", rest)
                # gtest cases are ctests of their own: a name may stand for all of its cases.
                if not name or not any(n == name or n.startswith(name + ".") for n in ctest_names):
                    failures.append(f"{b.where()}: {kind}: no ctest named '{name}'")
            if kind == "benchmark" and not os.path.isfile(os.path.join(source, rest)):
                failures.append(f"{b.where()}: benchmark: name the page that says how it is measured, not '{rest}'")
            if kind == "synopsis":
                failures += [f"{b.where()}: {p}" for p in synopsis_problems(b, help_of)]
            for p in source_paths(b):
                if not os.path.exists(os.path.join(source, p)):
                    failures.append(f"{b.where()}: {p} does not exist")
    return failures


def pages_run_by_ctest(build, source):
    """Pages that a ctest hands to run_doc.py, and every ctest name."""
    out = subprocess.run(["ctest", "--test-dir", build, "-N", "-V"], capture_output=True, text=True,
                         check=True).stdout
    pages = set()
    for line in out.split("\n"):
        if "Test command:" in line and "run_doc.py" in line:
            for arg in re.findall(r'"([^"]+\.md)"', line):
                pages.add(os.path.relpath(arg, source))
    names = set(re.findall(r"Test +#\d+: (\S+)", out))
    return pages, names


def help_reader(build, source):
    found = {}
    for root, _, files in os.walk(build):
        for name in files:
            full = os.path.join(root, name)
            if name.startswith("mb2co-") and os.access(full, os.X_OK) and name not in found:
                found[name] = full
    cache = {}

    def help_of(program, command):
        exe = found.get(os.path.basename(program))
        if exe is None and os.path.isfile(os.path.join(source, program)):
            exe = os.path.join(source, program)
        if exe is None:
            return None
        key = (exe, command)
        if key not in cache:
            args = [exe] + ([command] if command else []) + ["--help"]
            r = subprocess.run(args, capture_output=True, text=True, timeout=20, stdin=subprocess.DEVNULL)
            cache[key] = r.stdout + r.stderr if r.returncode == 0 or not command else ""
        return cache[key]

    return help_of


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--source", required=True)
    ap.add_argument("--build", required=True)
    args = ap.parse_args()
    source = os.path.abspath(args.source)
    run_pages, names = pages_run_by_ctest(os.path.abspath(args.build), source)
    failures = check(source, run_pages, names, help_reader(os.path.abspath(args.build), source))
    for f in failures:
        print(f)
    print(f"pages run by ctest: {', '.join(sorted(run_pages))}; {len(failures)} examples fail")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
