// The master's SDO side: one SdoClient per node (1..127), each working
// through its own queue of transfers, all nodes at once (seed 002: "all the
// types of data transfers, which can run simultaneously with several
// nodes"), and the watchdog: with a heartbeat consumer time set, a node whose
// heartbeats stop has its running transfer aborted (05040000h sent) and its
// queue failed, instead of waiting for the SDO timeout (seed 002's watchdog).
// A request that times out while the node's heartbeat says it serves SDO
// (operational or pre-operational) is taken for lost and the transfer is
// started over once (the timeout's abort sent first): a station Uno loses
// a request now and then when a neighbour's frames fill its two receive
// buffers (firmware/avr/README.md). A node heard from in no such state in
// that time (silent, stopped, without heartbeat) times out as before.
#pragma once
#include <stdint.h>

#include <deque>
#include <vector>

#include "bus_loop.h"
#include "canopen/master/node_monitor.h"
#include "canopen/sdo_client.h"
#include "transfer_network.h"

namespace mb2co {
namespace master {

class SdoNetwork : public BusService {
 public:
  /// `timeout_us`: SDO client timeout; `heartbeat_ms`: consumer time of the
  /// watchdog (0: none). Nodes are watched from their first transfer on.
  SdoNetwork(uint32_t timeout_us, uint16_t heartbeat_ms);

  /// Queues `t` behind the node's other transfers; it starts at once when
  /// the node's client is free.
  void queue(Transfer* t);
  /// Transfers not finished yet.
  size_t pending() const { return pending_; }
  /// Progress of the node's running transfer (bytes moved, size; size 0
  /// when unknown or idle).
  void progress(uint8_t node, uint32_t* moved, uint32_t* size) const;
  /// Ends the node's queued transfers that have not started with `code`,
  /// without calling their on_done (a running one runs on): for a caller
  /// that gave up on the node and would otherwise wait out their timeouts.
  void drop_queued(uint8_t node, canopen::SdoAbort code);
  /// Aborts every running transfer with `code` (SIGINT) and fails the queues.
  void abort_all(canopen::SdoAbort code, const CanSink& sink);
  /// Ends `t` alone (TransferNetwork::cancel): its on_done is not called.
  bool cancel(Transfer* t, canopen::SdoAbort code, const CanSink& sink);

  void on_frame(const CanFrame& f, uint32_t now_us, const CanSink& sink) override;
  void process(uint32_t now_us, const CanSink& sink) override;
  void next_deadline(NextDeadline& d) const override;

 private:
  struct Node {
    canopen::SdoClient client;
    std::deque<Transfer*> queue;  ///< front(): running
    bool used = false;
    /// A heartbeat saying operational or pre-operational came since the
    /// running transfer (re)started: the node is there to serve SDO.
    bool heard_serving = false;
  };
  /// The front transfer timed out (ours or the server's 05040000h) while
  /// the node was heard serving, for the first time and with nothing of it
  /// handed on yet (a streamed upload's bytes): started over
  /// kAskAgainPauseUs later, true. Else false (it ends).
  bool ask_again(uint8_t id, uint32_t now_us, const CanSink& sink);
  /// Out of step with periods of whole 10 ms (heartbeats, event timers).
  static const uint32_t kAskAgainPauseUs = 7000;
  /// Ends the node's transfers from position `from` of its queue on with
  /// `code` (nothing is sent: the caller aborts a running one);
  /// `notify`: their on_done is called.
  void end_queue(uint8_t id, size_t from, canopen::SdoAbort code, bool node_lost, bool notify);
  static void on_monitor(void* ctx, uint8_t node, canopen::MonitorEvent e, uint8_t, uint8_t);
  /// Starts the node's front transfer if its client is idle.
  void start_next(uint8_t id, uint32_t now_us, const CanSink& sink);
  /// The running transfer ended (client no longer busy).
  void finish_front(uint8_t id, uint32_t now_us, const CanSink& sink);

  static canopen::SdoAbort collect(void* ctx, uint32_t offset, const uint8_t* data, uint16_t n);
  static canopen::SdoAbort supply(void* ctx, uint32_t offset, uint8_t* buf, uint16_t n);

  Node nodes_[128];
  /// Ids of the nodes with `used` set, ascending: each pass visits these,
  /// not all 127 (a one-node transfer's pass was mostly that loop).
  std::vector<uint8_t> used_;
  /// Configured only with a watchdog (heartbeat_ms_): untouched otherwise.
  canopen::NodeMonitorTable<127> monitors_;
  uint32_t timeout_us_;
  uint16_t heartbeat_ms_;
  size_t pending_ = 0;
  uint32_t now_us_ = 0;
  CanSink sink_ = {nullptr, nullptr};
  std::vector<uint8_t> lost_;  ///< node ids the watchdog reported since the last process()
};

}  // namespace master
}  // namespace mb2co
