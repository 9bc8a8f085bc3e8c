#include "sim/target/target_node.hpp"

#include <rnav/target_truth_batch_t.hpp>

namespace rnav {

TargetNode::TargetNode(Bus& bus, const TargetOptions& o, double step_s, const UavContext& ctx)
    : LockstepNode(bus, "target", ctx.runner.peer_timeout_s),
      step_s_(step_s),
      ctx_(ctx),
      motion_(o, step_s),
      frame_(ctx.frame()) {}

int TargetNode::process(const sim_window_t& w) {
  const std::int64_t step = to_us(step_s_), end = to_us(ctx_.duration_s);
  const std::int64_t b = w.utime_begin - ctx_.runner.epoch_utime, e = w.utime_end - ctx_.runner.epoch_utime;
  target_truth_batch_t batch;
  for (std::int64_t t = (b + step - 1) / step * step; t < e && t <= end; t += step) {
    const TargetKinematics k = motion_.at(t * 1e-6);
    target_state_t s;
    s.utime = ctx_.utime(t);
    s.p_OT_F[0] = k.p_OT_F.x();
    s.p_OT_F[1] = k.p_OT_F.y();
    s.v_T_F[0] = k.v_T_F.x();
    s.v_T_F[1] = k.v_T_F.y();
    const Geodetic g = frame_.to_geodetic(Eigen::Vector3d(k.p_OT_F.x(), 0.0, k.p_OT_F.y()));
    s.lat_deg = g.lat_deg;
    s.lon_deg = g.lon_deg;
    batch.states.push_back(s);
  }
  batch.n = static_cast<int>(batch.states.size());
  publish_batch(ch::kTruthTarget, batch);
  return batch.n;
}

}  // namespace rnav
