#include "sim/datalink/datalink_node.hpp"

#include "common/io/atomic_file.hpp"
#include "common/io/config.hpp"

#include <rnav/nav_batch_t.hpp>

#include <filesystem>

namespace rnav {

DatalinkNode::DatalinkNode(Bus& bus, const DatalinkOptions& d, const SiteContext& site, std::string out_dir)
    : LockstepNode(bus, "datalink", site.runner.peer_timeout_s), link_(d, site), out_dir_(std::move(out_dir)) {
  if (!d.enabled)
    throw ConfigError("the node 'datalink' runs only with scenario key 'datalink.enabled' = true (otherwise snsins "
                      "publishes NAV_SOLUTION itself and nothing is sent on NAV_SOLUTION_TX)");
  add_input<nav_batch_t>(ch::kNavTx);
}

void DatalinkNode::reset(const sim_window_t& w) {
  rng_.emplace(static_cast<std::uint64_t>(w.seed), static_cast<std::uint64_t>(w.realization), Stream::kDatalink);
  realization_ = w.realization;
  cur_sent_ = cur_lost_ = 0;
}

int DatalinkNode::process(const sim_window_t&) {
  nav_batch_t out;
  for (const auto& s : input<nav_batch_t>(ch::kNavTx).solutions) {
    const double u = rng_->uniform();  // one draw per message, lost or not
    ++cur_sent_;
    if (link_.lost(link_.range_m(s), u)) {
      ++cur_lost_;
      continue;
    }
    out.solutions.push_back(s);
  }
  out.n = static_cast<int>(out.solutions.size());
  publish_batch(ch::kNav, out);
  return out.n;
}

void DatalinkNode::commit() {
  sent_ += cur_sent_;
  lost_ += cur_lost_;
  rows_ += std::to_string(realization_) + "," + std::to_string(cur_sent_) + "," + std::to_string(cur_lost_) + "\n";
  cur_sent_ = cur_lost_ = 0;
}

void DatalinkNode::finish(const sim_window_t&) {
  if (out_dir_.empty()) return;
  std::filesystem::create_directories(out_dir_);
  write_file_atomic(out_dir_, "datalink.csv", csv_header(csv_columns()) + rows_);
  write_csv_units(out_dir_, "datalink.csv", csv_columns());
}

std::vector<CsvColumnDoc> DatalinkNode::csv_columns() {
  return {{"realization", "", "realization index in the ensemble"},
          {"sent", "", "navigation messages the aircraft sent over the data link (NAV_SOLUTION_TX)"},
          {"lost", "", "of those, the messages the link lost"}};
}

}  // namespace rnav
