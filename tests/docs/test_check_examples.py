#!/usr/bin/env python3
"""check_examples.py on small pages: an unmarked command fails with its page
and line, a marked one passes, a marker's claims are checked."""
import os
import sys
import tempfile
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import check_examples  # noqa: E402

HELP = {("mb2co-demo", None): "usage: mb2co-demo [--port DEV] [--baud N]\n  -h, --help\n"}


def help_of(program, command):
    return HELP.get((os.path.basename(program), command))


class CheckExamples(unittest.TestCase):
    def run_page(self, text, run_pages=(), names=("demo.works",)):
        with tempfile.TemporaryDirectory() as source:
            os.mkdir(os.path.join(source, "docs"))
            with open(os.path.join(source, "README.md"), "w") as f:
                f.write("# readme\n")
            with open(os.path.join(source, "docs", "page.md"), "w") as f:
                f.write(text)
            return check_examples.check(source, set(run_pages), set(names), help_of)

    def test_an_unmarked_indented_command_fails_with_page_and_line(self):
        failures = self.run_page("# page\n\nText.\n\n    build/pcapp/plant/mb2co-plant --port /tmp/x\n")
        self.assertEqual(len(failures), 1)
        self.assertTrue(failures[0].startswith("docs/page.md:5: a command no test runs"), failures)

    def test_an_unmarked_fenced_command_fails(self):
        failures = self.run_page("# page\n\n```\n$ mbpoll -a 1 /tmp/x\n```\n")
        self.assertEqual([f.split(":")[1] for f in failures], ["3"])

    def test_marked_blocks_pass(self):
        page = ("<!-- example: needs hardware (a Uno on /dev/ttyACM0) -->\n\n    mb2co-demo --port /dev/ttyACM0\n\n"
                "<!-- example: synopsis -->\n\n    mb2co-demo [--port DEV] [--baud N]\n\n"
                "<!-- example: run by ctest demo.works -->\n\n    mb2co-demo --port /tmp/x\n")
        self.assertEqual(self.run_page(page), [])

    def test_output_and_prose_need_no_marker(self):
        page = "Text:\n\n    node 3: configured\n    presses=3 missed=0\n\n* item\n\n    continued item text\n"
        self.assertEqual(self.run_page(page), [])

    def test_a_synopsis_option_missing_from_the_help_fails(self):
        failures = self.run_page("<!-- example: synopsis -->\n\n    mb2co-demo [--port DEV] [--parity P]\n")
        self.assertEqual(len(failures), 1)
        self.assertIn("--parity is not in `mb2co-demo --help`", failures[0])

    def test_a_marker_naming_no_ctest_fails(self):
        failures = self.run_page("<!-- example: output, ctest demo.gone -->\n\n    mb2co-demo --port /tmp/x\n")
        self.assertIn("no ctest named 'demo.gone'", failures[0])

    def test_hardware_without_saying_which_fails(self):
        failures = self.run_page("<!-- example: needs hardware -->\n\n    mb2co-demo --port /dev/ttyACM0\n")
        self.assertIn("say which hardware", failures[0])

    def test_a_console_block_of_a_page_no_ctest_runs_fails(self):
        page = "```console\n$ mb2co-demo --help\n```\n"
        self.assertEqual(len(self.run_page(page)), 1)
        self.assertEqual(self.run_page(page, run_pages=["docs/page.md"]), [])

    def test_a_script_that_is_gone_fails(self):
        failures = self.run_page("<!-- example: build -->\n\n    scripts/no-such-script.sh\n")
        self.assertIn("scripts/no-such-script.sh does not exist", failures[0])


if __name__ == "__main__":
    unittest.main()
