// The node "datalink" in the lock-step chain, in one process: what it passes
// on is what snsins sent minus the lost messages, the number lost matches the configured
// p_loss of each message's range, the same seed drops the same messages whatever the windowing,
// and a link that loses nothing leaves the paper run's results byte-identical.
#include "test/csv_units.hpp"
#include "sim/datalink/datalink_node.hpp"
#include "scripts/compose/ensemble/inproc_ensemble.hpp"
#include "scripts/compose/scenario/scenario.hpp"
#include "sim/trajectory/trajectory.hpp"
#include "sim/trajectory/trajectory_node.hpp"

#include <rnav/nav_batch_t.hpp>

#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <vector>

namespace fs = std::filesystem;
using namespace rnav;

namespace {

const std::string kPaper = std::string(RNAV_SOURCE_DIR) + "/sim/scenarios/paper.json";

struct Sent {
  std::int64_t utime;
  double range_m;  // slant range to the radar antenna, computed in the landing frame
};

// Consumes NAV_SOLUTION_TX and NAV_SOLUTION; per realization, what was sent and what arrived.
class Recorder : public LockstepNode {
 public:
  Recorder(Bus& bus, const Scenario& sc)
      : LockstepNode(bus, "recorder", 10), L_(sc.landing_frame()), radar_L_(L_.from_geodetic(sc.radar_site())) {
    add_input<nav_batch_t>(ch::kNavTx);
    add_input<nav_batch_t>(ch::kNav);
  }
  std::map<int, std::vector<Sent>> sent;
  std::map<int, std::vector<std::int64_t>> received;

 protected:
  void reset(const sim_window_t& w) override {
    r_ = w.realization;
    sent[r_].clear();
    received[r_].clear();
  }
  int process(const sim_window_t&) override {
    for (const auto& s : input<nav_batch_t>(ch::kNavTx).solutions)
      sent[r_].push_back({s.utime, (L_.from_geodetic(Geodetic{s.lat_deg, s.lon_deg, s.h_m}) - radar_L_).norm()});
    for (const auto& s : input<nav_batch_t>(ch::kNav).solutions) received[r_].push_back(s.utime);
    return 0;
  }

 private:
  LocalLevelFrame L_;
  Eigen::Vector3d radar_L_;
  int r_ = 0;
};

struct Run {
  std::map<int, std::vector<Sent>> sent;
  std::map<int, std::vector<std::int64_t>> received;
  std::map<int, std::vector<std::int64_t>> dropped;  // sent minus received, per realization
  long node_sent = 0, node_lost = 0;
};

Run run_chain(const Scenario& sc, int n, std::int64_t seed) {
  InprocBus bus;
  std::vector<std::unique_ptr<LockstepNode>> nodes;
  nodes.push_back(std::make_unique<TrajectoryNode>(bus, sc.trajectory, sc.site()));
  add_nav_nodes(bus, sc, nodes, "");
  auto* link = dynamic_cast<DatalinkNode*>(nodes.back().get());
  REQUIRE(link != nullptr);
  nodes.push_back(std::make_unique<Recorder>(bus, sc));
  auto* rec = static_cast<Recorder*>(nodes.back().get());
  const auto r = run_inproc_nodes(bus, nodes, sc.runner, sc.trajectory.step_s, make_trajectory(sc.trajectory, sc.site())->duration_s(), n, seed);
  REQUIRE(r.exit_code == 0);
  Run out{rec->sent, rec->received, {}, link->sent(), link->lost()};
  for (const auto& [real, tx] : out.sent) {
    const auto& rx = out.received[real];
    std::size_t j = 0;
    for (const auto& s : tx) {
      if (j < rx.size() && rx[j] == s.utime) ++j;  // arrived, in order
      else out.dropped[real].push_back(s.utime);
    }
    CHECK(j == rx.size());  // everything received was sent, in the order sent
  }
  return out;
}

Scenario lossy(double peak_power_w, const std::vector<std::string>& more = {}) {
  std::vector<std::string> o{"datalink.enabled=true", "datalink.peak_power_w=" + std::to_string(peak_power_w)};
  o.insert(o.end(), more.begin(), more.end());
  return Scenario::load(kPaper, o);
}

std::string slurp(const fs::path& p) {
  std::ifstream f(p, std::ios::binary);
  REQUIRE(f.good());
  std::ostringstream s;
  s << f.rdbuf();
  return s.str();
}

}  // namespace

TEST_CASE("datalink node: messages lost over the approach match the sum of their p_loss", "[datalink][statistics]") {
  // 0.03 W peak: the link's 50 % range lies inside the approach (printed below), so hundreds of
  // messages have 0 < p < 1. Lost messages are a sum of independent Bernoulli(p_i): mean sum p_i,
  // variance sum p_i (1 - p_i). We accept |lost - mean| <= 4.5 SD (P(|Z| > 4.5) = 6.8e-6 under
  // the normal approximation; one assertion) and check that a model 20 % off would fail it.
  const Scenario sc = lossy(0.03);
  const int n = 6;
  const Run r = run_chain(sc, n, 21);
  const datalink::NavLink link(sc.datalink, sc.site());
  double mean = 0, var = 0;
  long sent = 0, lost = 0;
  for (const auto& [real, tx] : r.sent) {
    for (const auto& s : tx) {
      const double p = link.budget().p_loss(s.range_m);
      mean += p;
      var += p * (1 - p);
    }
    sent += static_cast<long>(tx.size());
    lost += static_cast<long>(r.dropped.at(real).size());
  }
  INFO("50 % loss at " << link.budget().range_for_p_loss(0.5) << " m; sent " << sent << ", lost " << lost
                       << ", expected " << mean << " +- " << std::sqrt(var));
  REQUIRE(r.sent.size() == static_cast<std::size_t>(n));
  CHECK(var > 100);  // the transition is inside the approach: the test has power
  CHECK(r.node_sent == sent);
  CHECK(r.node_lost == lost);
  const double band = 4.5 * std::sqrt(var);
  CHECK(std::abs(lost - mean) <= band);
  CHECK(std::abs(lost - 0.8 * mean) > band);
  CHECK(std::abs(lost - 1.2 * mean) > band);
}

TEST_CASE("datalink node: the same seed drops the same messages whatever the lock-step window", "[datalink][determinism]") {
  const Run a = run_chain(lossy(0.03), 3, 5);
  const Run b = run_chain(lossy(0.03), 3, 5);
  const Run c = run_chain(lossy(0.03, {"runner.window_s=7.25"}), 3, 5);
  const Run d = run_chain(lossy(0.03), 3, 6);
  CHECK(a.dropped == b.dropped);
  CHECK(a.dropped == c.dropped);
  CHECK(a.dropped != d.dropped);
  long n = 0;
  for (const auto& [real, v] : a.dropped) n += static_cast<long>(v.size());
  CHECK(n > 100);
}

TEST_CASE("datalink node: a link that loses nothing leaves the paper run byte-identical", "[datalink][determinism]") {
  const fs::path base = fs::temp_directory_path() / "rnav_test_datalink_node";
  fs::remove_all(base);
  // 1 W peak: p_loss < 1e-300 over the whole approach (50 % only beyond 80 km).
  const Scenario off = Scenario::load(kPaper), on = Scenario::load(kPaper, {"datalink.enabled=true"});
  REQUIRE(datalink::NavLink(on.datalink, on.site()).budget().range_for_p_loss(0.5) > 80e3);
  REQUIRE(run_inproc_ensemble(off, 4, 9, (base / "off").string()).exit_code == 0);
  REQUIRE(run_inproc_ensemble(on, 4, 9, (base / "on").string()).exit_code == 0);
  for (const char* f : {"table2.json", "table2_detail.json", "stats_time.csv", "stats_range.csv", "realizations.csv",
                        "ensemble_state.json"})
    CHECK(slurp(base / "off" / f) == slurp(base / "on" / f));
  CHECK_FALSE(fs::exists(base / "off" / "datalink.csv"));
  CHECK(slurp(base / "on" / "datalink.csv") == "realization,sent,lost\n0,997,0\n1,997,0\n2,997,0\n3,997,0\n");
  // Every CSV of both runs has its units.json (keys = its header's columns); the link's own
  // description only with the link.
  int n_off = 0, n_on = 0;
  CHECK(rnav_test::csv_folder_units_problems(base / "off", &n_off) == "");
  CHECK(rnav_test::csv_folder_units_problems(base / "on", &n_on) == "");
  CHECK(n_on == n_off + 1);
  CHECK(slurp(base / "off" / "stats_time.units.json") == slurp(base / "on" / "stats_time.units.json"));
  CHECK_FALSE(fs::exists(base / "off" / "datalink.units.json"));
  CHECK(slurp(base / "on" / "datalink.units.json").find("\"lost\": {\"unit\": \"\", \"meaning\": ") != std::string::npos);
  fs::remove_all(base);
}

TEST_CASE("datalink node: refuses to run when the scenario does not enable the link", "[datalink][input]") {
  InprocBus bus;
  CHECK_THROWS_WITH(DatalinkNode(bus, Scenario::load(kPaper).datalink, Scenario::load(kPaper).site()), Catch::Contains("datalink.enabled"));
}
