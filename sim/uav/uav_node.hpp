// Node "uav": the observer. From TRUTH_TARGET at each sensor frame it publishes the UAV's true
// state (TRUTH_UAV), its navigation solution (UAV_NAV: truth + white + Gauss-Markov position
// error per axis) and the passive sensor's bearings (UAV_BEARING: true bearing from the true
// UAV position + white noise; none when the object is outside the field of regard or range).
// The sensor's error model is BearingErrorModel (a list of effects).
// Guidance (uav.guidance): "orbit" flies ObserverPath's prescribed track; "los" and "estimate"
// close the loop (guidance.hpp): the UAV subscribes to UAV_TMA as a feedback input (each window
// gets the estimates of the window before) and steers, at each frame, with the estimate of
// uav.guidance_estimator that is uav.estimate_latency_s old and its own navigation solution.
#pragma once

#include "common/node/lockstep_node.hpp"
#include "sim/uav/bearing_error_model.hpp"
#include "sim/uav/guidance.hpp"
#include "sim/uav/observer_path.hpp"
#include "common/physics/random.hpp"
#include "sim/uav/sensor_options.hpp"
#include "common/node/uav_context.hpp"

#include <array>
#include <optional>
#include <vector>

namespace rnav {

class UavNode : public LockstepNode {
 public:
  /// @param target_start_NE_m  [m] the object's first position (north, east): the orbit's
  ///                           centre before uav.centre_offset_*
  UavNode(Bus& bus, const ObserverOptions& uav, const ObserverNavOptions& nav, const SensorOptions& sensor,
          const SensorEffectsOptions& effects, const Eigen::Vector2d& target_start_NE_m, const UavContext& ctx);

 protected:
  void reset(const sim_window_t& w) override;
  int process(const sim_window_t& w) override;

 private:
  ObserverOptions uav_;
  ObserverNavOptions nav_;
  SensorOptions sensor_;
  UavContext ctx_;
  LocalLevelFrame frame_;
  ObserverPath path_;
  std::optional<Rng> rng_;
  std::array<GaussMarkov, 2> corr_;
  BearingErrorModel bearing_error_;
  double last_t_s_ = 0;
  std::int64_t frame_id_ = 0;

  // Closed-loop guidance (uav.guidance != "orbit").
  struct HeldEstimate {
    std::int64_t utime;          // [us] time of validity
    Eigen::Vector4d x;           // (north, east, v_north, v_east) [m, m, m/s, m/s]
  };
  void take_estimates();                          // this window's feedback batch -> estimates_
  const HeldEstimate* estimate_at(std::int64_t utime) const;  // the newest with utime <= the given
  ObserverKinematics closed_loop_kinematics() const;
  void steer(std::int64_t utime, const Eigen::Vector2d& p_nav_F, const bearing_t* measured);
  guidance::Limits limits_;
  guidance::UavState state_;
  double state_t_s_ = 0;       // [s] time of state_
  double omega_radps_ = 0;     // turn rate held until the next frame
  std::optional<double> last_bearing_rad_;
  std::vector<HeldEstimate> estimates_;
};

}  // namespace rnav
