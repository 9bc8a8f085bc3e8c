// The node side of the lock-step protocol, in one process (InprocBus) with a toy source and a
// toy sink: a resend is ignored, a different second copy is an error, a lost START is replaced
// by the RESEND, a consumer's WAITING makes the publisher send its batch again, and a silent
// clock stops a node.
#include "common/node/bus.hpp"
#include "common/node/channels.hpp"
#include "common/node/lockstep_node.hpp"

#include <rnav/bearing_batch_t.hpp>
#include <rnav/node_ack_t.hpp>
#include <rnav/sim_window_t.hpp>

#include <catch2/catch.hpp>

#include <string>
#include <vector>

namespace {

using rnav::bearing_batch_t;
using rnav::node_ack_t;
using rnav::sim_window_t;

const std::string kCh = "TOY_BEARING";
constexpr std::int8_t kStart = sim_window_t::START, kResend = sim_window_t::RESEND, kOk = node_ack_t::OK,
                      kWaiting = node_ack_t::WAITING;

// Publishes one bearing per window whose value is the window index (deterministic).
class Source : public rnav::LockstepNode {
 public:
  explicit Source(rnav::Bus& bus) : LockstepNode(bus, "source", 10) {}
  int processed = 0;

 protected:
  void reset(const sim_window_t&) override {}
  int process(const sim_window_t& w) override {
    bearing_batch_t b{};
    b.n = 1;
    b.bearings.resize(1);
    b.bearings[0].utime = w.utime_begin;
    b.bearings[0].bearing_rad = w.window;
    publish_batch(kCh, b);
    ++processed;
    return 1;
  }
};

// Consumes TOY_BEARING; records what it got.
class Sink : public rnav::LockstepNode {
 public:
  explicit Sink(rnav::Bus& bus) : LockstepNode(bus, "sink", 10) { add_input<bearing_batch_t>(kCh); }
  std::vector<double> got;

 protected:
  void reset(const sim_window_t&) override { got.clear(); }
  int process(const sim_window_t&) override {
    got.push_back(input<bearing_batch_t>(kCh).bearings.at(0).bearing_rad);
    return 0;
  }
};

sim_window_t window(std::int8_t command, int w) {
  sim_window_t s{};
  s.command = command;
  s.seed = 1;
  s.n_realizations = 1;
  s.window = w;
  s.utime_begin = 1000000LL * w;
  s.utime_end = 1000000LL * (w + 1);
  return s;
}

struct Acks {
  std::vector<node_ack_t> all;
  explicit Acks(rnav::InprocBus& bus) {
    bus.subscribe<node_ack_t>(rnav::ch::kAck, [this](const node_ack_t& a) { all.push_back(a); });
  }
  int count(const std::string& node, std::int8_t status, int w) const {
    int n = 0;
    for (const auto& a : all) n += a.node == node && a.status == status && a.window == w;
    return n;
  }
};

void send(rnav::InprocBus& bus, const sim_window_t& w) {
  bus.publish(rnav::ch::kWindow, w);
  bus.run_until_idle();
}

}  // namespace

TEST_CASE("lock-step node: a batch lost once is sent again on the consumer's WAITING", "[lockstep][loss]") {
  rnav::InprocBus bus;
  Acks acks(bus);
  Source src(bus);
  Sink sink(bus);
  src.add_drop(rnav::DropSpec::parse(kCh + ":0:1:0:1"));  // window 1: its first transmission lost
  send(bus, window(kStart, 0));
  CHECK(acks.count("sink", kOk, 0) == 1);
  send(bus, window(kStart, 1));
  // The source acked window 1 listing TOY_BEARING, which the sink lacks: it answers WAITING at
  // once, the source publishes the kept batch again, the sink processes it.
  CHECK(acks.count("source", kOk, 1) == 1);
  CHECK(acks.count("sink", kWaiting, 1) == 1);
  CHECK(src.republished() == 1);
  CHECK(acks.count("sink", kOk, 1) == 1);
  CHECK(sink.got == std::vector<double>{0, 1});
  // A RESEND of window 1 (e.g. an ack lost): both ack again; no new batch is processed.
  send(bus, window(kResend, 1));
  CHECK(acks.count("sink", kOk, 1) == 2);
  CHECK(acks.count("source", kOk, 1) == 2);
  CHECK(src.processed == 2);
  CHECK(sink.got.size() == 2);
}

TEST_CASE("lock-step node: a RESEND stands for a lost START, an identical copy is ignored", "[lockstep][loss]") {
  rnav::InprocBus bus;
  Acks acks(bus);
  Source src(bus);
  Sink sink(bus);
  send(bus, window(kStart, 0));
  // Window 1's START lost at both nodes: the clock's RESEND grants it.
  send(bus, window(kResend, 1));
  CHECK(acks.count("source", kOk, 1) == 1);
  CHECK(acks.count("sink", kOk, 1) == 1);
  CHECK(sink.got == std::vector<double>{0, 1});
  // A byte-identical copy of the source's window-1 batch, published again by hand (seq 1): ignored.
  bearing_batch_t dup{};
  dup.header.seq = 1;
  dup.header.window = 1;
  dup.header.utime_begin = 1000000;
  dup.header.utime_end = 2000000;
  dup.n = 1;
  dup.bearings.resize(1);
  dup.bearings[0].utime = 1000000;
  dup.bearings[0].bearing_rad = 1;
  bus.publish(kCh, dup);
  bus.run_until_idle();
  CHECK(sink.duplicates_ignored() == 1);
  CHECK(sink.got.size() == 2);
  // A copy that differs (another value for the same window) stops the sink with an error.
  dup.bearings[0].bearing_rad = 1.5;
  bus.publish(kCh, dup);
  CHECK_THROWS_WITH(bus.run_until_idle(), Catch::Contains("two different batches for one window on TOY_BEARING") &&
                                              Catch::Contains("window 1"));
}

TEST_CASE("lock-step node: a clock silent for the peer timeout stops the node, naming it", "[lockstep][watchdog]") {
  rnav::InprocBus bus;
  Source src(bus);  // peer timeout 10 s
  src.poll(100.0);
  send(bus, window(kStart, 0));
  src.poll(100.1);  // heard at 100.1
  src.poll(110.0);
  CHECK_FALSE(src.done());
  src.poll(110.2);
  REQUIRE(src.done());
  CHECK(src.exit_code() == rnav::kClockSilentExit);
  CHECK_THAT(src.failure(), Catch::Contains("the clock fell silent") && Catch::Contains("runner.peer_timeout_s"));
}

// ---- runner.wire = sample: one message per sample ----
namespace {

// Publishes w % 3 bearings in window w (window 0: none), valued 10 w + 9 - i: decreasing within
// a window, so that an assembly that sorted them would show.
class MultiSource : public rnav::LockstepNode {
 public:
  explicit MultiSource(rnav::Bus& bus) : LockstepNode(bus, "source", 10) {}

 protected:
  void reset(const sim_window_t&) override {}
  int process(const sim_window_t& w) override {
    bearing_batch_t b{};
    b.n = w.window % 3;
    for (int i = 0; i < b.n; ++i) {
      rnav::bearing_t s{};
      s.utime = w.utime_begin + i;
      s.bearing_rad = 10.0 * w.window + 9 - i;
      b.bearings.push_back(s);
    }
    publish_batch(kCh, b);
    return b.n;
  }
};

// Consumes TOY_BEARING; records every window's values.
class AllSink : public rnav::LockstepNode {
 public:
  explicit AllSink(rnav::Bus& bus) : LockstepNode(bus, "sink", 10) { add_input<bearing_batch_t>(kCh); }
  std::vector<std::vector<double>> got;

 protected:
  void reset(const sim_window_t&) override { got.clear(); }
  int process(const sim_window_t&) override {
    got.emplace_back();
    for (const auto& b : input<bearing_batch_t>(kCh).bearings) got.back().push_back(b.bearing_rad);
    return 0;
  }
};

// Windows 0 .. n-1 granted in turn; what the sink got.
std::vector<std::vector<double>> run_windows(rnav::InprocBus& bus, AllSink& sink, int n) {
  for (int w = 0; w < n; ++w) send(bus, window(kStart, w));
  return sink.got;
}

}  // namespace

TEST_CASE("lock-step node: HELLO answers the clock's first heartbeat at once and CLOSE ends the linger after FINISH",
          "[lockstep][finish]") {
  rnav::InprocBus bus;
  Acks acks(bus);
  Source src(bus);
  src.poll(100.0);
  bus.run_until_idle();  // first poll: a HELLO, the next one due 0.2 s later
  REQUIRE(acks.count("source", node_ack_t::HELLO, -1) == 1);
  src.poll(100.001);
  bus.run_until_idle();
  CHECK(acks.count("source", node_ack_t::HELLO, -1) == 1);
  // The clock has started: its heartbeat is answered at once, even 1 ms after the last HELLO
  // (which the clock may have missed).
  send(bus, window(sim_window_t::HEARTBEAT, 0));
  CHECK(acks.count("source", node_ack_t::HELLO, -1) == 2);
  send(bus, window(kStart, 0));
  send(bus, window(sim_window_t::HEARTBEAT, 0));  // after the first grant: no more HELLOs
  CHECK(acks.count("source", node_ack_t::HELLO, -1) == 2);
  // FINISH: the node reports FINISHED and lingers to answer a repeated FINISH ...
  send(bus, window(sim_window_t::FINISH, 0));
  src.poll(100.1);
  bus.run_until_idle();
  CHECK(acks.count("source", node_ack_t::FINISHED, 0) == 1);
  send(bus, window(sim_window_t::FINISH, 0));
  CHECK(acks.count("source", node_ack_t::FINISHED, 0) == 2);
  src.poll(100.2);
  bus.run_until_idle();
  CHECK_FALSE(src.done());  // 0.1 s of the 0.5 s linger
  // ... until CLOSE (every node has finished): it stops at once, status 0.
  send(bus, window(sim_window_t::CLOSE, 0));
  CHECK(src.done());
  CHECK(src.exit_code() == 0);
  CHECK(src.failure().empty());
}

TEST_CASE("lock-step node, wire sample: one message per sample, none in an empty window, batches as in batch form",
          "[lockstep][wire]") {
  constexpr int kWindows = 6;  // sample counts 0 1 2 0 1 2
  std::vector<std::vector<double>> batch_got;
  {
    rnav::InprocBus bus;
    MultiSource src(bus);
    AllSink sink(bus);
    batch_got = run_windows(bus, sink, kWindows);
  }
  rnav::InprocBus bus;
  Acks acks(bus);
  MultiSource src(bus);
  AllSink sink(bus);
  src.set_wire(rnav::Wire::kSample);
  sink.set_wire(rnav::Wire::kSample);
  int messages = 0, not_a_sample = 0;
  bus.subscribe_raw(kCh, [&](const std::string&, const void* data, int size) {
    ++messages;
    rnav::bearing_t s;
    not_a_sample += s.decode(data, 0, size) != size;
  });
  const auto got = run_windows(bus, sink, kWindows);
  CHECK(messages == 0 + 1 + 2 + 0 + 1 + 2);
  CHECK(not_a_sample == 0);
  CHECK(got == batch_got);
  REQUIRE(got.size() == kWindows);
  CHECK(got[2] == std::vector<double>{29, 28});  // publish order kept
  CHECK(acks.count("sink", kOk, kWindows - 1) == 1);
}

TEST_CASE("lock-step node, wire sample: samples lost once are sent again on WAITING, copies ignored",
          "[lockstep][wire][loss]") {
  rnav::InprocBus bus;
  Acks acks(bus);
  MultiSource src(bus);
  AllSink sink(bus);
  src.set_wire(rnav::Wire::kSample);
  sink.set_wire(rnav::Wire::kSample);
  src.add_drop(rnav::DropSpec::parse(kCh + ":0:2:0:1"));  // window 2: both samples lost once
  for (int w = 0; w < 2; ++w) send(bus, window(kStart, w));
  send(bus, window(kStart, 2));
  CHECK(acks.count("sink", kWaiting, 2) == 1);
  CHECK(src.republished() == 1);
  CHECK(acks.count("sink", kOk, 2) == 1);
  // A copy of a sample of window 4, sent by hand before the source's own: ignored once the
  // source publishes the same bytes.
  send(bus, window(kStart, 3));
  rnav::bearing_t copy{};
  copy.utime = 4000000;
  copy.bearing_rad = 49;
  bus.publish(kCh, copy);
  bus.run_until_idle();
  send(bus, window(kStart, 4));
  CHECK(sink.duplicates_ignored() == 1);
  CHECK(sink.got == std::vector<std::vector<double>>{{}, {19}, {29, 28}, {}, {49}});
}

TEST_CASE("lock-step node, a sample where a batch is expected is an error naming runner.wire", "[lockstep][wire]") {
  rnav::InprocBus bus;
  MultiSource src(bus);
  AllSink sink(bus);
  src.set_wire(rnav::Wire::kSample);  // the sink stays on batch
  send(bus, window(kStart, 0));       // no samples in window 0: nothing to misread yet
  try {
    send(bus, window(kStart, 1));
    FAIL("a bearing_t on a batch channel was accepted");
  } catch (const std::exception& e) {
    CHECK_THAT(e.what(), Catch::Matchers::Contains("runner.wire"));
    CHECK_THAT(e.what(), Catch::Matchers::Contains(kCh));
  }
}

namespace {

const std::string kCmd = "TOY_CMD", kFb = "TOY_FB";

// The upstream end of a loop: publishes per window one bearing on TOY_CMD whose value is
// 100 w + the value fed back (-1 when none), and takes TOY_FB as a feedback input.
class Controller : public rnav::LockstepNode {
 public:
  explicit Controller(rnav::Bus& bus) : LockstepNode(bus, "controller", 10) { add_feedback_input<bearing_batch_t>(kFb); }
  std::vector<std::vector<double>> fed;  // per window, the feedback values it got

 protected:
  void reset(const sim_window_t&) override { fed.clear(); }
  int process(const sim_window_t& w) override {
    const auto& fb = input<bearing_batch_t>(kFb);
    std::vector<double> v;
    for (const auto& b : fb.bearings) v.push_back(b.bearing_rad);
    fed.push_back(v);
    bearing_batch_t out{};
    out.n = 1;
    out.bearings.resize(1);
    out.bearings[0].utime = w.utime_begin;
    out.bearings[0].bearing_rad = 100.0 * w.window + (v.empty() ? -1.0 : v.back());
    publish_batch(kCmd, out);
    return 1;
  }
};

// The downstream end: feeds back each command + 1 on TOY_FB.
class Echo : public rnav::LockstepNode {
 public:
  explicit Echo(rnav::Bus& bus) : LockstepNode(bus, "echo", 10) { add_input<bearing_batch_t>(kCmd); }

 protected:
  void reset(const sim_window_t&) override {}
  int process(const sim_window_t&) override {
    bearing_batch_t out = input<bearing_batch_t>(kCmd);
    for (auto& b : out.bearings) b.bearing_rad += 1;
    publish_batch(kFb, out);
    return out.n;
  }
};

}  // namespace

TEST_CASE("lock-step node, feedback input: window w gets the batch of window w-1, a lost one is sent again",
          "[lockstep][feedback][loss]") {
  for (const auto wire : {rnav::Wire::kBatch, rnav::Wire::kSample}) {
    INFO((wire == rnav::Wire::kBatch ? "wire batch" : "wire sample"));
    rnav::InprocBus bus;
    Acks acks(bus);
    Controller ctl(bus);
    Echo echo(bus);
    ctl.set_wire(wire);
    echo.set_wire(wire);
    echo.add_drop(rnav::DropSpec::parse(kFb + ":0:1:0:1"));  // the feedback of window 1: first transmission lost
    send(bus, window(kStart, 0));
    send(bus, window(kStart, 1));
    CHECK(acks.count("controller", kOk, 1) == 1);  // window 1 took window 0's feedback, which arrived
    send(bus, window(kStart, 2));
    // Window 2 needs window 1's feedback, which was lost: no OK; the clock's RESEND makes the
    // controller name it (WAITING for window 1), the echo publishes it again, the controller goes on.
    CHECK(acks.count("controller", kOk, 2) == 0);
    send(bus, window(kResend, 2));
    CHECK(acks.count("controller", kWaiting, 1) == 1);  // names the window it needs: 1
    CHECK(acks.count("controller", kWaiting, 2) == 0);
    CHECK(echo.republished() == 1);
    CHECK(acks.count("controller", kOk, 2) == 1);
    send(bus, window(kStart, 3));
    // fed: nothing before window 0, then 0 + (-1) + 1 = 0, then 100 + 0 + 1 = 101, then 200 + 101 + 1 = 302.
    CHECK(ctl.fed == std::vector<std::vector<double>>{{}, {0}, {101}, {302}});
  }
}

TEST_CASE("lock-step node: another run's grants, batches and acks are ignored and counted, and FINISHED reports them",
          "[lockstep][foreign]") {
  // Two runs on one network (--net host, or a replayed log): this run's id is 3, the other's 4.
  // The other run's START, its source's batch for the same window (another value) and its
  // sink's ack change nothing here; the sink's FINISHED report carries the count.
  rnav::InprocBus bus;
  bus.set_run_id(3);
  Acks acks(bus);
  Source src(bus);
  Sink sink(bus);
  sim_window_t w0 = window(kStart, 0);
  w0.run_id = 3;
  send(bus, w0);
  REQUIRE(sink.got == std::vector<double>{0});
  CHECK(acks.all.back().run_id == 3);
  sim_window_t other = window(kStart, 1);
  other.run_id = 4;
  send(bus, other);  // not ours: nothing processed
  CHECK(src.processed == 1);
  bearing_batch_t b{};
  b.header.seq = 1;
  b.header.window = 1;
  b.header.run_id = 4;
  b.n = 1;
  b.bearings.resize(1);
  b.bearings[0].bearing_rad = 42;
  bus.publish(kCh, b);
  node_ack_t a{};
  a.node = "sink_of_run_4";
  a.status = kWaiting;
  a.window = 0;
  a.run_id = 4;
  a.n_missing = 1;
  a.missing = {kCh};
  bus.publish(rnav::ch::kAck, a);  // the other run's WAITING: no batch published again here
  bus.run_until_idle();
  CHECK(src.republished() == 0);
  sim_window_t w1 = window(kStart, 1);
  w1.run_id = 3;
  send(bus, w1);
  CHECK(sink.got == std::vector<double>{0, 1});  // this run's batch, not the other's 42
  CHECK(sink.foreign_ignored() == 3);             // grant, batch, ack
  CHECK(src.foreign_ignored() == 2);              // grant, ack (the source takes no input)
  sim_window_t fin = window(sim_window_t::FINISH, 1);
  fin.run_id = 3;
  send(bus, fin);
  int reported = -1;
  for (const auto& x : acks.all)
    if (x.node == "sink" && x.status == node_ack_t::FINISHED) reported = x.n_foreign;
  CHECK(reported == 3);
}
