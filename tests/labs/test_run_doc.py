#!/usr/bin/env python3
"""The doc runner itself (tests/labs/run_doc.py), on small pages with plain
shell commands (no CAN): it passes a page that says what the commands print,
and fails, naming the page's line, where the page is wrong."""
import os
import subprocess
import sys
import tempfile
import unittest

RUNNER = os.path.join(os.path.dirname(os.path.abspath(__file__)), "run_doc.py")


def run_page(text):
    with tempfile.TemporaryDirectory() as root:
        os.mkdir(os.path.join(root, "docs"))
        page = os.path.join(root, "docs", "page.md")
        with open(page, "w", encoding="utf-8") as f:
            f.write(text)
        # A short job deadline: one case waits for a line that never comes.
        r = subprocess.run([sys.executable, RUNNER, page, "--build", root, "--job-deadline", "3"],
                           capture_output=True, text=True, timeout=120)
        return r.returncode, r.stdout.replace(page, "PAGE")


class RunDoc(unittest.TestCase):
    def test_exact_output_and_wildcards_pass(self):
        rc, out = run_page("text\n```console\n$ printf 'a\\nb 17 c\\nd\\ne\\n'\na\nb <...> c\n...\ne\n"
                           "$ x=5\n$ echo $x\n5\n```\n")
        self.assertEqual(rc, 0, out)
        self.assertIn("3 steps", out)

    def test_a_wrong_line_fails_with_a_diff_naming_the_command_line(self):
        rc, out = run_page("one\n\n```console\n$ echo yes\nyes\n$ echo no\nmaybe\n```\n")
        self.assertEqual(rc, 1, out)
        self.assertIn("PAGE:6: printed differs from the doc: echo no", out)
        self.assertIn("-maybe", out)
        self.assertIn("+no", out)
        self.assertIn("1 failed", out)

    def test_missing_and_extra_lines_fail(self):
        rc, out = run_page("```console\n$ printf 'a\\nb\\n'\na\n$ echo a\na\nb\n```\n")
        self.assertEqual(rc, 1, out)
        self.assertIn("PAGE:2:", out)
        self.assertIn("PAGE:4:", out)

    def test_a_failing_command_fails_unless_the_page_shows_its_exit(self):
        rc, out = run_page("```console\n$ false\n$ false || echo \"exit code $?\"\nexit code 1\n```\n")
        self.assertEqual(rc, 1, out)
        self.assertIn("PAGE:2: exit status 1: false", out)
        self.assertEqual(out.count("failed"), 1, out)
        self.assertIn("1 failed", out)

    def test_background_jobs_are_waited_for_in_order_and_killable_by_number(self):
        page = ("```console\n$ f=$(mktemp) && echo $f >/dev/null\n"
                "$ tail -f $f &\n[1] <...>\n"
                "$ echo one >> $f; echo noise >> $f; echo two >> $f\n```\n"
                "```output %1\none\ntwo\n```\n"
                "```console\n$ echo three >> $f\n```\n"
                "```output %1\nthree\n```\n"
                "```console\n$ kill %1\n```\n")
        rc, out = run_page(page)
        self.assertEqual(rc, 0, out)

    def test_named_jobs_need_no_job_numbers(self):
        # Two jobs by name, the first restarted under the same name: its
        # output block follows the newest one, and kill finds it by its file.
        page = ("```console\n$ d=$(mktemp -d) && touch $d/f $d/g\n"
                "$ tail -f $d/f & echo $! > $d/reader.pid\n[<...>] <...>\n"
                "$ tail -f $d/g & echo $! > $d/other-reader.pid\n[<...>] <...>\n"
                "$ echo one >> $d/f; echo two >> $d/g\n```\n"
                "```output reader\none\n```\n"
                "```output other-reader\ntwo\n```\n"
                "```console\n$ kill $(cat $d/reader.pid); wait $(cat $d/reader.pid) || true\n"
                "$ : > $d/f; tail -f $d/f & echo $! > $d/reader.pid\n[<...>] <...>\n"
                "$ echo three >> $d/f\n```\n"
                "```output reader\nthree\n```\n")
        rc, out = run_page(page)
        self.assertEqual(rc, 0, out)

    def test_a_named_job_that_never_prints_a_line_fails_naming_the_block(self):
        page = ("```console\n$ d=$(mktemp -d) && touch $d/f\n$ tail -f $d/f & echo $! > $d/reader.pid\n"
                "$ echo one >> $d/f\n```\n"
                "```output reader\ntwo\n```\n")
        rc, out = run_page(page)
        self.assertEqual(rc, 1, out)
        self.assertIn("PAGE:6: job reader never printed a line like the doc's", out)

    def test_a_line_a_job_never_prints_fails_naming_the_block(self):
        page = ("```console\n$ f=$(mktemp)\n$ tail -f $f &\n[1] <...>\n$ echo one >> $f\n```\n"
                "```output %1\none\none\n```\n")
        rc, out = run_page(page)
        self.assertEqual(rc, 1, out)
        self.assertIn("PAGE:7: job %1 never printed a line like the doc's", out)


if __name__ == "__main__":
    unittest.main()
