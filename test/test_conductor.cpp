// The lock-step clock's loss handling, driven in one process (InprocBus) with a scripted wall
// clock: when it asks for a window again (RESEND), which reports a retry names and when it acts,
// when it gives up on a silent node, and its heartbeat.
#include "common/node/bus.hpp"
#include "common/node/channels.hpp"
#include "sim/clock/conductor.hpp"
#include "common/node/lcm_bus.hpp"

#include <rnav/sim_window_t.hpp>

#include <catch2/catch.hpp>

#include <algorithm>
#include <fstream>
#include <vector>

namespace {

using rnav::Conductor;
using rnav::node_ack_t;

void ack(rnav::InprocBus& bus, const std::string& node, std::int8_t status, int window, const std::string& detail = "") {
  node_ack_t a{};
  a.node = node;
  a.status = status;
  a.realization = node_ack_t::HELLO == status ? -1 : 0;
  a.attempt = 0;
  a.window = window;
  a.n_published = 0;
  a.detail = detail;
  bus.publish(rnav::ch::kAck, a);
  bus.run_until_idle();
}

// The commands as values (LCM's constants have no out-of-class definition to bind to).
constexpr std::int8_t kStart = rnav::sim_window_t::START, kAbort = rnav::sim_window_t::ABORT,
                      kResend = rnav::sim_window_t::RESEND, kHeartbeat = rnav::sim_window_t::HEARTBEAT;

// Every SIM_WINDOW command the clock sends, in order.
struct Recorder {
  std::vector<rnav::sim_window_t> sent;
  explicit Recorder(rnav::InprocBus& bus) {
    bus.subscribe<rnav::sim_window_t>(rnav::ch::kWindow, [this](const rnav::sim_window_t& w) { sent.push_back(w); });
  }
  int count(std::int8_t command) const {
    int n = 0;
    for (const auto& w : sent) n += w.command == command;
    return n;
  }
};

}  // namespace

TEST_CASE("conductor: an overdue ack is asked for again (RESEND), and the realization is not repeated",
          "[conductor][loss]") {
  rnav::InprocBus bus;
  Recorder rec(bus);
  rnav::RunnerOptions runner;
  runner.window_s = 10;
  rnav::ConductorOptions o;
  o.nodes = {"prl_bias", "logger"};
  Conductor c(bus, runner, 0.25, o, 30.0);
  ack(bus, "prl_bias", node_ack_t::HELLO, -1);
  ack(bus, "logger", node_ack_t::HELLO, -1);
  c.poll(0.0);
  bus.run_until_idle();
  REQUIRE(rec.count(kStart) == 1);
  ack(bus, "prl_bias", node_ack_t::OK, 0);
  // Before any pace is known the clock waits 50 ms after the last progress (the ack at 0.0).
  c.poll(0.04);
  bus.run_until_idle();
  CHECK(rec.count(kResend) == 0);
  c.poll(0.06);
  bus.run_until_idle();
  REQUIRE(rec.count(kResend) == 1);
  CHECK(rec.sent.back().window == 0);
  REQUIRE(c.resends().size() == 1);
  CHECK(c.resends()[0].reason == "logger: no ack");
  // The logger answers WAITING: the next RESEND names what it misses. The answer shows the node
  // alive, so the wait stays 50 ms (from the RESEND at 0.06).
  ack(bus, "logger", node_ack_t::WAITING, 0, "logger: waiting for realization 0 attempt 0 window 0 on PRL_TOI");
  c.poll(0.06 + 0.04);
  bus.run_until_idle();
  CHECK(rec.count(kResend) == 1);
  c.poll(0.06 + 0.06);
  bus.run_until_idle();
  REQUIRE(c.resends().size() == 2);
  CHECK(c.resends()[1].reason == "logger: waiting for realization 0 attempt 0 window 0 on PRL_TOI");
  CHECK(c.resends()[1].wait_s == Approx(0.06));
  CHECK(c.resends()[1].wall_s == Approx(0.12));
  // This RESEND goes unanswered: the next waits twice as long (100 ms), the one after 200 ms.
  c.poll(0.12 + 0.09);
  bus.run_until_idle();
  CHECK(rec.count(kResend) == 2);
  c.poll(0.12 + 0.11);
  bus.run_until_idle();
  REQUIRE(rec.count(kResend) == 3);
  c.poll(0.23 + 0.19);
  bus.run_until_idle();
  CHECK(rec.count(kResend) == 3);
  c.poll(0.23 + 0.21);
  bus.run_until_idle();
  REQUIRE(rec.count(kResend) == 4);
  // An answer drops the wait back to 50 ms.
  ack(bus, "logger", node_ack_t::WAITING, 0, "logger: waiting for realization 0 attempt 0 window 0 on PRL_TOI");
  c.poll(0.44 + 0.06);
  bus.run_until_idle();
  REQUIRE(rec.count(kResend) == 5);
  ack(bus, "logger", node_ack_t::OK, 0);  // recovered: window 1 is granted
  CHECK(rec.sent.back().command == kStart);
  CHECK(rec.sent.back().window == 1);
  CHECK(c.retries().empty());
}

TEST_CASE("conductor: runner.window_s = 0 takes the whole realization as one window", "[conductor]") {
  // 30 s of trajectory + 5 s flush on a 0.25 s grid: one window [epoch, epoch + 35 s); 10 s
  // windows: four, the last one short.
  for (const double window_s : {0.0, 10.0}) {
    rnav::InprocBus bus;
    Recorder rec(bus);
    rnav::RunnerOptions runner;
    runner.window_s = window_s;
    rnav::ConductorOptions o;
    o.nodes = {"logger"};
    Conductor c(bus, runner, 0.25, o, 30.0);
    CHECK(c.windows_per_realization() == (window_s > 0 ? 4 : 1));
    ack(bus, "logger", node_ack_t::HELLO, -1);
    c.poll(0.0);
    bus.run_until_idle();
    REQUIRE(rec.count(kStart) == 1);
    const std::int64_t first_end_us = rec.sent.back().utime_end - rec.sent.back().utime_begin;
    CHECK(first_end_us == (window_s > 0 ? 10000000 : 35000000));
    CHECK(rec.sent.back().last_window == (window_s == 0));
  }
}

TEST_CASE("conductor: a node that answers no RESEND for the peer timeout fails the run, named",
          "[conductor][watchdog]") {
  rnav::InprocBus bus;
  Recorder rec(bus);
  rnav::RunnerOptions runner;
  runner.window_s = 10;
  runner.peer_timeout_s = 3;
  runner.ack_timeout_s = 100;  // the silent node, not the window's deadline, must end the run
  rnav::ConductorOptions o;
  o.nodes = {"prl_bias", "logger"};
  Conductor c(bus, runner, 0.25, o, 30.0);
  ack(bus, "prl_bias", node_ack_t::HELLO, -1);
  ack(bus, "logger", node_ack_t::HELLO, -1);
  c.poll(0.0);
  bus.run_until_idle();
  ack(bus, "logger", node_ack_t::OK, 0);
  // prl_bias is frozen: it neither acks nor answers the RESENDs. The run must fail naming it
  // after the peer timeout (3 s after the window's START, when it was last heard of), within 2 s.
  double t = 0;
  while (!c.done() && t < 10) {
    t += 0.01;
    c.poll(t);
    bus.run_until_idle();
  }
  INFO(c.failure());
  REQUIRE(c.done());
  CHECK(c.exit_code() == 4);
  CHECK(t > runner.peer_timeout_s);
  CHECK(t < runner.peer_timeout_s + 2);
  CHECK(c.failure().find("node 'prl_bias' fell silent") != std::string::npos);
  CHECK(c.failure().find("logger") == std::string::npos);
  CHECK(rec.count(kResend) >= 2);
  CHECK(rec.sent.back().command == kAbort);
}

TEST_CASE("conductor: the clock sends a heartbeat when it has nothing else to say", "[conductor][watchdog]") {
  // While it waits for HELLOs it sends nothing else; nodes must still hear it every
  // peer_timeout / 8 (here 0.5 s): over 4.9 s, 10 heartbeats (at 0, 0.5, ..., 4.5 s).
  rnav::InprocBus bus;
  Recorder rec(bus);
  rnav::RunnerOptions runner;
  runner.peer_timeout_s = 4;
  rnav::ConductorOptions o;
  o.nodes = {"prl_bias"};
  Conductor c(bus, runner, 0.25, o, 30.0);
  for (double t = 0; t < 4.9; t += 0.01) {
    c.poll(t);
    bus.run_until_idle();
  }
  CHECK(rec.count(kHeartbeat) == 10);
  CHECK(rec.count(kStart) == 0);
}

TEST_CASE("conductor: losses reported within half a stall timeout are named together in one retry",
          "[conductor][loss]") {
  rnav::InprocBus bus;
  rnav::RunnerOptions runner;
  runner.window_s = 10;
  runner.stall_timeout_s = 2;
  rnav::ConductorOptions o;
  o.nodes = {"prl_bias", "logger"};
  Conductor c(bus, runner, 0.25, o, 30.0);
  ack(bus, "prl_bias", node_ack_t::HELLO, -1);
  ack(bus, "logger", node_ack_t::HELLO, -1);
  c.poll(0.0);  // all ready: window 0 of realization 0, attempt 0 granted
  bus.run_until_idle();
  // The downstream node's report arrives first, the upstream cause 0.3 s later (< 1 s = half
  // the stall timeout): the retry waits for it and names both, in arrival order.
  c.poll(2.0);
  ack(bus, "logger", node_ack_t::LOSS, 0, "logger: no batch on PRL_TOI");
  c.poll(2.2);
  CHECK(c.retries().empty());  // still collecting
  c.poll(2.3);
  ack(bus, "prl_bias", node_ack_t::LOSS, 0, "prl_bias: no batch on NAV_SOLUTION");
  c.poll(2.9);
  CHECK(c.retries().empty());
  c.poll(3.01);  // half a stall timeout after the first report
  REQUIRE(c.retries().size() == 1);
  CHECK(c.retries()[0].reason == "logger: no batch on PRL_TOI; prl_bias: no batch on NAV_SOLUTION");
  CHECK(c.retries()[0].realization == 0);
  CHECK(c.retries()[0].attempt == 0);
  // A report of the abandoned attempt (attempt 0) is stale once attempt 1 runs: no second retry.
  ack(bus, "prl_bias", node_ack_t::LOSS, 0, "prl_bias: late");
  c.poll(5.0);  // (before attempt 1's ack timeout, 6 s after 3.01)
  CHECK(c.retries().size() == 1);
  CHECK(c.exit_code() == 0);
}

TEST_CASE("LCM bus: a receive buffer the kernel will not grant is refused, naming rmem_max", "[lcm][input]") {
  // The check runs before LCM opens anything (no traffic). The kernel caps SO_RCVBUF at
  // net.core.rmem_max; twice that can never be granted.
  std::ifstream f("/proc/sys/net/core/rmem_max");
  long rmem_max = 0;
  REQUIRE(f >> rmem_max);
  const std::string too_big = "udpm://239.255.76.67:7667?ttl=0&recv_buf_size=" + std::to_string(2 * rmem_max + 4096);
  CHECK_THROWS_WITH(rnav::LcmBus(too_big),
                    Catch::Contains("net.core.rmem_max") && Catch::Contains(std::to_string(2 * rmem_max + 4096)));
  CHECK_THROWS_WITH(rnav::LcmBus("udpm://239.255.76.67:7667?ttl=0&recv_buf_size=12x"),
                    Catch::Contains("recv_buf_size must be a positive integer") && Catch::Contains("12x"));
  CHECK(rnav::LcmBus::granted_receive_buffer(rmem_max / 2) >= rmem_max / 2);
}

TEST_CASE("conductor: in real time a RESEND waits half a window's wall time, not the batch pace",
          "[conductor][loss][realtime]") {
  rnav::InprocBus bus;
  Recorder rec(bus);
  rnav::RunnerOptions runner;
  runner.window_s = 1;  // at speed 4: a window every 0.25 s of wall time, so RESEND after 0.125 s
  rnav::ConductorOptions o;
  o.nodes = {"prl_bias", "logger"};
  o.realtime = true;
  o.speed = 4;
  Conductor c(bus, runner, 0.25, o, 30.0);
  ack(bus, "prl_bias", node_ack_t::HELLO, -1);
  ack(bus, "logger", node_ack_t::HELLO, -1);
  c.poll(0.0);  // all HELLOs: running
  c.poll(0.0);  // window 0 is due: granted
  bus.run_until_idle();
  REQUIRE(rec.count(kStart) == 1);
  ack(bus, "prl_bias", node_ack_t::OK, 0);
  c.poll(0.10);  // past the batch rule's first wait (50 ms), within half a window
  bus.run_until_idle();
  CHECK(rec.count(kResend) == 0);
  c.poll(0.13);
  bus.run_until_idle();
  CHECK(rec.count(kResend) == 1);
}

TEST_CASE("conductor: another run's SIM_WINDOW and acks are ignored and counted, a stranger of this run fails it, named",
          "[conductor][foreign]") {
  // Another run (or a replayed log) on the same LCM network carries another run id: ignored and
  // counted. Before, the run failed 18 s later with "no ack" and never said foreign traffic had
  // arrived. A message of this run's id that this clock did not send, or an ack from a node that
  // is not one of the run's, fails it at once, named.
  enum class Case { kOtherRunClock, kOtherRunAck, kSameRunClock, kStranger };
  for (const Case k : {Case::kOtherRunClock, Case::kOtherRunAck, Case::kSameRunClock, Case::kStranger}) {
    rnav::InprocBus bus;
    bus.set_run_id(5);
    Recorder rec(bus);
    rnav::RunnerOptions runner;
    runner.window_s = 10;
    rnav::ConductorOptions o;
    o.nodes = {"prl_bias", "logger"};
    o.seed = 7;
    Conductor c(bus, runner, 0.25, o, 30.0);
    auto ack_run = [&](const std::string& node, std::int8_t status, int window, std::int64_t run) {
      node_ack_t a{};
      a.node = node;
      a.status = status;
      a.realization = node_ack_t::HELLO == status ? -1 : 0;
      a.window = window;
      a.run_id = run;
      bus.publish(rnav::ch::kAck, a);
      bus.run_until_idle();
    };
    ack_run("prl_bias", node_ack_t::HELLO, -1, 5);
    ack_run("logger", node_ack_t::HELLO, -1, 5);
    c.poll(0.0);
    bus.run_until_idle();
    REQUIRE(rec.count(kStart) == 1);
    CHECK(rec.sent.back().run_id == 5);
    CHECK(!c.done());  // its own START, heard back, is not foreign
    rnav::sim_window_t w = rec.sent.back();
    w.seed = 99;
    switch (k) {
      case Case::kOtherRunClock: w.run_id = 6; bus.publish(rnav::ch::kWindow, w); break;
      case Case::kSameRunClock: bus.publish(rnav::ch::kWindow, w); break;
      case Case::kOtherRunAck: ack_run("prl_bias", node_ack_t::OK, 0, 6); ack_run("logger", node_ack_t::OK, 0, 6); break;
      case Case::kStranger: ack_run("prl", node_ack_t::OK, 0, 5); break;
    }
    bus.run_until_idle();
    c.poll(0.01);
    bus.run_until_idle();
    INFO(c.failure());
    if (k == Case::kOtherRunClock || k == Case::kOtherRunAck) {
      CHECK(!c.done());
      CHECK(c.foreign_ignored() == (k == Case::kOtherRunAck ? 2 : 1));
      auto starts = [&] {  // this run's STARTs (the recorder also hears the other run's clock)
        return std::count_if(rec.sent.begin(), rec.sent.end(), [](const auto& x) { return x.command == kStart && x.run_id == 5; });
      };
      CHECK(starts() == 1);  // the other run's acks closed no window
      ack_run("prl_bias", node_ack_t::OK, 0, 5);
      ack_run("logger", node_ack_t::OK, 0, 5);
      c.poll(0.02);
      bus.run_until_idle();
      CHECK(starts() == 2);  // this run's acks did
      continue;
    }
    REQUIRE(c.done());
    CHECK(c.exit_code() == 4);
    if (k == Case::kSameRunClock) {
      CHECK(c.failure().find("foreign traffic on SIM_WINDOW: a message this clock did not send (command 1, seed 99") !=
            std::string::npos);
      CHECK(c.failure().find("this run: seed 7") != std::string::npos);
    } else {
      CHECK(c.failure().find("foreign traffic on SIM_ACK: node 'prl' is not one of this run's nodes (prl_bias, logger)") !=
            std::string::npos);
    }
    CHECK(rec.count(kAbort) >= 1);
  }
}
