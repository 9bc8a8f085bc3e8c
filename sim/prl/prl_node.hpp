// Node "prl": the landing radar. From TRUTH_AIRCRAFT at the plot times
// t = phase_s + k period_s (within max_range_m) it publishes raw plots (PRL_APOI) and, as
// simulation truth, the injected errors (TRUTH_PRL_ERROR).
#pragma once

#include "common/node/lockstep_node.hpp"
#include "sim/prl/prl_error_model.hpp"
#include "common/node/site_context.hpp"

#include <optional>

namespace rnav {

class PrlNode : public LockstepNode {
 public:
  PrlNode(Bus& bus, const PrlOptions& o, const PrlEffectsOptions& fx, const SiteContext& site);

 protected:
  void reset(const sim_window_t& w) override;
  int process(const sim_window_t& w) override;

 private:
  PrlOptions o_;
  SiteContext site_;
  LocalLevelFrame frame_L_, frame_R_;
  PrlErrorModel model_;
  std::optional<Rng> rng_;
  std::int64_t plot_id_ = 0;
};

}  // namespace rnav
