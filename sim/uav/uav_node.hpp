// Node "uav": the observer. From TRUTH_TARGET at each sensor frame it publishes the UAV's true
// state (TRUTH_UAV), its navigation solution (UAV_NAV: truth + white + Gauss-Markov position
// error per axis) and the passive sensor's bearings (UAV_BEARING: true bearing from the true
// UAV position + white noise; none when the object is outside the field of regard or range).
// The sensor's error model is BearingErrorModel (a list of effects).
#pragma once

#include "lockstep_node.hpp"
#include "bearing_error_model.hpp"
#include "observer_path.hpp"
#include "random.hpp"

#include <array>
#include <optional>

namespace rnav {

class UavNode : public LockstepNode {
 public:
  UavNode(Bus& bus, const UavScenario& sc);

 protected:
  void reset(const sim_window_t& w) override;
  int process(const sim_window_t& w) override;

 private:
  UavScenario sc_;
  LocalLevelFrame frame_;
  ObserverPath path_;
  std::optional<Rng> rng_;
  std::array<GaussMarkov, 2> corr_;
  BearingErrorModel bearing_error_;
  double last_t_s_ = 0;
  std::int64_t frame_id_ = 0;
};

}  // namespace rnav
