// The lock-step protocol's options, shared by the clock and every node of either scenario.
#pragma once

#include "common/io/options_io.hpp"

#include <cstdint>
#include <string>

namespace rnav {

/// Lock-step protocol.
struct RunnerOptions {
  /// [s] sim time per lock-step window (batch size): 0 takes each realization as one window (the
  /// landing scenario's default: its nodes feed nothing back, so no result depends on the window,
  /// and one round trip per realization is fastest); else a multiple of the truth step (the
  /// landing scenario) or of sensor.period_s (the UAV scenario, whose default is 20 s and which
  /// needs windows > 0), [0, 1e5]
  double window_s = 0;
  double flush_s = 5;           ///< [s] sim time after the aircraft's last state, > prl_bias.nav_wait_s
  /// [s wall] the longest the clock waits for a window's next ack before it sends RESEND; the
  /// wait adapts to the run's own pace (twice the median over the last 32 windows of each
  /// window's slowest ack gap that no resend interrupted, at least 1 ms) and doubles with each resend
  /// in a row that no overdue node answered, up to this.
  /// [0.05, 600]
  double stall_timeout_s = 1;
  /// [s wall] a window not complete this long after its START, despite resends, repeats the
  /// realization. [0.1, 600]
  double ack_timeout_s = 6;
  long max_attempts = 3;        ///< attempts per realization before the run fails, [1, 100]
  /// [s wall] a node or the clock silent this long fails the run naming it: the clock names a
  /// node that neither acks nor answers RESEND; a node that hears nothing from the clock (it
  /// sends a heartbeat every peer_timeout_s / 8) stops. Must exceed the longest time a node
  /// takes to process one window. [0.5, 3600]
  double peer_timeout_s = 10;
  std::int64_t epoch_utime = 1767225600000000LL;  ///< [us since Unix epoch] sim time 0 (2026-01-01T00:00Z)
  /// How the data channels travel: "batch" (one message per channel and window, the fast
  /// ensemble's form) or "sample" (one message per sample, of the sample type: a prl_plot_t per
  /// radar plot, a nav_solution_t per solution; nothing in a window without samples; what
  /// lcm-spy and outside consumers expect; scripts/run --realtime chooses it). Every process
  /// of a run must use the same; the statistics are byte-identical either way.
  std::string wire = "batch";
};

namespace options_io {

template <class V> void visit(RunnerOptions& o, V& v) {
  v.num("window_s", o.window_s, 0, 1e5);
  v.num("flush_s", o.flush_s, 0, 1e4);
  v.num("stall_timeout_s", o.stall_timeout_s, 0.05, 600);
  v.num("ack_timeout_s", o.ack_timeout_s, 0.1, 600);
  v.integer("max_attempts", o.max_attempts, 1, 100);
  v.choice("wire", o.wire, {"batch", "sample"});
  v.num("peer_timeout_s", o.peer_timeout_s, 0.5, 3600);
  v.i64("epoch_utime", o.epoch_utime, 0, 4e15);
}

}  // namespace options_io
}  // namespace rnav
