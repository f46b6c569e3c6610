// Serial ports as QSerialPortInfo sees them, and the Arduino among them.
// QSerialPortInfo never lists pseudo-terminals: a pty is given by --port.
#pragma once
#include <stdint.h>

#include <QString>
#include <vector>

#include "host/status.h"

namespace mb2co {
namespace pcapp {

/// Arduino (2341h), Arduino.org (2A03h), and the CH340 USB-serial chip of
/// the Uno clones (1A86h:7523h).
bool is_arduino_usb(uint16_t vendor_id, uint16_t product_id);

struct PortInfo {
  QString path;         ///< /dev/ttyACM0
  QString description;  ///< manufacturer / description as the system reports them
  bool has_ids = false;
  uint16_t vendor_id = 0;
  uint16_t product_id = 0;
  bool arduino = false;
};

std::vector<PortInfo> list_ports();
/// The lines --list-ports prints (one per port, Arduinos marked).
QString format_ports(const std::vector<PortInfo>& ports);
/// The one Arduino among `ports` in `*path`; fails (and `*path` is empty)
/// when there is none or more than one.
Status pick_arduino(const std::vector<PortInfo>& ports, QString* path);
/// True when `path` (after resolving symlinks) is a listed Arduino port: it
/// resets when opened, so the boot loader must be waited for.
bool is_arduino_port(const std::vector<PortInfo>& ports, const QString& path);

}  // namespace pcapp
}  // namespace mb2co
