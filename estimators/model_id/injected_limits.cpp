// Limits measured by injection (injected_limits.hpp).
#include "estimators/model_id/injected_limits.hpp"

#include "estimators/model_id/parallel_for.hpp"
#include "estimators/model_id/progress_clock.hpp"

#include "estimators/model_id/search_design.hpp"
#include "estimators/model_id/stats.hpp"

#include <algorithm>
#include <cstdio>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace rnav {

using search_detail::Design;

namespace {

void check(const InjectionOptions& io) {
  if (io.injections < 0 || io.ladder_injections < 1 || io.max_ladder < 2 || io.threads < 1)
    throw std::invalid_argument("injected limits: injections >= 0, ladder_injections >= 1, max_ladder >= 2, threads >= 1");
  if (!(io.max_multiple > 1) || !std::isfinite(io.max_multiple))
    throw std::invalid_argument("injected limits: max_multiple must be finite and > 1");
  if (!(io.conf > 0 && io.conf < 1)) throw std::invalid_argument("injected limits: conf must be in (0, 1)");
}

std::uint64_t splitmix(std::uint64_t x) {
  x += 0x9e3779b97f4a7c15ULL;
  x = (x ^ (x >> 30)) * 0xbf58476d1ce4e5b9ULL;
  x = (x ^ (x >> 27)) * 0x94d049bb133111ebULL;
  return x ^ (x >> 31);
}

// The stream of one injection: (seed, entry, parameter, batch, index) only.
std::uint64_t stream_seed(std::uint64_t seed, std::size_t e, std::size_t j, std::size_t batch, int i) {
  std::uint64_t s = splitmix(seed);
  for (std::uint64_t x : {static_cast<std::uint64_t>(e), static_cast<std::uint64_t>(j), static_cast<std::uint64_t>(batch),
                          static_cast<std::uint64_t>(i)})
    s = splitmix(s ^ x);
  return s;
}

// What the bootstrap draws from: the data's fitted model and its identified noise.
struct Bootstrap {
  const Problem& pb;
  const SearchResult& res;
  const SearchOptions& inner;  // the search run on every injection (no limits of its own)
  const Design& d;
  std::vector<NoiseParams> noise;  // per channel

  // The fitted mean without entry e's own contribution (if it was named).
  Eigen::VectorXd base(std::size_t e) const {
    Eigen::VectorXd mu = res.nuisance_fit + res.effect_fit;
    for (const FoundEffect& f : res.effects) {
      if (f.entry != e) continue;
      const Eigen::MatrixXd C = d.raw_columns(f.entry, f.variant);
      mu -= C * Eigen::Map<const Eigen::VectorXd>(f.estimate.data(), static_cast<Eigen::Index>(f.estimate.size()));
    }
    return mu;
  }

  // One injection: named, detected.
  std::pair<bool, bool> run(const Eigen::VectorXd& mu, const Eigen::VectorXd& col, std::size_t e, double a,
                            std::uint64_t seed) const {
    std::mt19937_64 rng(seed);
    Problem q = pb;
    for (std::size_t c = 0; c < d.rows.size(); ++c) {
      const Eigen::VectorXd w = sample_noise(d.times[c], d.gains[c], noise[c], rng);
      for (std::size_t r = 0; r < d.rows[c].size(); ++r) {
        const std::size_t i = d.rows[c][r];
        const auto ii = static_cast<Eigen::Index>(i);
        q.y[i] = mu(ii) + a * col(ii) + w(static_cast<Eigen::Index>(r));
      }
    }
    const SearchResult s = search_effects(q, inner);
    bool named = false, detected = false;
    for (const FoundEffect& f : s.effects) {
      if (f.entry == e) named = detected = true;
      for (const auto& cf : f.confounded_with)
        if (cf.entry == e) detected = true;
    }
    return {named, detected};
  }
};

// Run `n` injections at size a on `threads` threads; returns (named, detected) counts.
std::pair<int, int> batch(const Bootstrap& b, const Eigen::VectorXd& mu, const Eigen::VectorXd& col, std::size_t e,
                          std::size_t j, std::size_t batch_id, double a, int n, const InjectionOptions& io) {
  std::vector<std::pair<bool, bool>> out(static_cast<std::size_t>(n));
  parallel_for(out.size(), io.threads, [&](std::size_t i) {
    out[i] = b.run(mu, col, e, a, stream_seed(io.seed, e, j, batch_id, static_cast<int>(i)));
  });
  int named = 0, detected = 0;
  for (const auto& [nm, dt] : out) named += nm, detected += dt;
  return {named, detected};
}

double normal_cdf(double z) { return 0.5 * std::erfc(-z / std::sqrt(2.0)); }

// The size hit with probability p by the probit P(hit | a) = Phi(b0 + b1 log a) fitted to the
// ladder by penalised maximum likelihood (Fisher scoring). A few rungs of ten leave the slope
// loose (one rung at 7/10 and one at 10/10 make it any steepness), so b1 carries a weak normal
// prior: a test that detects a with standard error SE has P = Phi(a / SE - z_crit), whose slope
// in log a at the crossing is a / SE = z_crit + z_p, about 4.8 here; prior N(4.8, 2^2), and
// b1 >= 0.5. Returns NaN when the ladder never reached p.
double probit_size(const std::vector<InjectedLimit::Rung>& ladder, bool named, double p) {
  double x_hit = INFINITY, x_miss = -INFINITY;
  for (const auto& r : ladder) {
    const double rate = static_cast<double>(named ? r.named : r.detected) / r.n;
    if (rate >= p) x_hit = std::min(x_hit, std::log(r.size));
    else x_miss = std::max(x_miss, std::log(r.size));
  }
  if (!std::isfinite(x_hit)) return std::numeric_limits<double>::quiet_NaN();
  const double zp = normal_upper_quantile(1 - p);
  double b1 = 4, b0 = zp - b1 * (std::isfinite(x_miss) ? 0.5 * (x_hit + x_miss) : x_hit);
  constexpr double kSlopePrior = 4.8, kSlopePriorSd = 2;
  auto loglik = [&](double c0, double c1) {
    double l = -0.5 * std::pow((c1 - kSlopePrior) / kSlopePriorSd, 2);
    for (const auto& r : ladder) {
      const double k = named ? r.named : r.detected;
      const double P = std::clamp(normal_cdf(c0 + c1 * std::log(r.size)), 1e-12, 1 - 1e-12);
      l += k * std::log(P) + (r.n - k) * std::log(1 - P);
    }
    return l;
  };
  for (int it = 0; it < 100; ++it) {
    // score and expected information of (b0, b1)
    Eigen::Vector2d g(0, -(b1 - kSlopePrior) / (kSlopePriorSd * kSlopePriorSd));
    Eigen::Matrix2d I = Eigen::Matrix2d::Zero();
    I(1, 1) = 1 / (kSlopePriorSd * kSlopePriorSd);
    for (const auto& r : ladder) {
      const double x = std::log(r.size), eta = b0 + b1 * x, k = named ? r.named : r.detected;
      const double P = std::clamp(normal_cdf(eta), 1e-12, 1 - 1e-12);
      const double phi = std::exp(-0.5 * eta * eta) / std::sqrt(2 * M_PI);
      const double w = phi * phi / (P * (1 - P));
      const Eigen::Vector2d dx(1, x);
      g += (k - r.n * P) * phi / (P * (1 - P)) * dx;
      I += r.n * w * dx * dx.transpose();
    }
    Eigen::Vector2d step = (I + 1e-9 * Eigen::Matrix2d::Identity()).ldlt().solve(g);
    const double l0 = loglik(b0, b1);
    double h = 1;
    while (h > 1e-6 && loglik(b0 + h * step(0), std::max(0.5, b1 + h * step(1))) < l0) h /= 2;
    if (h <= 1e-6) break;
    b0 += h * step(0), b1 = std::max(0.5, b1 + h * step(1));
    if (h * step.norm() < 1e-10) break;
  }
  double x = (zp - b0) / b1;
  // never beyond the ladder's evidence: within a factor 2 of the sizes tried
  double lo = INFINITY, hi = -INFINITY;
  for (const auto& r : ladder) lo = std::min(lo, std::log(r.size)), hi = std::max(hi, std::log(r.size));
  x = std::clamp(x, lo - std::log(2.0), hi + std::log(2.0));
  return std::exp(x);
}

// The parameter's Fisher limit: z SE, SE from the entry alone with the nuisance under the
// identified noise, z = z_(alpha / 2 m v) + z_power (v: the entry's grid size).
double fisher_limit(const Design& d, const SearchOptions& o, double m, std::size_t e, std::size_t v, std::size_t j) {
  const search_detail::Ols f = search_detail::ols(search_detail::model_matrix(d, {{e, v}}), d.yw, d.used);
  if (!f.ok) return INFINITY;
  const auto ix = d.Nw.cols() + static_cast<Eigen::Index>(j);
  const double se = std::sqrt(f.cov_unscaled(ix, ix) * f.rss / std::max(1.0, f.n - static_cast<double>(f.beta.size())));
  const double variants = static_cast<double>(d.pb->catalogue[e].variants());
  return (z_two_sided(o.alpha / (m * variants)) + normal_upper_quantile(1 - o.power)) * se;
}

// The ladder, the two fitted sizes and their check batches of one (entry, parameter).
InjectedLimit measure_one(const Bootstrap& b, const SearchOptions& o, const InjectionOptions& io, std::size_t e,
                          std::size_t j, double fisher) {
  const Candidate& c = b.pb.catalogue[e];
  const std::size_t v = c.variants() / 2;
  const Eigen::VectorXd mu = b.base(e);
  const Eigen::VectorXd col = b.d.raw_columns(e, v).col(static_cast<Eigen::Index>(j));
  InjectedLimit lim;
  lim.fisher = fisher;
  lim.variant_value = c.scanned() ? c.scan[v] : 0.0;
  std::size_t batch_id = 0;
  auto rung = [&](double m) {
    const auto [nm, dt] = batch(b, mu, col, e, j, batch_id++, m * fisher, io.ladder_injections, io);
    lim.ladder.push_back({m * fisher, io.ladder_injections, nm, dt});
  };
  auto reached = [&](bool named, bool at_least) {
    for (const auto& r : lim.ladder)
      if ((static_cast<double>(named ? r.named : r.detected) / r.n >= o.power) == at_least) return true;
    return false;
  };
  double m_lo = 1, m_hi = 1;
  rung(1);
  while (static_cast<int>(lim.ladder.size()) < io.max_ladder) {
    if (!reached(true, true)) {  // named never at power yet: go up
      if (m_hi * 2 > io.max_multiple) break;
      rung(m_hi *= 2);
    } else if (!reached(false, false)) {  // detected always at power: go down
      rung(m_lo /= 2);
    } else {
      break;
    }
  }
  auto fitted = [&](bool named) {
    InjectedSize s;
    const double a = probit_size(lim.ladder, named, o.power);
    s.size = std::isnan(a) ? INFINITY : a;
    return s;
  };
  // one more rung where the named curve is fitted to cross `power` (two rungs an octave apart
  // leave its slope loose), then the final fits
  if (reached(true, true)) {
    const double a = fitted(true).size;
    bool near = false;
    for (const auto& r : lim.ladder) near = near || std::abs(std::log(a / r.size)) < 0.05;
    if (std::isfinite(a) && !near) rung(a / fisher);
  }
  lim.named = fitted(true);
  lim.detected = fitted(false);
  // The check batches: at the named size, and at the detected size unless within 3 % of it
  // (then the named batch's detections tell it: one batch, both counts). A check whose
  // Clopper-Pearson interval excludes `power` joins the ladder, the curve is refitted and checked
  // again (at most kChecks batches): the size stated is the last one checked.
  constexpr int kChecks = 3;
  auto set = [&](InjectedSize& s, int hits) {
    s.n = io.injections;
    s.hits = hits;
    const Interval ci = clopper_pearson(hits, s.n, io.conf);
    s.lo = ci.lo, s.hi = ci.hi;
  };
  for (int k = 0; k < kChecks && std::isfinite(lim.named.size); ++k) {
    const auto [nm, dt] = batch(b, mu, col, e, j, batch_id++, lim.named.size, io.injections, io);
    set(lim.named, nm);
    const bool same = std::abs(lim.detected.size / lim.named.size - 1) < 0.03;
    if (same) lim.detected.size = lim.named.size, set(lim.detected, dt);
    if ((lim.named.lo <= o.power && o.power <= lim.named.hi) || k + 1 == kChecks) break;
    lim.ladder.push_back({lim.named.size, io.injections, nm, dt});
    lim.named = fitted(true);
    lim.detected = fitted(false);
  }
  const bool detected_done = lim.detected.n > 0 && lim.detected.size == lim.named.size;
  for (int k = 0; k < kChecks && !detected_done && std::isfinite(lim.detected.size); ++k) {
    const auto [nm, dt] = batch(b, mu, col, e, j, batch_id++, lim.detected.size, io.injections, io);
    set(lim.detected, dt);
    if ((lim.detected.lo <= o.power && o.power <= lim.detected.hi) || k + 1 == kChecks) break;
    lim.ladder.push_back({lim.detected.size, io.injections, nm, dt});
    lim.detected.size = fitted(false).size;
  }
  return lim;
}

}  // namespace

std::string unknown_injection_entry(const Problem& pb, const InjectionOptions& io) {
  for (const std::string& s : io.entries) {
    bool known = false;
    for (const Candidate& c : pb.catalogue)
      for (const std::string& p : c.params) known = known || injection_selects({s}, c, p);
    if (!known) return s;
  }
  return "";
}

bool injection_selects(const std::vector<std::string>& entries, const Candidate& c, const std::string& param) {
  if (entries.empty()) return true;
  const std::string key = c.name + "@" + c.scope.label();
  for (const std::string& s : entries)
    for (const std::string& k : {c.name, key})
      if (s == k || s == k + ":" + param) return true;
  return false;
}

InjectedLimits measure_injected_limits(const Problem& pb, const SearchResult& res, const SearchOptions& o,
                                       const InjectionOptions& io) {
  check(io);
  const std::string bad = unknown_injection_entry(pb, io);
  if (!bad.empty()) throw std::invalid_argument("injected limits: no catalogue entry '" + bad + "' (name, name@scope, or either with :param)");
  InjectedLimits out;
  if (io.injections == 0) return out;  // Fisher limits only
  Design d(pb);
  std::vector<NoiseParams> np;
  std::vector<std::vector<char>> skip;
  for (const ChannelNoise& n : res.noise) {
    NoiseParams q = n.fit.params;
    q.p_out = 0, q.s_out2 = 0;
    np.push_back(q);
    skip.push_back(n.fit.outlier);
  }
  if (np.size() != pb.channels.size()) throw std::invalid_argument("injected limits: the result has no noise fit per channel");
  d.set_noise(np, skip);
  SearchOptions inner = o;
  inner.progress = nullptr;  // the searches inside: their own lines would drown the limits'
  inner.injection.injections = 0;
  inner.score_holdout = false;
  inner.threads = 1;  // the injections run at once instead
  inner.noise_memo = nullptr;  // each injection's data are its own: a shared memo would only grow
  Bootstrap b{pb, res, inner, d, {}};
  for (const ChannelNoise& n : res.noise) {
    NoiseParams q = n.fit.params;
    if (!n.outliers_named) q.p_out = 0, q.s_out2 = 0;  // heavy tails only where the report names them
    b.noise.push_back(q);
  }
  // The (entry, parameter, Fisher limit) measured, in catalogue order.
  struct Job {
    std::size_t e, j;
    double fisher;
  };
  std::vector<Job> jobs;
  for (std::size_t e = 0; e < pb.catalogue.size(); ++e) {
    const Candidate& c = pb.catalogue[e];
    if (c.scope_only) continue;
    for (std::size_t j = 0; j < c.params.size(); ++j) {
      if (!injection_selects(io.entries, c, c.params[j])) continue;
      const double fisher = fisher_limit(d, o, res.family_size, e, c.variants() / 2, j);
      if (!std::isfinite(fisher) || !(fisher > 0)) continue;  // inside the nuisance: no size is ever seen
      jobs.push_back({e, j, fisher});
    }
  }
  // Progress: a line before the first parameter, and one per parameter with the time left at
  // the mean time per parameter so far (the lines go to the caller; no result depends on them).
  const ProgressClock clock(std::max<std::size_t>(jobs.size(), 1));
  if (io.progress && !jobs.empty())
    io.progress(std::to_string(jobs.size()) + " parameter(s) to measure, " + std::to_string(io.ladder_injections) +
                " injections per ladder size and " + std::to_string(io.injections) + " per check");
  for (std::size_t k = 0; k < jobs.size(); ++k) {
    const Job& jb = jobs[k];
    const Candidate& c = pb.catalogue[jb.e];
    InjectedLimit& L = out[c.name + "@" + c.scope.label()][c.params[jb.j]];
    L = measure_one(b, o, io, jb.e, jb.j, jb.fisher);
    if (io.progress) {
      char head[128];
      std::snprintf(head, sizeof head, "%zu of %zu, %.0f s, about %.0f s left: ", k + 1, jobs.size(), clock.spent_s(),
                    clock.left_s(k + 1));
      io.progress(head + c.name + "@" + c.scope.label() + " " + c.params[jb.j] + ": named at " + short_num(L.named.size) +
                  " (" + std::to_string(L.named.hits) + "/" + std::to_string(L.named.n) + "), detected at " +
                  short_num(L.detected.size) + " (" + std::to_string(L.detected.hits) + "/" + std::to_string(L.detected.n) +
                  "), Fisher " + short_num(L.fisher));
    }
  }
  return out;
}

}  // namespace rnav
