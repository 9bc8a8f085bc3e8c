// Node "datalink": the navigation data link between the aircraft and the ground.
// Reads NAV_SOLUTION_TX (what snsins has the aircraft send, when datalink.enabled) and publishes
// on NAV_SOLUTION the solutions that survive the link, in the same window and order: each
// message is lost with probability p_loss(d) of its slant range d (NavLink), decided by one
// uniform draw per message from the stream (seed, realization, Stream::kDatalink) in message
// order, so the same seed drops the same messages whatever the scheduling or windowing.
// With an output folder it writes DIR/datalink.csv on FINISH: per realization (in order) the
// messages sent and lost, `realization,sent,lost`, and datalink.units.json beside it (csv_columns()).
#pragma once

#include "common/io/csv_columns.hpp"
#include "common/node/lockstep_node.hpp"
#include "sim/datalink/nav_link.hpp"
#include "common/physics/random.hpp"

#include <optional>
#include <string>
#include <vector>

namespace rnav {

class DatalinkNode : public LockstepNode {
 public:
  /// datalink.csv's columns (its header and datalink.units.json).
  static std::vector<CsvColumnDoc> csv_columns();
  /// @param out_dir  where FINISH writes datalink.csv; "" writes nothing
  DatalinkNode(Bus& bus, const DatalinkOptions& d, const SiteContext& site, std::string out_dir = "");
  const datalink::NavLink& link() const { return link_; }
  /// Messages sent and lost over the realizations completed so far (repeated attempts counted once).
  long sent() const { return sent_; }
  long lost() const { return lost_; }

 protected:
  void reset(const sim_window_t& w) override;
  int process(const sim_window_t& w) override;
  void commit() override;
  void finish(const sim_window_t& w) override;

 private:
  datalink::NavLink link_;
  std::string out_dir_;
  std::optional<Rng> rng_;
  int realization_ = -1;
  long cur_sent_ = 0, cur_lost_ = 0;  // the current attempt of the current realization
  long sent_ = 0, lost_ = 0;          // committed realizations
  std::string rows_;                  // datalink.csv's rows, in realization order
};

}  // namespace rnav
