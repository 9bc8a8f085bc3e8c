// The lock-step clock's loss handling, driven in one process (InprocBus) with a scripted wall
// clock: which reports a retry names, and when it acts.
#include "bus.hpp"
#include "channels.hpp"
#include "conductor.hpp"

#include <catch2/catch.hpp>

namespace {

using rnav::Conductor;
using rnav::node_ack_t;

void ack(rnav::InprocBus& bus, const std::string& node, std::int8_t status, int window, const std::string& detail = "") {
  node_ack_t a;
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

}  // namespace

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
