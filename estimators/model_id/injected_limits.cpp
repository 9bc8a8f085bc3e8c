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
#include <memory>
#include <mutex>
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
  InjectionHit run(const Eigen::VectorXd& mu, const Eigen::VectorXd& col, std::size_t e, double a,
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

// What a batch of injections has given so far: injections run, named, detected.
struct Count {
  int run = 0, named = 0, detected = 0;
};

// Run injections 0, 1, ... of a batch of at most n at size a, `threads` at a time, until
// settled(count) says no further injection can change what the batch is run for. The count is
// taken in index order and cut at the first injection after which it is settled, so it is the
// same whatever the number of threads (a round's later injections are then dropped unread).
template <class Settled>
Count batch(const InjectionDraw& draw, std::size_t batch_id, double a, int n, int threads, Settled settled) {
  std::vector<InjectionHit> out(static_cast<std::size_t>(n));
  Count c;
  for (int first = 0; first < n; first += threads) {
    const int m = std::min(threads, n - first);
    parallel_for(static_cast<std::size_t>(m), threads, [&](std::size_t k) {
      const int i = first + static_cast<int>(k);
      out[static_cast<std::size_t>(i)] = draw(a, batch_id, i);
    });
    for (int i = first; i < first + m; ++i) {
      const InjectionHit& h = out[static_cast<std::size_t>(i)];
      ++c.run, c.named += h.named, c.detected += h.detected;
      if (settled(c)) return c;
    }
  }
  return c;
}

// The verdict "hit rate >= power" of `hits` of n injections: the one rule the rungs stop on, the
// ladder climbs on and the probit's starting bracket reads.
bool at_power(int hits, int n, double power) { return static_cast<double>(hits) / n >= power; }
bool at_power(const InjectedLimit::Rung& r, bool named, double power) {
  return at_power(named ? r.named : r.detected, r.n, power);
}

// A ladder rung's verdicts, at_power for the named and for the detected count, are settled once
// the hits reach `need` (the fewest of n at power) or the misses exceed n minus that: the rate of
// the injections run then gives the verdict all n would give.
struct RungRule {
  int n, need;
  RungRule(int n_, double power) : n(n_), need(n_ + 1) {
    for (int h = n; h >= 0 && at_power(h, n, power); --h) need = h;
  }
  bool settled(int run, int hits) const { return hits >= need || run - hits > n - need; }
};

// A check batch of n is run for one verdict: does the Clopper-Pearson interval of its hits
// contain `power`? The counts whose interval does form a set `in`; the verdict is settled once
// every count the rest of the batch can still give is in it, or none is (the same verdict as the
// whole batch, from fewer injections).
struct CheckRule {
  int n;
  std::vector<char> in;  // in[h]: the interval of h of n contains power
  CheckRule(int n_, double power, double conf) : n(n_), in(static_cast<std::size_t>(n_) + 1) {
    for (int h = 0; h <= n; ++h) {
      const Interval ci = clopper_pearson(h, n, conf);
      in[static_cast<std::size_t>(h)] = ci.lo <= power && power <= ci.hi;
    }
  }
  // 1: every final count reachable from (run, hits) is in; 0: none is; -1: not settled
  int verdict(int run, int hits) const {
    bool any = false, all = true;
    for (int h = hits; h <= hits + n - run; ++h) any = any || in[static_cast<std::size_t>(h)], all = all && in[static_cast<std::size_t>(h)];
    return all ? 1 : !any ? 0 : -1;
  }
};

// The probit slope's prior (probit_log_crossing says why): mean and SD.
constexpr double kSlopePrior = 4.8, kSlopePriorSd = 2;

// The size hit with probability p by the probit P(hit | a) = Phi(b0 + b1 log a) fitted to the
// ladder by penalised maximum likelihood (Fisher scoring). A few rungs of ten leave the slope
// loose (one rung at 7/10 and one at 10/10 make it any steepness), so b1 carries a weak normal
// prior: a test that detects a with standard error SE has P = Phi(a / SE - z_crit), whose slope
// in log a at the crossing is a / SE = z_crit + z_p, about 4.8 here; prior N(4.8, 2^2), and
// b1 >= 0.5. Returns log a at the crossing, unclamped; when no rung reached p, extrapolated
// (the prior's slope carries it beyond the largest size: where the next rung should go).
double probit_log_crossing(const std::vector<InjectedLimit::Rung>& ladder, bool named, double p) {
  double x_hit = INFINITY, x_miss = -INFINITY;
  for (const auto& r : ladder) {
    if (at_power(r, named, p)) x_hit = std::min(x_hit, std::log(r.size));
    else x_miss = std::max(x_miss, std::log(r.size));
  }
  const double zp = normal_upper_quantile(1 - p);
  // start: the crossing between the two nearest rungs, at the lowest hit, or an octave above
  // the highest miss
  const double x0 = std::isfinite(x_hit) ? (std::isfinite(x_miss) ? 0.5 * (x_hit + x_miss) : x_hit) : x_miss + std::log(2.0);
  double b1 = 4, b0 = zp - b1 * x0;
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
  return (zp - b0) / b1;
}

// The size hit with probability p (probit_log_crossing), never beyond the ladder's evidence:
// within a factor 2 of the sizes tried. NaN when the ladder never reached p.
double probit_size(const std::vector<InjectedLimit::Rung>& ladder, bool named, double p) {
  bool reached = false;
  for (const auto& r : ladder) reached = reached || at_power(r, named, p);
  if (!reached) return std::numeric_limits<double>::quiet_NaN();
  double x = probit_log_crossing(ladder, named, p);
  double lo = INFINITY, hi = -INFINITY;
  for (const auto& r : ladder) lo = std::min(lo, std::log(r.size)), hi = std::max(hi, std::log(r.size));
  x = std::clamp(x, lo - std::log(2.0), hi + std::log(2.0));
  return std::exp(x);
}

// The catalogue's columns are the same in every injected search (only y changes): computed once
// here, each search's entries read them instead of computing them again (the columns were a
// tenth of an injected landing search). Only while they take at most kKeptColumnsBytes: a
// multi-sensor catalogue of per-target entries over 10^5 detections computes them as before.
constexpr std::size_t kKeptColumnsBytes = std::size_t{256} << 20;

Problem with_columns_kept(const Problem& pb, const Design& d) {
  std::size_t bytes = 0;
  for (const Candidate& c : pb.catalogue) bytes += c.variants() * pb.size() * c.params.size() * sizeof(double);
  if (bytes > kKeptColumnsBytes) return pb;
  Problem q = pb;
  for (std::size_t e = 0; e < pb.catalogue.size(); ++e) {
    auto kept = std::make_shared<KeptColumns>();
    for (std::size_t v = 0; v < pb.catalogue[e].variants(); ++v) {
      kept->columns.push_back(d.raw_columns(e, v));  // checked
      kept->touches.push_back(d.touches(kept->columns.back()));
    }
    q.catalogue[e].columns = [kept](std::size_t v) { return kept->columns.at(v); };
    q.catalogue[e].kept_columns = kept;
  }
  return q;
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

// The ladder's steps: the first step up (or down) goes where the probit (with its prior slope)
// puts the crossing, at least kMinStep and at most kMaxStep times beyond the sizes tried
// (doubling at once spent a rung of 10 at twice a size named in 7 of 10, whose crossing lies
// near 1.2x); a further step in the same direction means the curve is flatter than the prior
// says (a rival named instead at a plateau of 70 %), and doubles.
constexpr double kMinStep = 1.25, kMaxStep = 2.0;
// A fitted size within this of a rung in log needs no rung of its own before its check: a
// little over half the smallest step (log 1.25 / 2 = 0.112), so a crossing between two rungs a
// step apart is checked at once, and one inside a wider bracket gets its rung first.
constexpr double kNearRung = 0.12;
// The top of the band a stated size's rate should lie in (80-97 %, docs/diagnosis.md): a
// detection limit is stated at the naming limit where the detected rate there stays below it.
constexpr double kBandHi = 0.97;

}  // namespace

InjectedLimit measure_ladder(const InjectionDraw& draw, double fisher, double power, const InjectionOptions& io) {
  check(io);
  if (!(fisher > 0) || !std::isfinite(fisher)) throw std::invalid_argument("injected limits: the Fisher limit must be finite and > 0");
  if (!(power > 0 && power < 1)) throw std::invalid_argument("injected limits: power must be in (0, 1)");
  if (io.injections < 1) throw std::invalid_argument("injected limits: a ladder needs injections >= 1 per check");
  InjectedLimit lim;
  lim.fisher = fisher;
  std::size_t batch_id = 0;
  // a rung at size a: run until both its verdicts (named, detected rate >= power) are settled
  const RungRule rr(io.ladder_injections, power);
  auto rung = [&](double a) {
    const Count k = batch(draw, batch_id++, a, io.ladder_injections, io.threads,
                          [&](const Count& n) { return rr.settled(n.run, n.named) && rr.settled(n.run, n.detected); });
    lim.ladder.push_back({a, k.run, k.named, k.detected});
  };
  auto reached = [&](bool named, bool at_least) {
    for (const auto& r : lim.ladder)
      if (at_power(r, named, power) == at_least) return true;
    return false;
  };
  const double a_max = io.max_multiple * fisher;
  rung(fisher);
  int ups = 0, downs = 0;
  while (static_cast<int>(lim.ladder.size()) < io.max_ladder) {
    double lo = INFINITY, hi = 0;
    for (const auto& r : lim.ladder) lo = std::min(lo, r.size), hi = std::max(hi, r.size);
    if (!reached(true, true)) {  // named never at power yet: go up
      if (hi >= a_max) break;
      const double a = ups++ > 0 ? kMaxStep * hi
                                 : std::clamp(std::exp(probit_log_crossing(lim.ladder, true, power)), kMinStep * hi, kMaxStep * hi);
      rung(std::min(a_max, a));
    } else if (!reached(false, false)) {  // detected always at power: go down
      rung(downs++ > 0 ? lo / kMaxStep
                       : std::clamp(std::exp(probit_log_crossing(lim.ladder, false, power)), lo / kMaxStep, lo / kMinStep));
    } else {
      break;
    }
  }
  auto fitted = [&](bool named) {
    InjectedSize s;
    const double a = probit_size(lim.ladder, named, power);
    s.size = std::isnan(a) ? INFINITY : a;
    return s;
  };
  // one more rung where the named curve is fitted to cross `power` unless a rung is near it
  // (two rungs far apart leave its slope loose), then the final fits
  if (reached(true, true)) {
    const double a = fitted(true).size;
    bool near = false;
    for (const auto& r : lim.ladder) near = near || std::abs(std::log(a / r.size)) < kNearRung;
    if (std::isfinite(a) && !near) rung(a);
  }
  lim.named = fitted(true);
  lim.detected = fitted(false);
  // The check batches: at the named size, and at the detected size unless that is stated at
  // the named size (same_ratio below: then the named batch's detections tell it, one batch,
  // both counts). A batch stops once its
  // verdict - does the Clopper-Pearson interval of all `injections` contain `power`? - is
  // settled (CheckRule), and states the injections run, their hits and their interval. A check
  // whose verdict is "no" joins the ladder, the curve is refitted and checked again (at most
  // kChecks batches): the size stated is the last one checked.
  constexpr int kChecks = 3;
  const CheckRule cr(io.injections, power, io.conf);
  auto set = [&](InjectedSize& s, int run, int hits) {
    s.n = run;
    s.hits = hits;
    const Interval ci = clopper_pearson(hits, run, io.conf);
    s.lo = ci.lo, s.hi = ci.hi;
  };
  // A detection limit fitted above the naming limit, or below it by less than same_ratio, is
  // stated at the naming limit and checked by its batch: every injection named is detected, so
  // the detected rate there is at least the named one, and at most kBandHi where the curves'
  // slope is the prior's: log(a_named / a_detected) <= (z_kBandHi - z_power) / kSlopePrior.
  const double same_ratio = std::exp(-(normal_upper_quantile(1 - kBandHi) - normal_upper_quantile(1 - power)) / kSlopePrior);
  for (int k = 0; k < kChecks && std::isfinite(lim.named.size); ++k) {
    const bool same = !(lim.detected.size < same_ratio * lim.named.size);
    const Count n = batch(draw, batch_id++, lim.named.size, io.injections, io.threads, [&](const Count& m) {
      return cr.verdict(m.run, m.named) >= 0 && (!same || cr.verdict(m.run, m.detected) >= 0);
    });
    set(lim.named, n.run, n.named);
    if (same) lim.detected.size = lim.named.size, set(lim.detected, n.run, n.detected);
    if (cr.verdict(n.run, n.named) == 1 || k + 1 == kChecks) break;
    lim.ladder.push_back({lim.named.size, n.run, n.named, n.detected});
    lim.named = fitted(true);
    lim.detected = fitted(false);
  }
  const bool detected_done = lim.detected.n > 0 && lim.detected.size == lim.named.size;
  for (int k = 0; k < kChecks && !detected_done && std::isfinite(lim.detected.size); ++k) {
    const Count n = batch(draw, batch_id++, lim.detected.size, io.injections, io.threads,
                          [&](const Count& m) { return cr.verdict(m.run, m.detected) >= 0; });
    set(lim.detected, n.run, n.detected);
    if (cr.verdict(n.run, n.detected) == 1 || k + 1 == kChecks) break;
    lim.ladder.push_back({lim.detected.size, n.run, n.named, n.detected});
    // (never above the naming limit: every injection named there is detected)
    lim.detected.size = std::min(fitted(false).size, lim.named.size);
  }
  return lim;
}

namespace {

// The ladder of one (entry, parameter): its injections into the bootstrap's data.
InjectedLimit measure_one(const Bootstrap& b, const SearchOptions& o, const InjectionOptions& io, std::size_t e,
                          std::size_t j, double fisher) {
  const Candidate& c = b.pb.catalogue[e];
  const std::size_t v = c.variants() / 2;
  const Eigen::VectorXd mu = b.base(e);
  const Eigen::VectorXd col = b.d.raw_columns(e, v).col(static_cast<Eigen::Index>(j));
  const InjectionDraw draw = [&](double a, std::size_t batch_id, int i) {
    return b.run(mu, col, e, a, stream_seed(io.seed, e, j, batch_id, i));
  };
  InjectedLimit lim = measure_ladder(draw, fisher, o.power, io);
  lim.variant_value = c.scanned() ? c.scan[v] : 0.0;
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
  inner.effects_only = true;  // the verdict reads the named effects and their confounding alone
  inner.noise.se_tau = false;  // nor the noise fits' SE of tau
  inner.threads = 1;  // the injections run at once instead
  inner.noise_memo = nullptr;  // each injection's data are its own: a shared memo would only grow
  const Problem fixed_columns = with_columns_kept(pb, d);
  Bootstrap b{fixed_columns, res, inner, d, {}};
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
  // The parameters are measured at once, one per thread, each with its batches run one
  // injection at a time; with fewer parameters than threads, the threads are shared among a
  // parameter's injections instead. Why: with two threads on one parameter, every round of two
  // waited for the slower search, and a batch settled after an odd count dropped the other
  // injection of its round unread (the cores were 93 % busy on the 500-plot landing flight).
  // What each parameter gets is the same either way: every injection draws from its own stream
  // and a batch's count is cut in index order (batch).
  const int per_job = std::max(1, io.threads / static_cast<int>(std::max<std::size_t>(jobs.size(), 1)));
  InjectionOptions one = io;
  one.threads = per_job;
  // Progress: a line before the first parameter, and one per parameter as it is done with the
  // time left at the mean time per parameter so far (the lines go to the caller, one at a time;
  // no result depends on them).
  const ProgressClock clock(std::max<std::size_t>(jobs.size(), 1));
  if (io.progress && !jobs.empty())
    io.progress(std::to_string(jobs.size()) + " parameter(s) to measure, " + std::to_string(io.ladder_injections) +
                " injections per ladder size and " + std::to_string(io.injections) + " per check");
  std::vector<InjectedLimit> found(jobs.size());
  std::mutex progress_m;
  std::size_t done = 0;
  parallel_for(jobs.size(), std::max(1, io.threads / per_job), [&](std::size_t k) {
    const Job& jb = jobs[k];
    const Candidate& c = pb.catalogue[jb.e];
    const InjectedLimit& L = found[k] = measure_one(b, o, one, jb.e, jb.j, jb.fisher);
    if (!io.progress) return;
    const std::lock_guard<std::mutex> lock(progress_m);
    ++done;
    char head[128];
    std::snprintf(head, sizeof head, "%zu of %zu, %.0f s, about %.0f s left: ", done, jobs.size(), clock.spent_s(),
                  clock.left_s(done));
    io.progress(head + c.name + "@" + c.scope.label() + " " + c.params[jb.j] + ": named at " + short_num(L.named.size) +
                " (" + std::to_string(L.named.hits) + "/" + std::to_string(L.named.n) + "), detected at " +
                short_num(L.detected.size) + " (" + std::to_string(L.detected.hits) + "/" + std::to_string(L.detected.n) +
                "), Fisher " + short_num(L.fisher));
  });
  for (std::size_t k = 0; k < jobs.size(); ++k) {
    const Candidate& c = pb.catalogue[jobs[k].e];
    out[c.name + "@" + c.scope.label()][c.params[jobs[k].j]] = found[k];
  }
  return out;
}

}  // namespace rnav
