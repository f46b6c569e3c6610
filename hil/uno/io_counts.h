// The system calls mb2co-uno's loop makes, by kind (--stats). Under
// user-mode Linux every one of them is trapped (~15 us of the VM's one CPU,
// a wake-up ~80 us), so the loop batches. Per pass of Pacer::kLeadUs of
// simulated time at most: one clock reading; one sleep; two polls over all
// inputs (the second only after a wake-up by input); at each poll one read
// per input that has something (CAN: again while a batch came back full;
// each CAN read that returned frames also reads two clocks, with which
// host/platform/socketcan_port.cpp dates them); one serial write and one
// CAN send (sendmmsg, 32 frames each) for all that the pass produced.
// Quiet and paced: a poll that sleeps and a clock reading, two per pass;
// unpaced: one poll per pass.
#pragma once
#include <stdint.h>

#include <string>

namespace mb2co {
namespace uno {

struct IoCounts {
  uint64_t passes = 0;         ///< runs of the simulation (each at most Pacer::kLeadUs)
  uint64_t clock_reads = 0;    ///< clock_gettime()
  uint64_t polls = 0;          ///< ppoll() over every input, sleeping or not
  uint64_t sleeps = 0;         ///< clock_nanosleep() to the end of a pass woken early
  uint64_t reads = 0;          ///< read()/recvmmsg() of the pty, the CAN socket, stdin
  uint64_t writes = 0;         ///< write() to the pty, sendmmsg() to the CAN socket
  uint64_t can_frames_in = 0;  ///< frames those reads took from the CAN socket

  uint64_t system_calls() const { return clock_reads + polls + sleeps + reads + writes; }
  /// "stats passes=P system_calls=N per_sim_s=R clock=.. poll=.. sleep=.. read=.. write=..
  /// can_frames_in=F cpu_ms=C cpu_per_sim_s_ms=D" over `sim_us` of simulated
  /// time, in which the process used `cpu_us` of CPU (user and system).
  std::string line(uint64_t sim_us, uint64_t cpu_us) const;
};

}  // namespace uno
}  // namespace mb2co
