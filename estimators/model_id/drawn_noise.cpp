#include "estimators/model_id/drawn_noise.hpp"

#include "estimators/model_id/parallel_for.hpp"

#include <algorithm>

namespace rnav::search_detail {

Eigen::VectorXd final_residual(const Design& d, std::size_t c, const SearchResult& res) {
  Eigen::VectorXd e = channel_y(d, c);
  for (std::size_t r = 0; r < d.rows[c].size(); ++r) {
    const auto i = static_cast<Eigen::Index>(d.rows[c][r]);
    e(static_cast<Eigen::Index>(r)) -= res.nuisance_fit(i) + res.effect_fit(i);
  }
  return e;
}

NoiseFit drawn_model(const Design& d, const SearchOptions& o, std::size_t c, const SearchResult& res, const Eigen::VectorXd& e,
                     const Eigen::MatrixXd& X) {
  const ChannelNoise& cn = res.noise[c];
  NoiseIdOptions nc = channel_options(*d.pb, c, o.noise);
  nc.profile_ml = true;
  nc.tau_span_divisor = 0.25;
  const NoiseFit f = identify_noise(d.times[c], d.gains[c], e, X, nc, &cn.fit.outlier);
  NoiseFit drawn = cn.fit;
  // a correlated part only where the data support it by Akaike's 2 per parameter (as the
  // identified noise whitens), else the identified noise stands
  if (!(2 * (f.loglik_correlated - f.loglik_nominal) > o.noise.use_correlated_lr)) return drawn;
  drawn.params.s2 = f.params.s2;
  drawn.params.lambda = f.params.lambda;
  drawn.params.tau_s = f.params.tau_s;
  drawn.correlated = f.correlated;
  drawn.loglik_ml = f.loglik_ml;
  return drawn;
}

bool slow_wander(const ChannelNoise& cn, const std::vector<double>& t, const NoiseIdOptions& no) {
  const double span = t.back() - t.front();
  return cn.drawn.correlated && cn.drawn.params.lambda > 0 && cn.drawn.params.tau_s > span / no.tau_span_divisor &&
         cn.drawn.params.s2 > 1.21 * cn.fit.params.s2;
}

void drawn_noise(const Design& d, const SearchOptions& o, SearchResult& res) {
  parallel_for(res.noise.size(), std::max(1, o.threads), [&](std::size_t ch) {
    ChannelNoise& cn = res.noise[ch];
    cn.drawn = cn.fit;
    try {
      cn.drawn = drawn_model(d, o, ch, res, final_residual(d, ch, res), Eigen::MatrixXd());
      cn.drawn_ok = true;
    } catch (const DegenerateSeries&) {
      return;  // no spread left: the channel's fit stands
    }
    cn.slow_wander = slow_wander(cn, d.times[ch], o.noise);
  });
}

}  // namespace rnav::search_detail
