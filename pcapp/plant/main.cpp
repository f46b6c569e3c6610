// mb2co-plant: the PC side of one bottling station (plant simulator and
// controller over Modbus/RTU) and the latency lab. docs/mb2co-plant.md.
#include <signal.h>

#include <QCoreApplication>
#include <QTimer>
#include <cstdio>

#include "options.h"
#include "plant_app.h"
#include "port_finder.h"
#include "signal_pipe.h"

int main(int argc, char** argv) {
  using namespace mb2co::pcapp;
  QCoreApplication app(argc, argv);
  QCoreApplication::setApplicationName("mb2co-plant");
  QCoreApplication::setApplicationVersion(MB2CO_VERSION);

  AppOptions options;
  const mb2co::Status parsed = parse_options(QCoreApplication::arguments(), options);
  if (!parsed) {
    std::fprintf(stderr, "mb2co-plant: %s\n", parsed.message().c_str());
    return 2;
  }
  if (!options.exit_text.isEmpty()) {
    std::fputs(options.exit_text.toLocal8Bit().constData(), stdout);
    return 0;
  }
  if (options.list_ports) {
    std::fputs(format_ports(list_ports()).toLocal8Bit().constData(), stdout);
    return 0;
  }

  SignalPipe signals_in({SIGINT, SIGTERM});
  if (!signals_in.ok()) {
    std::fprintf(stderr, "mb2co-plant: cannot install the signal handlers\n");
    return 1;
  }
  PlantApp plant(options);
  if (const int rc = plant.prepare()) return rc;
  QObject::connect(&signals_in, &SignalPipe::received, &plant,
                   [&plant](int signo) { plant.shutdown(0, signo == SIGINT ? "SIGINT" : "SIGTERM"); });
  QObject::connect(&plant, &PlantApp::finished, &app, &QCoreApplication::exit, Qt::QueuedConnection);
  QTimer::singleShot(0, &plant, &PlantApp::start);
  return app.exec();
}
