"""Independent peer: python3-pymodbus 3.0 (Debian) as master of our slave.

Usage: pymodbus_peer_test.py PTY_SLAVE
pymodbus 3.0 truncates timeouts to whole seconds (DESIGN §10): timeout=1.
Requests built as objects take the slave address as `unit` in this version.
"""
import sys
import unittest

from pymodbus.client import ModbusSerialClient
from pymodbus import diag_message as diag
from pymodbus.mei_message import ReadDeviceInformationRequest
from pymodbus.register_read_message import ReadWriteMultipleRegistersRequest

from slave_runner import SlaveRunner

PTY_SLAVE = sys.argv[1]


class PymodbusPeer(unittest.TestCase):
    def setUp(self):
        self.slave = SlaveRunner(PTY_SLAVE)
        self.client = ModbusSerialClient(port=self.slave.device, baudrate=115200, parity="N",
                                         stopbits=1, bytesize=8, timeout=1, retries=0)
        self.assertTrue(self.client.connect())

    def tearDown(self):
        self.client.close()
        self.slave.__exit__(None, None, None)

    def ok(self, response):
        self.assertFalse(response.isError(), str(response))
        return response

    def test_every_data_function(self):
        c = self.client
        self.ok(c.write_coil(3, True, slave=1))                             # 05
        self.ok(c.write_coils(8, [True, False, True], slave=1))             # 0F
        self.assertEqual(self.ok(c.read_coils(3, 8, slave=1)).bits[:8],     # 01
                         [True, False, False, False, False, True, False, True])
        self.assertEqual(self.ok(c.read_discrete_inputs(0, 4, slave=1)).bits[:4],  # 02
                         [True, False, False, True])
        self.ok(c.write_register(20, 0xBEEF, slave=1))                      # 06
        self.ok(c.write_registers(21, [1, 2], slave=1))                     # 10
        self.assertEqual(self.ok(c.read_holding_registers(20, 3, slave=1)).registers,  # 03
                         [0xBEEF, 1, 2])
        self.assertEqual(self.ok(c.read_input_registers(7, 2, slave=1)).registers,     # 04
                         [0x1007, 0x1008])
        # readwrite_registers(slave=1) of pymodbus 3.0.0rc1 loses the address
        # (it goes out as a broadcast): build the request object instead.
        rw = c.execute(ReadWriteMultipleRegistersRequest(                            # 17
            read_address=20, read_count=2, write_address=21, write_registers=[9], unit=1))
        self.assertEqual(self.ok(rw).registers, [0xBEEF, 9])

    def test_exceptions(self):
        c = self.client
        self.assertEqual(c.read_holding_registers(256, 1, slave=1).exception_code, 2)
        self.assertEqual(c.write_register(105, 1, slave=1).exception_code, 2)
        self.assertEqual(c.read_input_registers(0, 126, slave=1).exception_code, 3)
        self.assertEqual(c.read_input_registers(200, 1, slave=1).exception_code, 4)
        self.assertEqual(c.write_registers(110, [1, 1001], slave=1).exception_code, 4)
        self.assertEqual(self.ok(c.read_holding_registers(110, 1, slave=1)).registers, [0])
        r = c.execute(diag.ReturnDiagnosticRegisterRequest(unit=1))
        self.assertFalse(r.isError())
        self.assertEqual(c.execute(diag.ChangeAsciiInputDelimiterRequest(unit=1)).exception_code, 1)

    def counter(self, request_class):
        return self.ok(self.client.execute(request_class(unit=1))).message[0]

    def test_diagnostics(self):
        c = self.client
        echo = self.ok(c.execute(diag.ReturnQueryDataRequest(0x1234, unit=1)))
        self.assertEqual(list(echo.message), [0x1234])
        self.assertEqual(c.read_input_registers(0, 126, slave=1).exception_code, 3)
        self.assertEqual(self.counter(diag.ReturnBusMessageCountRequest), 3)
        self.assertEqual(self.counter(diag.ReturnBusExceptionErrorCountRequest), 1)
        self.assertEqual(self.counter(diag.ReturnBusCommunicationErrorCountRequest), 0)
        self.assertEqual(self.counter(diag.ReturnSlaveNoResponseCountRequest), 0)
        self.assertEqual(self.counter(diag.ReturnSlaveBusCharacterOverrunCountRequest), 0)
        self.assertEqual(self.counter(diag.ReturnSlaveMessageCountRequest), 8)  # all so far
        self.ok(c.execute(diag.ClearCountersRequest(unit=1)))
        self.assertEqual(self.counter(diag.ReturnSlaveMessageCountRequest), 1)

    def test_device_identification(self):
        r = self.ok(self.client.execute(ReadDeviceInformationRequest(read_code=1, object_id=0, unit=1)))
        self.assertEqual(r.conformity, 0x81)
        self.assertEqual(r.information, {0: b"mb2co", 1: b"MB2CO-GW", 2: b"0.1.0"})

    def test_broadcast_silent_but_executed(self):
        r = self.client.write_register(30, 77, slave=0)
        self.assertTrue(r.isError(), "a broadcast was answered: %s" % r)
        self.assertEqual(self.ok(self.client.read_holding_registers(30, 1, slave=1)).registers, [77])


if __name__ == "__main__":
    unittest.main(argv=[sys.argv[0]], verbosity=2)
