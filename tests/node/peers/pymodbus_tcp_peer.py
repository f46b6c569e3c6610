"""Independent peer: python3-pymodbus 3.0 (Debian) as Modbus/TCP client of
mb2co-node --can none --serial none --tcp 127.0.0.1:0 (docs/mb2co-node.md,
"Modbus/TCP"): every function code of the gateway's map (docs/register-map.md),
FC 17 and 2B/0E, the exceptions, FC 08 refused (serial line only), any unit id.

Usage: pymodbus_tcp_peer.py MB2CO_NODE
pymodbus 3.0 truncates timeouts to whole seconds (DESIGN §10): timeout=3 (a loaded 2-core host once took over 1 s).
Requests built as objects take the unit id as `unit` in this version.
"""
import selectors
import subprocess
import sys
import unittest

from pymodbus.client import ModbusTcpClient
from pymodbus import diag_message as diag
from pymodbus.mei_message import ReadDeviceInformationRequest
from pymodbus.register_read_message import ReadWriteMultipleRegistersRequest

NODE = sys.argv[1]
READY_TIMEOUT_S = 10


class Node:
    """mb2co-node until its ready line, which names the TCP port it took."""

    def __init__(self):
        self.proc = subprocess.Popen([NODE, "--can", "none", "--serial", "none", "--tcp", "127.0.0.1:0"],
                                     stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True)
        sel = selectors.DefaultSelector()
        sel.register(self.proc.stdout, selectors.EVENT_READ)
        while True:
            if not sel.select(READY_TIMEOUT_S):
                self.proc.kill()
                sys.exit("mb2co-node printed no ready line")
            line = self.proc.stdout.readline()
            if line.startswith("ready "):
                break
        fields = dict(w.split("=", 1) for w in line.split()[1:])
        host, port = fields["tcp"].rsplit(":", 1)
        self.host, self.port = host, int(port)

    def stop(self):
        self.proc.stdin.write("quit\n")
        self.proc.stdin.flush()
        rc = self.proc.wait(timeout=10)
        self.proc.stdout.close()
        self.proc.stdin.close()
        return rc


class PymodbusTcpPeer(unittest.TestCase):
    def setUp(self):
        self.node = Node()
        self.client = ModbusTcpClient(self.node.host, port=self.node.port, timeout=3, retries=0)
        self.assertTrue(self.client.connect())

    def tearDown(self):
        self.client.close()
        self.assertEqual(self.node.stop(), 0)

    def ok(self, response):
        self.assertFalse(response.isError(), str(response))
        return response

    def test_every_data_function(self):
        c = self.client
        self.ok(c.write_register(7, 35, slave=1))                                  # 06 debounce
        # The Modbus watchdog (2000h/09, 2 s) runs from power-on: a loaded host
        # that starts this client late has rightly latched a stop (cause 4),
        # which holds until RUN 0 (docs/register-map.md). Clear it as a PC would.
        self.ok(c.write_register(0, 0, slave=1))
        self.ok(c.write_registers(0, [1, 1], slave=1))                             # 10 RUN, lab LED
        self.assertEqual(self.ok(c.read_holding_registers(0, 2, slave=1)).registers, [1, 1])  # 03
        self.assertEqual(self.ok(c.read_holding_registers(7, 1, slave=1)).registers, [35])
        self.assertEqual(self.ok(c.read_coils(0, 2, slave=1)).bits[:2], [True, True])         # 01
        self.ok(c.write_coil(1, False, slave=1))                                   # 05 lab LED off
        self.ok(c.write_coils(0, [True, True], slave=1))                           # 0F
        self.assertEqual(self.ok(c.read_holding_registers(1, 1, slave=1)).registers, [1])
        run_and_cause = self.ok(c.read_input_registers(1, 3, slave=1)).registers              # 04 RUN state
        self.assertEqual(run_and_cause[0], 1, f"RUN state 0, stop cause {run_and_cause[2]}")
        self.assertEqual(self.ok(c.read_discrete_inputs(0, 4, slave=1)).bits[:4],              # 02
                         [False, False, False, True])
        # readwrite_registers(slave=...) of pymodbus 3.0.0rc1 loses the unit:
        # the request object instead.
        rw = c.execute(ReadWriteMultipleRegistersRequest(                          # 17
            read_address=7, read_count=1, write_address=7, write_registers=[40], unit=1))
        self.assertEqual(self.ok(rw).registers, [40])

    def test_device_identification(self):
        r = self.ok(self.client.execute(ReadDeviceInformationRequest(read_code=1, object_id=0, unit=1)))
        self.assertEqual(r.conformity, 0x81)
        self.assertEqual(r.information[0], b"mb2co")

    def test_exceptions(self):
        c = self.client
        self.assertEqual(c.read_holding_registers(20, 1, slave=1).exception_code, 2)  # past the map
        self.assertEqual(c.write_register(0, 2, slave=1).exception_code, 4)           # RUN command 2
        self.assertEqual(c.read_input_registers(0, 126, slave=1).exception_code, 3)
        echo = c.execute(diag.ReturnQueryDataRequest(0x1234, unit=1))
        self.assertEqual(echo.exception_code, 1, "FC 08 is the serial line's")

    def test_any_unit_id_is_served(self):
        for unit in (0, 1, 17, 247, 255):
            r = self.ok(self.client.read_holding_registers(7, 1, slave=unit))
            self.assertEqual(r.unit_id, unit)


if __name__ == "__main__":
    unittest.main(argv=[sys.argv[0]], verbosity=2)
