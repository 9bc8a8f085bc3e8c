// Noise first, then forward selection under the identified noise, re-identified until the
// choice settles (effect_search.hpp). The reporting steps are in effect_report.cpp.
#include "effect_search.hpp"

#include "effect_report.hpp"
#include "search_design.hpp"
#include "stats.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace rnav {

using search_detail::Design;
using Chosen = std::vector<std::pair<std::size_t, std::size_t>>;

std::string Scope::label() const {
  if (sensor.empty() && target.empty()) return "common";
  if (target.empty()) return "sensor " + sensor;
  if (sensor.empty()) return "target " + target;
  return sensor + ":" + target;
}

namespace {

void check_options(const SearchOptions& o) {
  if (!(o.alpha > 0 && o.alpha < 0.5)) throw std::invalid_argument("effect search: alpha must be in (0, 0.5)");
  if (!(o.power > 0.5 && o.power < 1)) throw std::invalid_argument("effect search: power must be in (0.5, 1)");
  if (!(o.confound_corr > 0 && o.confound_corr < 1))
    throw std::invalid_argument("effect search: confound_corr must be in (0, 1)");
  if (o.max_effects < 1 || o.max_rounds < 1) throw std::invalid_argument("effect search: max_effects, max_rounds >= 1");
}

// Each channel's noise, identified with the nuisance, the chosen effects and every non-scanned
// catalogue entry (restricted to the channel) as fixed effects: a physical effect in the data,
// chosen yet or not, is then not taken for correlated noise (REML keeps the cost of the extra
// columns in its log-determinant).
std::vector<NoiseFit> identify_all(const Design& d, const Chosen& chosen, const NoiseIdOptions& no) {
  const Problem& p = *d.pb;
  Chosen fixed = chosen;
  for (std::size_t e = 0; e < p.catalogue.size(); ++e)
    if (!p.catalogue[e].scanned() &&
        std::none_of(chosen.begin(), chosen.end(), [&](const auto& c) { return c.first == e; }))
      fixed.push_back({e, 0});
  const Eigen::MatrixXd X = search_detail::raw_model_matrix(d, fixed);
  std::vector<NoiseFit> out;
  for (std::size_t c = 0; c < d.rows.size(); ++c) {
    const auto m = static_cast<Eigen::Index>(d.rows[c].size());
    Eigen::VectorXd e(m);
    Eigen::MatrixXd Xc(m, X.cols());
    for (Eigen::Index r = 0; r < m; ++r) {
      const auto i = d.rows[c][static_cast<std::size_t>(r)];
      e(r) = p.y[i];
      Xc.row(r) = X.row(static_cast<Eigen::Index>(i));
    }
    // keep only the columns that touch this channel
    std::vector<Eigen::Index> keep;
    for (Eigen::Index j = 0; j < Xc.cols(); ++j)
      if (!Xc.col(j).isZero(0)) keep.push_back(j);
    Eigen::MatrixXd Xk(m, static_cast<Eigen::Index>(keep.size()));
    for (std::size_t j = 0; j < keep.size(); ++j) Xk.col(static_cast<Eigen::Index>(j)) = Xc.col(keep[j]);
    out.push_back(identify_noise(d.times[c], e, Xk, no));
  }
  return out;
}

// Forward selection under the design's current noise: the entry with the smallest adjusted
// log p enters while it is below log alpha.
Chosen forward_select(const Design& d, const SearchOptions& o, double m_family) {
  const Problem& p = *d.pb;
  Chosen chosen;
  std::vector<char> taken(p.catalogue.size(), 0);
  const double log_alpha = std::log(o.alpha);
  for (int step = 0; step < o.max_effects; ++step) {
    const search_detail::Projector P(search_detail::model_matrix(d, chosen), d.yw, d.n_used);
    double best = 0;
    std::pair<std::size_t, std::size_t> arg{0, 0};
    bool any = false;
    for (std::size_t e = 0; e < p.catalogue.size(); ++e) {
      if (taken[e]) continue;
      const double k = static_cast<double>(p.catalogue[e].params.size());
      for (std::size_t v = 0; v < d.Cw[e].size(); ++v) {
        const double lr = P.lr(d.Cw[e][v]);
        if (lr <= 0) continue;
        // Bonferroni: alpha / m per entry, split over the entry's grid.
        const double lp = log_chi2_sf(lr, k) + std::log(static_cast<double>(d.Cw[e].size())) + std::log(m_family);
        if (!any || lp < best) best = lp, arg = {e, v}, any = true;
      }
    }
    if (!any || best >= log_alpha) break;
    chosen.push_back(arg);
    taken[arg.first] = 1;
  }
  return chosen;
}

}  // namespace

SearchResult search_effects(const Problem& pb, const SearchOptions& o_in) {
  check_options(o_in);
  SearchOptions o = o_in;
  Design d(pb);
  SearchResult res;
  const double n_ch = static_cast<double>(pb.channels.size());
  // The family: every catalogue entry, and three noise tests (scale, correlation, outliers) per channel.
  res.family_size = static_cast<double>(pb.catalogue.size()) + 3 * n_ch;
  res.familywise = "alpha = " + short_num(o.alpha) + " familywise: Bonferroni over " + short_num(res.family_size) +
                   " tests (" + std::to_string(pb.catalogue.size()) + " catalogue entries, each scanned entry split over "
                   "its grid; 3 noise tests per channel x " + std::to_string(pb.channels.size()) + " channels)";
  o.noise.alpha_correlated = o.alpha / res.family_size;

  Chosen chosen;
  std::vector<NoiseFit> fits;
  for (int round = 0; round < o.max_rounds; ++round) {
    fits = identify_all(d, chosen, o.noise);
    std::vector<NoiseParams> np;
    std::vector<std::vector<char>> sk;
    for (const auto& f : fits) {
      NoiseParams q = f.params;
      q.p_out = 0, q.s_out2 = 0;
      np.push_back(q);
      sk.push_back(f.outlier);
    }
    d.set_noise(np, sk);
    const Chosen next = forward_select(d, o, res.family_size);
    const bool settled = next == chosen;
    chosen = next;
    if (settled && round > 0) break;
  }
  search_detail::report(d, o, chosen, fits, res);
  return res;
}

}  // namespace rnav
