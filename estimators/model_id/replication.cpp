#include "estimators/model_id/replication.hpp"

#include "estimators/model_id/stats.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace rnav::search_detail {

double t_two_sided(double t, double nu) {
  // P(|T| > t) = I_{nu / (nu + t^2)}(nu / 2, 1 / 2)
  if (!(nu > 0)) return std::numeric_limits<double>::quiet_NaN();
  return beta_inc(nu / 2, 0.5, nu / (nu + t * t));
}

Replication replication(const Design& d, const Chosen& chosen, std::size_t s) {
  const Problem& p = *d.pb;
  const auto [e, v] = chosen[s];
  const Candidate& c = p.catalogue[e];
  Replication out;
  if (c.replicates.empty()) return out;
  const auto k = static_cast<Eigen::Index>(c.params.size());
  // the replicates with data: a whitened column set that is not zero
  std::vector<std::size_t> reps;
  for (std::size_t r : c.replicates)
    if (d.Cw[r][c.scanned() ? v : 0].norm() > 0) reps.push_back(r);
  if (reps.size() < 2) return out;
  // the rest of the model, without the entry's own per-replicate copies where they are chosen
  // too (a recording's own start-up bias): with them in, its replicates would be spanned and
  // the check would have nothing to compare
  Chosen model;
  for (std::size_t i = 0; i < chosen.size(); ++i)
    if (i != s && std::find(c.replicates.begin(), c.replicates.end(), chosen[i].first) == c.replicates.end())
      model.push_back(chosen[i]);
  const Eigen::Index base = model_matrix(d, model).cols();
  for (std::size_t r : reps) model.push_back({r, c.scanned() ? v : 0});
  const Eigen::MatrixXd M = model_matrix(d, model);
  const Ols f = ols(M, d.yw, d.used);
  if (!f.ok) return out;  // a replicate inside the rest of the model: no per-replicate values
  const double scale = f.rss / std::max(1.0, f.n - static_cast<double>(M.cols()));
  const auto R = static_cast<Eigen::Index>(reps.size());
  Eigen::MatrixXd b(R, k), se(R, k);
  for (Eigen::Index r = 0; r < R; ++r) {
    const Scope& rs = p.catalogue[reps[static_cast<std::size_t>(r)]].scope;
    if (rs.recording.empty() && !rs.target.empty()) out.over = "targets";
    out.recordings.push_back(rs.recording.empty() ? rs.target : rs.recording);
    for (Eigen::Index j = 0; j < k; ++j) {
      const Eigen::Index col = base + r * k + j;
      b(r, j) = f.beta(col);
      se(r, j) = std::sqrt(f.cov_unscaled(col, col) * scale);
    }
  }
  out.estimate.assign(static_cast<std::size_t>(R), std::vector<double>(static_cast<std::size_t>(k)));
  out.stderr_ = out.estimate;
  for (Eigen::Index r = 0; r < R; ++r)
    for (Eigen::Index j = 0; j < k; ++j) {
      out.estimate[static_cast<std::size_t>(r)][static_cast<std::size_t>(j)] = b(r, j);
      out.stderr_[static_cast<std::size_t>(r)][static_cast<std::size_t>(j)] = se(r, j);
    }
  const double nu = static_cast<double>(R - 1);
  double min_p = 1, min_q = 1;
  for (Eigen::Index j = 0; j < k; ++j) {
    std::vector<double> bj(static_cast<std::size_t>(R)), vj(bj.size());
    for (Eigen::Index r = 0; r < R; ++r) bj[static_cast<std::size_t>(r)] = b(r, j), vj[static_cast<std::size_t>(r)] = se(r, j) * se(r, j);
    if (!std::all_of(vj.begin(), vj.end(), [](double v) { return v > 0 && std::isfinite(v); })) {
      // an exact fit or a singular column: no spread to pool, this parameter tests nothing
      out.mean.push_back(std::numeric_limits<double>::quiet_NaN());
      out.mean_se.push_back(std::numeric_limits<double>::quiet_NaN());
      out.between_sd.push_back(std::numeric_limits<double>::quiet_NaN());
      continue;
    }
    const RandomEffects re = dersimonian_laird(bj, vj);
    min_q = std::min(min_q, chi2_sf(re.q, nu));
    // Hartung-Knapp on the random-effects weights w*_r = 1 / (se_r^2 + tau^2):
    //   SE^2 = sum w* (b_r - m)^2 / ((R - 1) sum w*), t = m / SE ~ t(R - 1)
    const double m = re.mean;
    double hk = 0;
    for (std::size_t r = 0; r < bj.size(); ++r) hk += (bj[r] - m) * (bj[r] - m) / (vj[r] + re.tau2);
    const double se_hk = std::sqrt(hk / (nu * re.sum_w));
    out.mean.push_back(m);
    out.mean_se.push_back(se_hk);
    out.between_sd.push_back(std::sqrt(re.tau2));
    const double pj = se_hk > 0 ? t_two_sided(m / se_hk, nu) : (m != 0 ? 0.0 : 1.0);
    min_p = std::min(min_p, pj);
  }
  out.tested = true;
  out.log10_p = std::log10(std::max(1e-300, std::min(1.0, min_p * static_cast<double>(k))));  // Bonferroni over its parameters
  out.homogeneity_log10_p = std::log10(std::max(1e-300, std::min(1.0, min_q * static_cast<double>(k))));
  return out;
}

}  // namespace rnav::search_detail
