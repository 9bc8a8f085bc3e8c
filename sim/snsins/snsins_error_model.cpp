#include "sim/snsins/snsins_error_model.hpp"

#include <cmath>
#include <limits>

namespace rnav {

namespace {
double smooth_alpha(const SnsinsOptions& o) {
  return o.ins_tau_s > 0 ? std::min(1.0, o.sns_period_s / o.ins_tau_s) : 1.0;
}
}  // namespace

SnsinsErrorModel::SnsinsErrorModel(const SnsinsOptions& o)
    : o_(o),
      // sigma_s = sigma_w sqrt(a / (2 - a)): stationary variance of y = (1-a) y + a x
      sigma_smooth_(o.white_sigma_m * std::sqrt(smooth_alpha(o) / (2 - smooth_alpha(o)))),
      // phi = 1 - a per fix  =>  T = -dt / ln(1 - a); a = 1 (white) -> T -> 0
      tau_smooth_(smooth_alpha(o) < 1 ? -o.sns_period_s / std::log(1 - smooth_alpha(o))
                                      : std::numeric_limits<double>::min()),
      corr_{GaussMarkov(o.corr_sigma_m, o.corr_tau_s), GaussMarkov(o.corr_sigma_m, o.corr_tau_s),
            GaussMarkov(o.corr_sigma_m, o.corr_tau_s)},
      smooth_{GaussMarkov(sigma_smooth_, tau_smooth_), GaussMarkov(sigma_smooth_, tau_smooth_),
              GaussMarkov(sigma_smooth_, tau_smooth_)} {}

double SnsinsErrorModel::sigma_pos_m() const {
  return std::sqrt(o_.corr_sigma_m * o_.corr_sigma_m + sigma_smooth_ * sigma_smooth_);
}

void SnsinsErrorModel::start(Rng& rng) {
  t_s_ = 0;
  for (int i = 0; i < 3; ++i) {
    corr_[i].start(rng);
    smooth_[i].start(rng);
    dp_[i] = corr_[i].value() + smooth_[i].value();
    dv_[i] = o_.vel_sigma_mps * rng.normal();
  }
}

void SnsinsErrorModel::step(double t_s, Rng& rng) {
  const double dt = t_s - t_s_;
  t_s_ = t_s;
  for (int i = 0; i < 3; ++i) {
    dp_[i] = corr_[i].step(dt, rng) + smooth_[i].step(dt, rng);
    dv_[i] = o_.vel_sigma_mps * rng.normal();
  }
}

}  // namespace rnav
