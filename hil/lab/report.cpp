#include "report.h"

#include <algorithm>

#include "histogram_svg.h"
#include "plot_axis.h"
#include "sim/event_log.h"

namespace mb2co {
namespace lab {

using sim::strf;

namespace {

std::string ms(uint64_t ns) {
  return strf("%.2f", static_cast<double>(ns) / 1e6);
}
const char* yes(bool b) {
  return b ? "yes" : "NO";
}
const char* path_name(bool remote) {
  return remote ? "modbus+canopen" : "modbus";
}

std::string leds_text(uint8_t l) {
  return strf("%c%c%c%c", (l & 2) ? 'P' : '-', (l & 1) ? 'S' : '-', (l & 4) ? 'N' : '-', (l & 8) ? 'L' : '-');
}

}  // namespace

std::string error_frames_text(const sim::LineSummary& s) {
  std::string t = strf("%llu error frames", static_cast<unsigned long long>(s.error_frames));
  // A station powered before its neighbours sends alone: nobody acknowledges
  // its boot-up and heartbeats, and it retries as error-passive until the
  // next one is up (docs/lab.md). Said, so a PASS with hundreds of error
  // frames does not read as a faulty bus.
  if (s.ack_error_frames == s.error_frames && s.error_frames != 0) {
    t += " (all ACK errors: no other station powered yet to acknowledge)";
  } else if (s.ack_error_frames != 0) {
    t += strf(" (%llu of them ACK errors: no other station powered yet to acknowledge)",
              static_cast<unsigned long long>(s.ack_error_frames));
  }
  return t;
}

namespace {

std::string summary_lines(const sim::LineSummary& s) {
  return strf(
      "  CAN: %llu frames, %s, bus load %.1f %%, %llu receive overflows; "
      "%.0f s simulated, %llu events\n",
      static_cast<unsigned long long>(s.can_frames), error_frames_text(s).c_str(), s.bus_load * 100.0,
      static_cast<unsigned long long>(s.rx_overflows), static_cast<double>(s.duration_ns) / 1e9,
      static_cast<unsigned long long>(s.events));
}

std::string stations_table(const sim::LineSummary& s) {
  std::string out =
      "  station  RUN  LEDs  bottles filled  handed on  overfilled  spilled_ml  PC cycles  overruns  "
      "failures\n";
  for (size_t i = 0; i < s.stations.size(); ++i) {
    const sim::StationSummary& st = s.stations[i];
    out += strf(
        "  %7zu  %3s  %4s  %14u  %9u  %10u  %10.1f  %9llu  %8llu  %8llu\n", i + 1, st.running ? "on" : "off",
        leds_text(st.leds).c_str(), st.bottles_filled, st.handed_off, st.overfilled,
        static_cast<double>(st.spilled_ul) / 1000.0, static_cast<unsigned long long>(st.pc_cycles),
        static_cast<unsigned long long>(st.pc_overruns), static_cast<unsigned long long>(st.pc_failures));
  }
  return out + "  (LEDs: P RUN-prev, S RUN-self, N RUN-next, L lab)\n";
}

std::string xml_escape(const std::string& s) {
  std::string o;
  for (char c : s) {
    if (c == '<')
      o += "&lt;";
    else if (c == '>')
      o += "&gt;";
    else if (c == '&')
      o += "&amp;";
    else
      o += c;
  }
  return o;
}

}  // namespace

std::string report_header(const Options& o) {
  const sim::LineConfig& c = o.line;
  std::string h = "mb2co-lab: virtual-time simulation of the production line\n";
  h += strf("seed %llu, %d stations (%s), Modbus/RTU %u baud 8E1, PC cycle %llu ms (+0..%llu us jitter)\n",
            static_cast<unsigned long long>(c.seed), c.stations, c.ring ? "ring" : "chain", c.baud,
            static_cast<unsigned long long>(c.pc.cycle_ns / sim::kNsPerMs),
            static_cast<unsigned long long>(c.pc.jitter_ns / sim::kNsPerUs));
  if (o.firmware == "fast") {
    h += strf("firmware: a pass every %llu us taking %llu..%llu us\n",
              static_cast<unsigned long long>(c.node.loop_ns / sim::kNsPerUs),
              static_cast<unsigned long long>(c.node.pass_ns / sim::kNsPerUs),
              static_cast<unsigned long long>((c.node.pass_ns + c.node.jitter_ns) / sim::kNsPerUs));
  } else {
    h += strf(
        "firmware: ATmega328P pass times (back-to-back loop, %llu us per pass + %llu us per CAN frame "
        "+ Modbus request costs)\n",
        static_cast<unsigned long long>(c.node.pass_ns / sim::kNsPerUs),
        static_cast<unsigned long long>(c.node.frame_ns / sim::kNsPerUs));
  }
  h += strf("line: heartbeat %u ms (consumers 3x), TPDO1 inhibit %u.%u ms, debounce %u ms\n", c.heartbeat_ms,
            c.tpdo1_inhibit_100us / 10, c.tpdo1_inhibit_100us % 10, c.debounce_ms);
  return h;
}

std::string run_section(const sim::RunResult& r) {
  std::string s = "\n== run: bottles flow, RUN LEDs\n";
  s += stations_table(r.line);
  s += summary_lines(r.line);
  // Each criterion with what was measured, so a FAIL says which one and why.
  unsigned fewest = UINT32_MAX, fewest_station = 0, overfilled = 0;
  double spilled_ml = 0;
  for (size_t i = 0; i < r.line.stations.size(); ++i) {
    const sim::StationSummary& st = r.line.stations[i];
    if (st.bottles_filled < fewest) {
      fewest = st.bottles_filled;
      fewest_station = static_cast<unsigned>(i + 1);
    }
    overfilled += st.overfilled;
    spilled_ml += static_cast<double>(st.spilled_ul) / 1000.0;
  }
  const bool filled = fewest > 0 && fewest != UINT32_MAX;
  const bool clean = overfilled == 0 && spilled_ml == 0;
  struct Criterion {
    const char* what;
    bool ok;
    std::string measured;
  };
  const Criterion criteria[] = {
      {"every station running at the end", r.all_running, ""},
      {"LEDs show own and neighbour RUN", r.leds_ok, ""},
      {"every station filled a bottle", filled,
       strf("fewest %u, station %u", fewest == UINT32_MAX ? 0 : fewest, fewest_station)},
      {"no bottle overfilled or spilled", clean,
       strf("%u overfilled, %.1f ml spilled", overfilled, spilled_ml)},
  };
  std::string failed;
  for (const Criterion& c : criteria) {
    s += strf("  %s: %s%s\n", c.what, yes(c.ok), c.measured.empty() ? "" : (" (" + c.measured + ")").c_str());
    if (!c.ok) failed += std::string(failed.empty() ? "" : "; ") + c.what;
  }
  s += r.ok ? strf("verdict run: PASS (all %zu criteria met)\n", sizeof criteria / sizeof criteria[0])
            : "verdict run: FAIL (not met: " + failed + ")\n";
  return s;
}

std::string stop2_section(const sim::Stop2Result& r) {
  std::string s = "\n== stop2: STOP2 at station k stops k and k+1; LEDs of k-1..k+2 show it\n";
  s += "  k  stopped    expected   LEDs k-1..k+2  press->own LED ms  press->next LED ms  restarted\n";
  for (const sim::Stop2Case& c : r.cases) {
    auto list = [](const std::vector<int>& v) {
      std::string t;
      for (int i : v) t += (t.empty() ? "" : ",") + std::to_string(i + 1);
      return t.empty() ? std::string("-") : t;
    };
    s += strf("  %d  %-9s  %-9s  %-13s  %17s  %18s  %s\n", c.k + 1, list(c.stopped).c_str(),
              list(c.expected).c_str(), c.leds_ok ? "ok" : "WRONG", ms(c.own_led_ns).c_str(),
              c.next_led_ns ? ms(c.next_led_ns).c_str() : "-", yes(c.restarted));
    for (const std::string& e : c.led_errors) s += "     " + e + "\n";
  }
  s += summary_lines(r.line);
  // A case passes when the stations expected (k and k+1) and only they
  // stopped, the LEDs of k-1..k+2 showed it, the own LED came and START
  // restarted the line.
  std::string failed;
  for (const sim::Stop2Case& c : r.cases) {
    if (!c.ok) failed += strf("%s%d", failed.empty() ? "" : ", ", c.k + 1);
  }
  if (r.ok) {
    s += strf("verdict stop2: PASS (%zu of %zu cases: expected stations stopped, LEDs right, restarted)\n",
              r.cases.size(), r.cases.size());
  } else if (failed.empty()) {
    s += "verdict stop2: FAIL (the line did not come up running before the first press)\n";
  } else {
    s += "verdict stop2: FAIL (cases k = " + failed + ": see their rows)\n";
  }
  return s;
}

std::string latency_section(const std::vector<sim::LatencyResult>& results) {
  const bool worst = !results.empty() && results.front().c.worst;
  std::string s = strf("\n== latency: button -> LED (seed 000 §11), %s, ms\n",
                       worst ? "presses at the phasings of a deterministic worst-case search (--worst)"
                             : "presses at random phases");
  s += "  bitrate  path             n     min    mean     p99     max  | bound best   worst | inside  "
       "max/worst\n";
  bool all = true;
  size_t total = 0;
  uint32_t lost = 0;
  uint64_t lab_frames = 0;
  for (const sim::LatencyResult& r : results) {
    total += r.samples_ns.size();
    lost += r.lost;
    lab_frames += r.lab_frames_lost;
    all = all && r.ok;
    if (!r.bound.ok) {
      s += strf("  %4uk    %-14s  no bound: %s\n", r.c.bitrate_kbit, path_name(r.c.remote),
                r.bound.error.c_str());
      continue;
    }
    const double ratio = static_cast<double>(r.max_ns) / static_cast<double>(r.bound.bound.worst_ns);
    s += strf("  %4uk    %-14s %5zu %7s %7s %7s %7s  | %10s %7s | %6s  %8.1f%%\n", r.c.bitrate_kbit,
              path_name(r.c.remote), r.samples_ns.size(), ms(r.min_ns).c_str(),
              strf("%.2f", r.mean_ns / 1e6).c_str(), ms(r.p99_ns).c_str(), ms(r.max_ns).c_str(),
              ms(r.bound.bound.best_ns).c_str(), ms(r.bound.bound.worst_ns).c_str(),
              r.outside == 0 ? "all" : strf("%u out", r.outside).c_str(), ratio * 100.0);
  }
  s += "  bound: hil/sim/lab_bound.cpp for the simulated configuration (docs/timing.md §9): every firmware\n"
       "  step the longest pass of its kind, the CAN frames counted where they reach a pass the path "
       "waits\n"
       "  for, CAN hops by the revised response-time analysis of the commissioned message set (Davis\n"
       "  stuffing), PC cycle = period + jitter.\n";
  for (const sim::LatencyResult& r : results) {
    if (!r.bound.ok) continue;
    const sim::LabBound& b = r.bound;
    s += strf("  %4uk/%s: passes %llu/%llu/%llu us (plain/read/write), frames %u + %u", r.c.bitrate_kbit,
              path_name(r.c.remote), static_cast<unsigned long long>(b.plain_pass_ns / sim::kNsPerUs),
              static_cast<unsigned long long>(b.read_pass_ns / sim::kNsPerUs),
              static_cast<unsigned long long>(b.write_pass_ns / sim::kNsPerUs), b.frames_pc, b.frames_led);
    if (r.c.remote) {
      const timing::LatencyParams& p = b.params;
      s += strf(", CAN up %s..%s ms, down %s..%s ms", ms(p.can_up_best_ns).c_str(),
                ms(p.can_up_worst_ns).c_str(), ms(p.can_down_best_ns).c_str(),
                ms(p.can_down_worst_ns).c_str());
    }
    s += strf("; %llu overflows, %llu t1.5 discards\n", static_cast<unsigned long long>(r.rx_overflows),
              static_cast<unsigned long long>(r.t15_discards));
  }
  s += strf("verdict latency: every one of %zu measurements inside its analytical bounds: %s\n", total,
            yes(all));
  s += strf(
      "presses lost: %u (their button or LED PDO was dropped in an MCP2515 receive overflow %llu time(s);\n"
      "  the bound assumes no frame is lost; see docs/lab.md, --can-rx-buffers)\n",
      lost, static_cast<unsigned long long>(lab_frames));
  return s;
}

std::string faults_section(const sim::FaultsResult& r) {
  std::string s = "\n== faults: frame loss, bus-off, neighbour reboot, serial unplug\n";
  for (const sim::FaultCheck& c : r.checks) {
    s += strf("  [%s] %s\n        %s\n", c.ok ? "ok" : "FAIL", c.what.c_str(), c.detail.c_str());
  }
  for (const std::string& n : r.notes) s += "  [note] " + n + "\n";
  s += stations_table(r.line);
  s += summary_lines(r.line);
  size_t failed = 0;
  std::string first;
  for (const sim::FaultCheck& c : r.checks) {
    if (c.ok) continue;
    if (failed++ == 0) first = c.what;
  }
  if (r.ok) {
    s += strf("verdict faults: PASS (all %zu checks)\n", r.checks.size());
  } else {
    s += strf("verdict faults: FAIL (%zu of %zu checks failed, first: %s)\n", failed, r.checks.size(),
              first.c_str());
  }
  return s;
}

std::string latency_csv(const std::vector<sim::LatencyResult>& results) {
  std::string s = "bitrate_kbit,path,press,latency_ns,best_ns,worst_ns,inside\n";
  for (const sim::LatencyResult& r : results) {
    for (size_t i = 0; i < r.samples_ns.size(); ++i) {
      const uint64_t v = r.samples_ns[i];
      const bool in = r.bound.ok && v >= r.bound.bound.best_ns && v <= r.bound.bound.worst_ns;
      s += strf("%u,%s,%zu,%llu,%llu,%llu,%d\n", r.c.bitrate_kbit, path_name(r.c.remote), i + 1,
                static_cast<unsigned long long>(v), static_cast<unsigned long long>(r.bound.bound.best_ns),
                static_cast<unsigned long long>(r.bound.bound.worst_ns), in ? 1 : 0);
    }
  }
  return s;
}

std::string bound_terms_csv(const std::vector<sim::LatencyResult>& results) {
  std::string s = "bitrate_kbit,path,term,best_ns,worst_ns\n";
  for (const sim::LatencyResult& r : results) {
    if (!r.bound.ok) continue;
    const timing::LatencyBound& b = r.bound.bound;
    for (size_t i = 0; i < b.count; ++i) {
      s += strf("%u,%s,%s,%llu,%llu\n", r.c.bitrate_kbit, path_name(r.c.remote), b.terms[i].name,
                static_cast<unsigned long long>(b.terms[i].best_ns),
                static_cast<unsigned long long>(b.terms[i].worst_ns));
    }
    s += strf("%u,%s,total,%llu,%llu\n", r.c.bitrate_kbit, path_name(r.c.remote),
              static_cast<unsigned long long>(b.best_ns), static_cast<unsigned long long>(b.worst_ns));
  }
  return s;
}

HistogramPanel latency_panel(const sim::LatencyResult& r, const char* name) {
  HistogramPanel p;
  p.name = name;
  p.samples = &r.samples_ns;
  p.min = r.min_ns;
  p.max = r.max_ns;
  p.bounded = r.bound.ok;
  p.best = r.bound.bound.best_ns;
  p.worst = r.bound.bound.worst_ns;
  p.fill = r.c.remote ? "#e08020" : "#3070c0";
  return p;
}

std::string latency_svg(const std::vector<sim::LatencyResult>& results, uint32_t bitrate_kbit) {
  std::vector<HistogramPanel> panels;
  for (const sim::LatencyResult& r : results) {
    if (r.c.bitrate_kbit == bitrate_kbit) panels.push_back(latency_panel(r, path_name(r.c.remote)));
  }
  return histogram_svg(strf("Button to LED latency at %u kbit/s:", bitrate_kbit), "presses", kMs, panels);
}

std::string timeline_svg(const sim::LineSummary& line, int stations, const std::string& title) {
  const int W = 900, lane = 40, left = 80, right = 20, top = 40;
  const int H = top + stations * lane + 40;
  const PlotAxis t_axis = round_axis(static_cast<double>(line.duration_ns) / 1e9, 10);
  const double t_max = t_axis.max();
  const double pw = W - left - right;
  auto X = [&](uint64_t t) { return left + pw * (static_cast<double>(t) / 1e9) / t_max; };
  std::string s = strf(
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%d\" height=\"%d\" font-family=\"sans-serif\" "
      "font-size=\"12\">\n<rect width=\"100%%\" height=\"100%%\" fill=\"white\"/>\n",
      W, H);
  s += strf(
      "<text x=\"%d\" y=\"22\" font-size=\"15\">%s: RUN (green) per station, STOP2 presses (red), START "
      "presses (blue)</text>\n",
      left, xml_escape(title).c_str());
  for (int st = 0; st < stations; ++st) {
    const int y = top + st * lane;
    s += strf("<text x=\"10\" y=\"%d\">station %d</text>\n", y + 22, st + 1);
    s += strf("<rect x=\"%d\" y=\"%d\" width=\"%.1f\" height=\"20\" fill=\"#dddddd\"/>\n", left, y + 8, pw);
    bool running = false;
    uint64_t since = 0;
    for (const sim::TimelineEvent& e : line.timeline) {
      if (e.station != st) continue;
      if (e.kind == sim::TimelineEvent::kRun && !running) {
        running = true;
        since = e.t_ns;
      } else if (e.kind == sim::TimelineEvent::kStop && running) {
        running = false;
        s += strf("<rect x=\"%.1f\" y=\"%d\" width=\"%.1f\" height=\"20\" fill=\"#40a040\"/>\n", X(since),
                  y + 8, std::max(0.5, X(e.t_ns) - X(since)));
      }
    }
    if (running) {
      s += strf("<rect x=\"%.1f\" y=\"%d\" width=\"%.1f\" height=\"20\" fill=\"#40a040\"/>\n", X(since),
                y + 8, std::max(0.5, X(line.duration_ns) - X(since)));
    }
    for (const sim::TimelineEvent& e : line.timeline) {
      if (e.station != st) continue;
      if (e.kind == sim::TimelineEvent::kStop2Press || e.kind == sim::TimelineEvent::kStartPress) {
        const double x = X(e.t_ns);
        s += strf("<path d=\"M%.1f %d l-5 -8 h10 z\" fill=\"%s\"/>\n", x, y + 8,
                  e.kind == sim::TimelineEvent::kStop2Press ? "red" : "#3070c0");
      }
    }
  }
  const int base = top + stations * lane + 5;
  for (int t = 0; t <= t_axis.ticks; ++t) {
    const double x = left + pw * t / t_axis.ticks;
    s += strf("<text x=\"%.1f\" y=\"%d\" text-anchor=\"middle\">%s</text>\n", x, base + 12,
              t_axis.label(t).c_str());
  }
  s += strf("<text x=\"%d\" y=\"%d\" text-anchor=\"end\">s</text>\n", W - right, base + 26);
  return s + "</svg>\n";
}

}  // namespace lab
}  // namespace mb2co
