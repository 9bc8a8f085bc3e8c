#include "estimators/model_id/offset_groups.hpp"

#include "estimators/model_id/drawn_noise.hpp"
#include "estimators/model_id/noise_model.hpp"
#include "estimators/model_id/parallel_for.hpp"
#include "estimators/model_id/stats.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>

namespace rnav::search_detail {

namespace {

// The channels each chosen non-shape entry touches (a column not zero on one of its rows); a
// shape (a drift, a step, a manoeuvre) explains no constant offset and touches none here.
std::vector<std::set<std::size_t>> touched(const Design& d, const Chosen& chosen) {
  const Problem& p = *d.pb;
  std::vector<std::set<std::size_t>> out;
  for (const auto& [e, v] : chosen) {
    std::set<std::size_t> t;
    if (!p.catalogue[e].is_shape()) {
      const Eigen::MatrixXd X = d.raw_columns(e, v);
      for (std::size_t c = 0; c < d.rows.size(); ++c)
        for (std::size_t i : d.rows[c])
          if (X.row(static_cast<Eigen::Index>(i)).cwiseAbs().maxCoeff() > 0) {
            t.insert(c);
            break;
          }
    }
    out.push_back(std::move(t));
  }
  return out;
}

// One channel's residual mean under the final model and its variance, with the noise a
// simulation draws about that mean:
//   e = y - N beta_N - C beta_C,  m = (1' W e) / (1' W 1),  var m = 1 / (1' W 1),
// W the inverse covariance of the drawn noise (drawn_noise.hpp's model with the mean as its
// fixed effect), applied by whitening; the channel's outlier flags kept out.
struct ChannelMean {
  bool ok = false;
  double m = 0, v = 0;
  NoiseFit drawn;
};
ChannelMean channel_mean(const Design& d, const SearchOptions& o, std::size_t c, const SearchResult& res) {
  ChannelMean out;
  const Eigen::VectorXd e = final_residual(d, c, res);
  try {
    out.drawn = drawn_model(d, o, c, res, e, Eigen::MatrixXd::Ones(e.size(), 1));
  } catch (const DegenerateSeries&) {
    return out;
  }
  NoiseParams q = out.drawn.params;
  q.p_out = 0, q.s_out2 = 0;
  Eigen::MatrixXd M(e.size(), 2);
  M.col(0).setOnes();
  M.col(1) = e;
  whiten(d.times[c], d.gains[c], q, res.noise[c].fit.outlier, M);
  const double ww = M.col(0).squaredNorm();
  if (!(ww > 0)) return out;
  out.m = M.col(0).dot(M.col(1)) / ww;
  out.v = 1 / ww;
  out.ok = std::isfinite(out.m) && std::isfinite(out.v) && out.v > 0;
  return out;
}

}  // namespace

void offset_groups(const Design& d, const SearchOptions& o, const Chosen& chosen, SearchResult& res) {
  const Problem& p = *d.pb;
  std::map<std::string, std::vector<std::size_t>> groups;
  for (std::size_t c = 0; c < p.channels.size(); ++c)
    if (!p.channels[c].offset_group.empty()) groups[p.channels[c].offset_group].push_back(c);
  if (groups.empty()) return;
  const std::vector<std::set<std::size_t>> touches = touched(d, chosen);
  for (const auto& [g, chans] : groups) {
    if (chans.size() < static_cast<std::size_t>(kMinOffsetTargets)) continue;
    // an entry that touches some but not all of the group's channels is their own (a target's
    // hull, antenna or echo offset): it explains their offsets
    std::set<std::size_t> explained;
    for (const auto& t : touches) {
      std::vector<std::size_t> in;
      for (std::size_t c : chans)
        if (t.count(c)) in.push_back(c);
      if (!in.empty() && in.size() < chans.size()) explained.insert(in.begin(), in.end());
    }
    std::vector<std::size_t> members;
    for (std::size_t c : chans)
      if (!explained.count(c)) members.push_back(c);
    if (members.size() < static_cast<std::size_t>(kMinOffsetTargets)) continue;
    std::vector<ChannelMean> cm(members.size());
    parallel_for(members.size(), std::max(1, o.threads), [&](std::size_t k) { cm[k] = channel_mean(d, o, members[k], res); });
    std::vector<std::size_t> used;
    for (std::size_t k = 0; k < members.size(); ++k)
      if (cm[k].ok) used.push_back(k);
    if (used.size() < static_cast<std::size_t>(kMinOffsetTargets)) continue;
    // DerSimonian-Laird over the targets' means; SE(mu) = (sum w*)^-1/2
    std::vector<double> means, vars;
    for (std::size_t k : used) means.push_back(cm[k].m), vars.push_back(cm[k].v);
    const RandomEffects re = dersimonian_laird(means, vars);
    OffsetGroup og;
    og.group = g;
    og.unit = p.channels[members[used.front()]].unit;
    og.targets = static_cast<int>(used.size());
    og.mean = re.mean;
    og.mean_se = std::sqrt(1 / re.sum_w);
    og.sd = std::sqrt(re.tau2);
    og.q = re.q;
    for (std::size_t k : used) {
      const std::size_t c = members[k];
      og.channels.push_back(p.channels[c].name);
      ChannelNoise& cn = res.noise[c];
      cn.drawn = cm[k].drawn;
      cn.offset_group = g;
      cn.slow_wander = slow_wander(cn, d.times[c], o.noise);
    }
    for (std::size_t c : explained) og.explained.push_back(p.channels[c].name);
    res.offsets.push_back(std::move(og));
  }
}

}  // namespace rnav::search_detail
