"""Independent peer: the FC 2Bh/0Dh client of docs/gateway-network.md ("A
client of your own: Python with pymodbus"), run as the page shows it, with
python3-pymodbus 3.0 (Debian 12), through the gateway on PORT to node 2 (an
mb2co-node) and node 32 (a fresh I/O node); node 9 is nobody.

Usage: pymodbus_network_peer.py DOC PORT
The client's code is taken from DOC as written (its ```python block that
starts with "# fc2b_pymodbus.py"), and so is the example's output (the
```console block after it): what the page shows is what runs. Only this
file's assertions are the test's own.
"""
import importlib.util
import os
import re
import struct
import subprocess
import sys
import tempfile
import time
import unittest

DOC, PORT = sys.argv[1], sys.argv[2]
REMOTE, IONODE, MISSING = 2, 32, 9
# docs/gateway-network.md "How long a master waits": a missing node is
# answered 500 ms after the request plus the frame times. A simulated Uno in
# user-mode Linux on a shared host may wait ~100 ms for the CPU: the upper
# bound has that slack (as uno.network's), the lower none.
SDO_TIMEOUT_S, SLACK_S = 0.5, 0.25
# A deadline that bounds a failure only: user-mode Linux is slow.
ANSWER_DEADLINE_S = 5.0


def page_parts(doc):
    """The client's source and the example (command, expected output) as the page shows them."""
    with open(doc, encoding="utf-8") as f:
        text = f.read()
    code = re.search(r"```python\n(# fc2b_pymodbus\.py.*?)```", text, re.S)
    example = re.search(r"```console\n\$ (python3 fc2b_pymodbus\.py .*?)\n(.*?)```", text[code.end():], re.S)
    return code.group(1), example.group(1), example.group(2)


SOURCE, EXAMPLE_COMMAND, EXAMPLE_OUTPUT = page_parts(DOC)
WORKDIR = tempfile.mkdtemp(prefix="fc2b_pymodbus.")
CLIENT_PATH = os.path.join(WORKDIR, "fc2b_pymodbus.py")
with open(CLIENT_PATH, "w", encoding="utf-8") as out:
    out.write(SOURCE)
_spec = importlib.util.spec_from_file_location("fc2b_pymodbus", CLIENT_PATH)
fc2b = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(fc2b)


class GatewayNetworkWithPymodbus(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.client = fc2b.connect(PORT)
        assert cls.client is not None, "pymodbus cannot open " + PORT

    @classmethod
    def tearDownClass(cls):
        cls.client.close()

    def transact(self, request):
        return fc2b.transact(self.client, request, ANSWER_DEADLINE_S)

    def upload(self, node, index, sub, start=0, count=0):
        return self.transact(fc2b.NetworkRequest(fc2b.SDO, node, index, sub, start, count))

    def refused(self, request):
        """The NetworkError a request gets (fails when it is answered)."""
        with self.assertRaises(fc2b.NetworkError) as refusal:
            self.transact(request)
        return refusal.exception

    def test_the_pages_example_prints_what_the_page_shows(self):
        # The page's command with this gateway's port for /dev/ttyACM0, the
        # client's own process on the port: this test's client lets go of it.
        self.client.close()
        try:
            command = EXAMPLE_COMMAND.replace("/dev/ttyACM0", PORT).split()
            command[0] = sys.executable
            run = subprocess.run(command, cwd=WORKDIR, capture_output=True, text=True, timeout=60)
        finally:
            self.assertTrue(self.client.connect())
        self.assertEqual(run.returncode, 0, run.stderr)
        self.assertEqual(run.stdout, EXAMPLE_OUTPUT)

    def test_expedited_upload_of_1018_2_from_both_nodes(self):
        # docs/mb2co-gateway.eds and docs/mb2co-ionode.eds: 1018h/2 product code.
        for node, product in ((REMOTE, 0xB2C), (IONODE, 0x401)):
            answer = self.upload(node, 0x1018, 2)
            self.assertEqual((answer.node, answer.index, answer.sub, answer.start), (node, 0x1018, 2, 0))
            self.assertEqual((answer.size, answer.count, answer.more), (4, 4, False))
            self.assertEqual(answer.data, struct.pack("<I", product), "node %d" % node)

    def test_segmented_upload_of_1008_whole_and_in_windows(self):
        name = b"mb2co gateway"  # 13 bytes: a segmented SDO upload
        whole = self.upload(REMOTE, 0x1008, 0)
        self.assertEqual((whole.size, whole.count, whole.more, whole.data), (len(name), len(name), False, name))
        # Windows of 4 bytes: `more follows` until the last one, which is short.
        first = self.upload(REMOTE, 0x1008, 0, 0, 4)
        self.assertEqual((first.size, first.data, first.more), (len(name), name[:4], True))
        last = self.upload(REMOTE, 0x1008, 0, 12, 4)
        self.assertEqual((last.start, last.data, last.more), (12, name[12:], False))
        self.assertEqual(fc2b.read_object(self.client, REMOTE, 0x1008, 0, 4), name)
        self.assertEqual(fc2b.read_object(self.client, IONODE, 0x1008, 0), b"mb2co I/O node")

    def test_download_to_a_remote_node_and_read_back(self):
        for node in (REMOTE, IONODE):
            before = self.upload(node, 0x1017, 0).data  # producer heartbeat time, ms
            self.assertEqual(len(before), 2, "1017h is 16 bits")
            written = fc2b.download(self.client, node, 0x1017, 0, struct.pack("<H", 300))
            self.assertEqual((written.node, written.index, written.size, written.data), (node, 0x1017, 2, b""))
            self.assertEqual(self.upload(node, 0x1017, 0).data, struct.pack("<H", 300), "node %d" % node)
            fc2b.download(self.client, node, 0x1017, 0, before)
            self.assertEqual(self.upload(node, 0x1017, 0).data, before)
        # More than 4 bytes in one part: a segmented SDO download (1F50h/1 of
        # mb2co-node is a DOMAIN), read back whole.
        blob = bytes((i * 13 + 5) & 0xFF for i in range(40))
        self.assertEqual(fc2b.download(self.client, REMOTE, 0x1F50, 1, blob).size, len(blob))
        self.assertEqual(fc2b.read_object(self.client, REMOTE, 0x1F50, 1), blob)
        # A refusal carries the node's own abort code: 1000h is read-only.
        refusal = self.refused(fc2b.NetworkRequest(fc2b.SDO | fc2b.WRITE, REMOTE, 0x1000, 0, size=4, data=bytes(4)))
        self.assertEqual((refusal.code, refusal.abort), (4, 0x06010002))

    def view_states(self):
        """Node id -> NMT state of every node the gateway's network view lists."""
        states, first = {}, 1
        while True:
            view = self.transact(fc2b.NetworkRequest(fc2b.VIEW, first))
            entries = [view.data[i:i + 4] for i in range(0, len(view.data), 4)]
            states.update((entry[0], entry[1]) for entry in entries)
            if not view.more:
                return states
            first = entries[-1][0] + 1

    def wait_view_state(self, node, state):
        """Polls the view until `node` shows `state` (its next heartbeat); the last states seen."""
        deadline = time.monotonic() + ANSWER_DEADLINE_S
        while True:
            states = self.view_states()
            if states.get(node) == state or time.monotonic() > deadline:
                return states
            time.sleep(0.05)

    def test_nmt_commands_seen_in_the_network_view(self):
        # The view lists a node by its heartbeat: 04h stopped, 05h operational.
        self.addCleanup(fc2b.nmt, self.client, REMOTE, 0x01)  # SDO needs node 2 out of stopped
        stop = fc2b.nmt(self.client, REMOTE, 0x02)
        self.assertEqual((stop.control, stop.node, stop.data), (fc2b.NMT | fc2b.WRITE, REMOTE, b"\x02"), "the echo")
        self.assertEqual(self.wait_view_state(REMOTE, 0x04).get(REMOTE), 0x04, "node 2 stopped")
        fc2b.nmt(self.client, REMOTE, 0x01)
        self.assertEqual(self.wait_view_state(REMOTE, 0x05).get(REMOTE), 0x05, "node 2 operational again")
        self.assertEqual(self.view_states().get(1), 0x05, "the gateway itself, operational")

    def test_missing_node_answers_05040000_after_the_sdo_timeout(self):
        start = time.monotonic()
        refusal = self.refused(fc2b.NetworkRequest(fc2b.SDO, MISSING, 0x1000, 0))
        elapsed = time.monotonic() - start
        self.assertEqual((refusal.code, refusal.abort), (4, 0x05040000))
        self.assertGreaterEqual(elapsed, SDO_TIMEOUT_S)
        self.assertLessEqual(elapsed, SDO_TIMEOUT_S + SLACK_S)
        print("missing node 9: exception 04 abort 05040000h after %.0f ms" % (elapsed * 1000), file=sys.stderr)

    def test_malformed_requests_get_exception_03(self):
        # docs/gateway-network.md, "Exceptions": malformed is 03 (3 bytes, no abort).
        bad = {
            "SDO to node 0": fc2b.NetworkRequest(fc2b.SDO, 0, 0x1018, 1),
            "node id 128": fc2b.NetworkRequest(fc2b.SDO, 128, 0x1018, 1),
            "more follows on an upload": fc2b.NetworkRequest(fc2b.SDO | fc2b.MORE, REMOTE, 0x1018, 2),
            "NMT command 03": fc2b.NetworkRequest(fc2b.NMT | fc2b.WRITE, REMOTE, data=b"\x03"),
            "NMT with an index": fc2b.NetworkRequest(fc2b.NMT | fc2b.WRITE, REMOTE, 0x1000, data=b"\x01"),
            "service 3": fc2b.NetworkRequest(0xC0, REMOTE, 0x1018, 2),
            "view with a subindex": fc2b.NetworkRequest(fc2b.VIEW, 0, 0, 1),
            "count 2, one byte follows": fc2b.NetworkRequest(fc2b.NMT | fc2b.WRITE, REMOTE, count=2, data=b"\x01"),
            "a part continuing nothing": fc2b.NetworkRequest(fc2b.SDO | fc2b.WRITE, REMOTE, 0x1017, 0, 7, size=9,
                                                             data=b"\xaa\x00"),
        }
        for what, request in bad.items():
            refusal = self.refused(request)
            self.assertEqual((refusal.code, refusal.abort), (3, None), what)
        self.assertEqual(self.upload(REMOTE, 0x1018, 2).size, 4, "and the gateway serves again")

    def test_own_registers_answered_with_fc_03_and_04(self):
        c = self.client
        # docs/register-map.md: HR 2 the node id (2000h/01; a fresh board: 1),
        # HR 8 1017h, IR 22 the NMT state; FC 2Bh to the gateway's own node id
        # reads the same OD, and the network view lists its state.
        node_id = c.read_holding_registers(2, 1, slave=1)
        self.assertFalse(node_id.isError(), str(node_id))
        self.assertEqual(node_id.registers, [1])
        heartbeat = c.read_holding_registers(8, 1, slave=1)
        self.assertFalse(heartbeat.isError(), str(heartbeat))
        self.assertEqual(struct.pack("<H", heartbeat.registers[0]), self.upload(1, 0x1017, 0).data)
        state = c.read_input_registers(22, 1, slave=1)
        self.assertFalse(state.isError(), str(state))
        view = self.transact(fc2b.NetworkRequest(fc2b.VIEW, 1))
        self.assertEqual(view.data[:4], bytes([1, state.registers[0], 0, 0]), "own entry first, age 0")


if __name__ == "__main__":
    unittest.main(argv=[sys.argv[0]], verbosity=2)
