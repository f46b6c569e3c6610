#include "port_finder.h"

#include <QFileInfo>
#include <QSerialPortInfo>

namespace mb2co {
namespace pcapp {

bool is_arduino_usb(uint16_t vendor_id, uint16_t product_id) {
  return vendor_id == 0x2341 || vendor_id == 0x2A03 || (vendor_id == 0x1A86 && product_id == 0x7523);
}

std::vector<PortInfo> list_ports() {
  std::vector<PortInfo> out;
  for (const QSerialPortInfo& p : QSerialPortInfo::availablePorts()) {
    PortInfo i;
    i.path = p.systemLocation();
    i.description = (p.manufacturer() + " " + p.description()).trimmed();
    i.has_ids = p.hasVendorIdentifier() && p.hasProductIdentifier();
    i.vendor_id = p.vendorIdentifier();
    i.product_id = p.productIdentifier();
    i.arduino = i.has_ids && is_arduino_usb(i.vendor_id, i.product_id);
    out.push_back(i);
  }
  return out;
}

QString format_ports(const std::vector<PortInfo>& ports) {
  if (ports.empty())
    return QStringLiteral("no serial ports found (a pty is not listed: give it with --port)\n");
  QString s;
  for (const PortInfo& p : ports) {
    s += p.path;
    if (p.has_ids) {
      s += QStringLiteral("  %1:%2")
               .arg(p.vendor_id, 4, 16, QLatin1Char('0'))
               .arg(p.product_id, 4, 16, QLatin1Char('0'));
    }
    if (!p.description.isEmpty()) s += QStringLiteral("  ") + p.description;
    if (p.arduino) s += QStringLiteral("  [Arduino]");
    s += QLatin1Char('\n');
  }
  return s;
}

Status pick_arduino(const std::vector<PortInfo>& ports, QString* path) {
  QStringList found;
  for (const PortInfo& p : ports) {
    if (p.arduino) found << p.path;
  }
  path->clear();
  if (found.size() == 1) {
    *path = found.front();
    return Status::ok();
  }
  if (found.isEmpty())
    return Status::failure("no Arduino found on USB (see --list-ports; give the port with --port)");
  return Status::failure(QStringLiteral("several Arduinos found (%1): choose one with --port")
                             .arg(found.join(", "))
                             .toStdString());
}

bool is_arduino_port(const std::vector<PortInfo>& ports, const QString& path) {
  const QString real = QFileInfo(path).canonicalFilePath();  // empty when it does not exist
  for (const PortInfo& p : ports) {
    if (p.arduino && (p.path == path || (!real.isEmpty() && QFileInfo(p.path).canonicalFilePath() == real))) {
      return true;
    }
  }
  return false;
}

}  // namespace pcapp
}  // namespace mb2co
