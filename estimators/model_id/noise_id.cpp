#include "estimators/model_id/noise_id.hpp"

#include "estimators/model_id/box_ascent.hpp"
#include "estimators/model_id/byte_hash.hpp"
#include "estimators/model_id/gram_memo.hpp"
#include "estimators/model_id/generation_store.hpp"
#include "estimators/model_id/stats.hpp"

#include <algorithm>
#include <cmath>
#include <iterator>
#include <list>
#include <stdexcept>
#include <string>
#include <unordered_map>

namespace rnav {

namespace {

struct Reml {
  double ll = -INFINITY;
  double s2 = 1;
  double ml = -INFINITY;  ///< the ordinary (ML) log-likelihood at these noise parameters, s^2 profiled
  double dof = 0;         ///< n - rank(X): the residual degrees of freedom of s^2
};

// The frames of one channel and what stays fixed while the noise model is searched.
struct Series {
  const std::vector<double>& t;
  const std::vector<double>& h;  ///< nominal component's gains (empty: 1)
  const Eigen::MatrixXd& Xe;     ///< [X | e]
  double tau0;                   ///< the nominal component's correlation time
  std::pair<std::uint64_t, std::uint64_t> key = frames_key(t, h);  ///< ByteHash of the frames (t, h)
  mutable std::vector<GramMemo::Key> col_keys = {};  ///< GramMemo::column_key of Xe's columns, once asked for

  static std::pair<std::uint64_t, std::uint64_t> frames_key(const std::vector<double>& t, const std::vector<double>& h) {
    ByteHash k;
    k.value(t.size()), k.value(h.size());
    k.bytes(t.data(), t.size() * sizeof(double));
    k.bytes(h.data(), h.size() * sizeof(double));
    return k.key();
  }
};

// The noise model (lambda, tau, mu) of a series, s^2 = 1.
NoiseParams model_of(const Series& sr, double mu, double lambda, double tau) {
  NoiseParams p;
  p.lambda = lambda;
  p.tau_s = tau;
  p.nom_share = mu;
  p.nom_tau_s = sr.tau0;
  return p;
}

// The REML and ML log-likelihoods, s^2 profiled, from the residual sum of squares of the
// whitened e on the whitened X (rank columns), log|X~' X~| over them, sum log S_i and n frames.
Reml reml_of(double rss, double logdet, Eigen::Index rank, double sum_logS, double n) {
  const double nprime = n - static_cast<double>(rank);
  if (nprime < 5) return {};
  if (!(rss > 0)) return {};
  Reml out;
  out.s2 = rss / nprime;
  out.dof = nprime;
  out.ll = -0.5 * (nprime * std::log(out.s2) + sum_logS + logdet + nprime * (1 + std::log(2 * M_PI)));
  out.ml = -0.5 * (n * std::log(rss / n) + sum_logS + n * (1 + std::log(2 * M_PI)));
  return out;
}

// The frames kept.
double frames_used(const Series& sr, const std::vector<char>& skip) {
  double n = 0;
  for (std::size_t i = 0; i < sr.t.size(); ++i) n += skip.empty() || !skip[i];
  return n;
}

// REML from [X | e] whitened (W) with s^2 = 1 and its sum of log S_i, through a rank-revealing QR
// (the rank: R's diagonal above 1e-10 of its largest).
Reml reml_whitened(const Series& sr, const Eigen::MatrixXd& W, double sum_logS, const std::vector<char>& skip) {
  const Eigen::Index k = W.cols() - 1;
  const auto X = W.leftCols(k);
  const auto e = W.col(k);
  Eigen::Index rank = 0;
  Eigen::VectorXd r = e;
  double logdet = 0;  // log|X~' X~| over the rank-revealing R's diagonal
  if (k > 0) {        // (Eigen's QR of an n x 0 matrix is not defined)
    Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(X.rows(), X.cols());
    qr.setThreshold(1e-10);
    qr.compute(X);
    rank = qr.rank();
    r = e - X * qr.solve(e);
    for (Eigen::Index j = 0; j < rank; ++j) logdet += 2 * std::log(std::abs(qr.matrixR()(j, j)));
  }
  return reml_of(r.squaredNorm(), logdet, rank, sum_logS, frames_used(sr, skip));
}

// The Gram matrix's conditioning below which reml_gram leaves the model to the QR: a pivot of
// the equilibrated X~' X~ under 1e-8 (a column within 1e-4 of the others' span: the Gram's
// rounding, about n eps, is then no longer far below it) or a residual under 1e-6 of e~'s
// squared norm (the subtraction would cost six of the sixteen digits).
constexpr double kGramPivot = 1e-8, kGramResidual = 1e-6;

// REML from the Gram matrix G = W' W of [X | e] whitened (s^2 = 1): X~' X~ equilibrated and
// Cholesky factored, L L'; log|X~' X~| = 2 sum log L_jj + 2 sum log ||x~_j||, and
// RSS = e~' e~ - |L^-1 X~' e~|^2 (the Schur complement). Returns false when G is too close to
// singular for these digits (kGramPivot, kGramResidual): the caller then takes the QR.
// (Mat, Vec: the matrix types of its factorisation; up to kSmallGram columns on the stack, a
// call per model of every grid point and refinement step allocating nothing)
template <class Mat, class Vec>
bool reml_gram_as(const Eigen::MatrixXd& G, double sum_logS, double n, Reml& out) {
  const Eigen::Index k = G.rows() - 1;
  const double ee = G(k, k);
  if (!(ee > 0)) return false;
  double logdet = 0, rss = ee;
  if (k > 0) {
    Vec d(k);
    for (Eigen::Index j = 0; j < k; ++j) {
      if (!(G(j, j) > 0)) return false;  // a column all zero once whitened (its frames kept out)
      d(j) = 1 / std::sqrt(G(j, j));
    }
    const Mat A = d.asDiagonal() * G.topLeftCorner(k, k) * d.asDiagonal();
    const Eigen::LLT<Mat> llt(A);
    if (llt.info() != Eigen::Success) return false;
    const auto L = llt.matrixL();
    for (Eigen::Index j = 0; j < k; ++j) {
      const double Ljj = llt.matrixLLT()(j, j);
      if (!(Ljj * Ljj > kGramPivot)) return false;
      logdet += 2 * std::log(Ljj) - 2 * std::log(d(j));
    }
    const Vec z = L.solve(d.asDiagonal() * G.topRightCorner(k, 1));
    rss = ee - z.squaredNorm();
    if (!(rss > kGramResidual * ee)) return false;
  }
  out = reml_of(rss, logdet, k, sum_logS, n);
  return true;
}

constexpr int kSmallGram = 16;

bool reml_gram(const Eigen::MatrixXd& G, double sum_logS, double n, Reml& out) {
  using SmallMat = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kSmallGram, kSmallGram>;
  using SmallVec = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kSmallGram, 1>;
  if (G.rows() - 1 <= kSmallGram) return reml_gram_as<SmallMat, SmallVec>(G, sum_logS, n, out);
  return reml_gram_as<Eigen::MatrixXd, Eigen::VectorXd>(G, sum_logS, n, out);
}

// REML log-likelihood under each model of a gain table with s^2 profiled: from the Gram
// matrices of [X | e] whitened under them (grams[j] under model j), a model too close to
// singular for them from its whitened matrix's QR.
std::vector<Reml> reml_from_grams(const Series& sr, const GainTable& table, const std::vector<Eigen::MatrixXd>& grams,
                                  const std::vector<char>& skip) {
  const double n = frames_used(sr, skip);
  std::vector<Reml> out(table.models.size());
  for (std::size_t j = 0; j < out.size(); ++j) {
    if (reml_gram(grams[j], table.sum_logS[j], n, out[j])) continue;
    Eigen::MatrixXd W = sr.Xe;
    whiten(table, j, W);  // the table's gains: whiten()'s values without computing them again
    out[j] = reml_whitened(sr, W, table.sum_logS[j], skip);
  }
  return out;
}

// reml_from_grams with the Gram matrices computed (whitened_grams).
std::vector<Reml> reml_table(const Series& sr, const GainTable& table, const std::vector<char>& skip) {
  thread_local std::vector<Eigen::MatrixXd> grams;  // kept per thread between calls (whiten_batch says why)
  whitened_grams(table, sr.Xe, grams);
  return reml_from_grams(sr, table, grams, skip);
}

// The models of the shares lambdas at one tau (and the nominal component's share mu), s^2 = 1.
std::vector<NoiseParams> shares(const Series& sr, double mu, const double* lambdas, std::size_t count, double tau) {
  std::vector<NoiseParams> ps;
  for (std::size_t j = 0; j < count; ++j) ps.push_back(model_of(sr, mu, lambdas[j], tau));
  return ps;
}

// REML log-likelihood at each of the shares lambdas at one tau with s^2 profiled, the models'
// gains computed afresh (a refinement's models, never asked for twice).
std::vector<Reml> reml_shares(const Series& sr, double mu, const double* lambdas, std::size_t count, double tau,
                              const std::vector<char>& skip) {
  thread_local GainTable table;  // kept per thread between calls
  innovation_gains(sr.t, sr.h, shares(sr, mu, lambdas, count, tau), skip, table);
  return reml_table(sr, table, skip);
}

// The gain tables of the models every identification of a series evaluates (the grid's, the
// null's, white's), kept per thread: they depend on the frame times, h, the frames kept out and
// the models alone, and one diagnosis identifies the noise of the same few series thousands of
// times (each candidate's columns, each injection's residuals) - their first pass was half of
// an injected search's time. Keyed by ByteHash of all they depend on; once the tables exceed
// kGainCacheBytes, those not used for two generations go (GenerationStore). A pure function's
// values: what is computed is the same whether a table was kept or not.
class GainCache {
 public:
  using Key = GenerationStore<GainTable>::Key;
  /// The gains of models ps on the series, frames skip kept out, and their key.
  std::pair<Key, const GainTable*> get(const Series& sr, const std::vector<NoiseParams>& ps, const std::vector<char>& skip) {
    ByteHash k;
    k.value(sr.key), k.value(skip.size());
    k.bytes(skip.data(), skip.size());
    k.value(ps.size());
    for (const NoiseParams& p : ps) k.value(p.s2), k.value(p.lambda), k.value(p.tau_s), k.value(p.nom_share), k.value(p.nom_tau_s);
    const Key key = k.key();
    if (const GainTable* kept = kept_.find(key)) return {key, kept};
    // (those not used lately go a generation at a time: a linear scan for the oldest was a
    // fifteenth of a pooled multi-sensor diagnosis, whose many series churn)
    GainTable table;
    innovation_gains(sr.t, sr.h, ps, skip, table);
    if (ps.size() > 1) pack_gains(table);  // (kept tables whiten columns under all their models at once)
    const std::size_t bytes = table.bytes();
    return {key, &kept_.insert(key, std::move(table), bytes)};
  }

 private:
  // per thread: a landing flight's three channels of 500 frames take about 20 MB, a 2 000-bearing
  // flight about 25 MB
  static constexpr std::size_t kGainCacheBytes = std::size_t{128} << 20;
  GenerationStore<GainTable> kept_{kGainCacheBytes};
};

// The gain tables kept for this thread.
GainCache& gain_cache() {
  thread_local GainCache cache;
  return cache;
}

// per thread: the whitened columns and as much for the entries and again for the grids'
// entries (a landing search's three channels of 500 frames under the grid touch about 3 000
// columns of 28 kB)
GramMemo& gram_memo() {
  thread_local GramMemo memo(std::size_t{96} << 20);
  return memo;
}

// Xe's column keys (GramMemo::column_key), computed once per series.
const std::vector<GramMemo::Key>& column_keys(const Series& sr) {
  if (sr.col_keys.empty())
    for (Eigen::Index c = 0; c < sr.Xe.cols(); ++c) sr.col_keys.push_back(GramMemo::column_key(sr.Xe, c));
  return sr.col_keys;
}

// reml_shares for models every identification evaluates (GainCache).
// Their whitened Gram matrices from the entries remembered per pair of columns (GramMemo): the
// same values, bit for bit.
std::vector<Reml> reml_kept(const Series& sr, double mu, const double* lambdas, std::size_t count, double tau,
                            const std::vector<char>& skip) {
  const auto [key, table] = gain_cache().get(sr, shares(sr, mu, lambdas, count, tau), skip);
  if (!GramMemo::serves(*table, sr.Xe)) return reml_table(sr, *table, skip);
  thread_local std::vector<Eigen::MatrixXd> grams;
  gram_memo().grams(*table, key, sr.Xe, column_keys(sr), grams);
  return reml_from_grams(sr, *table, grams, skip);
}

// reml_kept at each of the correlation times taus (the grid's), [i][j] at taus[i] and
// lambdas[j]: the same values bit for bit, the Gram matrices' entries remembered per pair of
// columns for the whole grid (GramMemo::grid_grams: one lookup per pair instead of one per tau).
std::vector<std::vector<Reml>> reml_grid(const Series& sr, double mu, const double* lambdas, std::size_t count,
                                         const std::vector<double>& taus, const std::vector<char>& skip) {
  std::vector<std::vector<Reml>> out;
  const Eigen::Index K = sr.Xe.cols();
  if (count > GramMemo::kMaxModels || K < 1 || K > GramMemo::kMaxColumns || sr.Xe.rows() < GramMemo::kMinFrames) {
    for (double tau : taus) out.push_back(reml_kept(sr, mu, lambdas, count, tau, skip));
    return out;
  }
  // the grid's key: everything its tables depend on
  ByteHash k;
  k.value(sr.key), k.value(skip.size());
  k.bytes(skip.data(), skip.size());
  k.value(mu), k.value(sr.tau0), k.value(count);
  k.bytes(lambdas, count * sizeof(double));
  k.value(taus.size());
  k.bytes(taus.data(), taus.size() * sizeof(double));
  auto table_of = [&](std::size_t i) { return gain_cache().get(sr, shares(sr, mu, lambdas, count, taus[i]), skip); };
  thread_local std::vector<std::vector<Eigen::MatrixXd>> grams;
  gram_memo().grid_grams(taus.size(), table_of, k.key(), sr.Xe, column_keys(sr), grams);
  for (std::size_t i = 0; i < taus.size(); ++i) out.push_back(reml_from_grams(sr, *table_of(i).second, grams[i], skip));
  return out;
}

// The null model of share mu (no further Gauss-Markov part; mu = 0: white), its gains kept.
Reml reml_null(const Series& sr, double mu, const std::vector<char>& skip) {
  const double lambda = 0;
  return reml_kept(sr, mu, &lambda, 1, 1.0, skip)[0];
}

// reml_shares at one share lambda.
Reml reml(const Series& sr, double mu, double lambda, double tau, const std::vector<char>& skip) {
  return reml_shares(sr, mu, &lambda, 1, tau, skip)[0];
}

// REML at each model (lambda_k, tau_k), their gains computed afresh in one pass (the
// recursions interleaved: a batch of six costs little more than one model's).
std::vector<Reml> reml_points(const Series& sr, double mu, const std::vector<std::pair<double, double>>& lambda_tau,
                              const std::vector<char>& skip) {
  thread_local GainTable table;  // kept per thread between calls
  std::vector<NoiseParams> ps;
  for (const auto& [lambda, tau] : lambda_tau) ps.push_back(model_of(sr, mu, lambda, tau));
  innovation_gains(sr.t, sr.h, ps, skip, table);
  return reml_table(sr, table, skip);
}

// The refinement's resolution, in log tau (0.1 % of tau) and in logit lambda: the trust-region
// ascent stops once a step is under it, the line searches (where the ascent meets a model
// leaving no spread) once their bracket is narrower. Fixed iteration counts (30 and 40) used to
// narrow the line searches' brackets to 1e-7 and 1e-8: twice the REML evaluations, for maxima
// whose log-likelihood then differed by less than the decisions' rounding.
constexpr double kRefineWidth = 1e-3;

// Brent's maximum of f on [a, b] (Brent 1973, ch. 5: parabolic interpolation through the three
// best points, a golden-section step whenever the parabola's step is not safely inside the
// bracket or not shrinking), stopped once x lies within `width` / 2 of the middle of a bracket at
// most `width` wide. A log-likelihood is smooth near its maximum: the parabola converges in a
// few evaluations where golden section took one per factor 0.618 of the bracket (15 for log tau,
// 21 for logit lambda; a noise identification's refinement was half its time). A non-finite
// value (a model leaving no spread) only ever gets golden steps.
template <class F>
double brent_max(F f, double a, double b, double width) {
  const double c = 0.5 * (3 - std::sqrt(5.0));  // the golden section's smaller part
  const double tol = width / 4;                  // |x - xm| <= 2 tol - (b - a) / 2 leaves b - a <= 4 tol
  double x = a + c * (b - a), w = x, v = x;
  double fx = f(x), fw = fx, fv = fx;
  double d = 0, e = 0;  // the last step, and the one before it
  for (int it = 0; it < 100; ++it) {
    const double xm = 0.5 * (a + b);
    if (std::abs(x - xm) <= 2 * tol - 0.5 * (b - a)) break;
    bool golden = true;
    if (std::abs(e) > tol && std::isfinite(fx) && std::isfinite(fw) && std::isfinite(fv)) {
      // the parabola through (x, fx), (w, fw), (v, fv): its vertex at x + p / q
      const double r = (x - w) * (fx - fv);
      double q = (x - v) * (fx - fw);
      double p = (x - v) * q - (x - w) * r;
      q = 2 * (q - r);
      if (q > 0) p = -p;
      q = std::abs(q);
      const double e_before = e;
      e = d;
      // a vertex inside the bracket, by a step under half the step before last
      if (std::abs(p) < std::abs(0.5 * q * e_before) && p > q * (a - x) && p < q * (b - x)) {
        d = p / q;
        const double u = x + d;
        if (u - a < 2 * tol || b - u < 2 * tol) d = xm >= x ? tol : -tol;
        golden = false;
      }
    }
    if (golden) {
      e = x >= xm ? a - x : b - x;
      d = c * e;
    }
    const double u = std::abs(d) >= tol ? x + d : x + (d >= 0 ? tol : -tol);
    const double fu = f(u);
    if (fu >= fx) {  // u the new best: the bracket closes on it
      (u >= x ? a : b) = x;
      v = w, fv = fw, w = x, fw = fx, x = u, fx = fu;
    } else {
      (u < x ? a : b) = u;
      if (fu >= fw || w == x) v = w, fv = fw, w = u, fw = fu;
      else if (fu >= fv || v == x || v == w) v = u, fv = fu;
    }
  }
  return x;
}

// The (lambda, tau) search grid: n_tau log-spaced correlation times by these shares.
constexpr double grid_lambdas[] = {0.3, 0.6, 0.8, 0.9, 0.95, 0.98, 0.995};
constexpr int n_tau = 28;

// The grid's correlation times between exp(ltau_lo) and exp(ltau_hi) [s], the i-th as
// search_lambda_tau computes it.
std::vector<double> grid_taus(double ltau_lo, double ltau_hi) {
  std::vector<double> taus;
  for (int i = 0; i < n_tau; ++i) taus.push_back(std::exp(ltau_lo + (ltau_hi - ltau_lo) * i / (n_tau - 1)));
  return taus;
}

// The searched range of log tau [s] for a series spanning span seconds.
std::pair<double, double> log_tau_range(const NoiseIdOptions& o, double span) {
  const double tau_hi = std::max(o.tau_min_s * 1.0001, std::min(o.tau_max_s, span / o.tau_span_divisor));
  return {std::log(o.tau_min_s), std::log(tau_hi)};
}

// [trend | X | e] with an independent set of fixed-effect columns. Fixed effects: 1,
// (t - tm) / span, ((t - tm) / span)^2 (not in profile_ml mode), then X; and e last.
Eigen::MatrixXd fixed_effects(const std::vector<double>& t, const Eigen::VectorXd& e, const Eigen::MatrixXd& X,
                              const NoiseIdOptions& o) {
  const auto n = static_cast<Eigen::Index>(t.size());
  const double t0 = t.front(), span = std::max(t.back() - t0, 1e-6);
  const double tm = t0 + span / 2;
  const Eigen::Index n_trend = o.profile_ml ? 0 : 3;
  Eigen::MatrixXd Xe(n, n_trend + X.cols() + 1);
  for (Eigen::Index i = 0; i < n && n_trend > 0; ++i) {
    const double u = (t[static_cast<std::size_t>(i)] - tm) / span;
    Xe(i, 0) = 1, Xe(i, 1) = u, Xe(i, 2) = u * u;
  }
  if (X.cols() > 0) Xe.middleCols(n_trend, X.cols()) = X;
  Xe.col(Xe.cols() - 1) = e;
  if (Xe.cols() > 1) {
    // Keep an independent set of fixed-effect columns, decided once on the unit-norm columns:
    // a rank decided per (lambda, tau) would make log|X~' X~| jump between models (e.g. a
    // caller's constant next to the trend's).
    const Eigen::Index k = Xe.cols() - 1;
    Eigen::MatrixXd U = Xe.leftCols(k);
    for (Eigen::Index j = 0; j < k; ++j)
      if (U.col(j).norm() > 0) U.col(j).normalize();
    Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(U);
    qr.setThreshold(1e-8);
    if (qr.rank() < k) {
      std::vector<Eigen::Index> keep;
      for (Eigen::Index j = 0; j < qr.rank(); ++j) keep.push_back(qr.colsPermutation().indices()(j));
      std::sort(keep.begin(), keep.end());
      Eigen::MatrixXd R(n, static_cast<Eigen::Index>(keep.size()) + 1);
      for (std::size_t j = 0; j < keep.size(); ++j) R.col(static_cast<Eigen::Index>(j)) = Xe.col(keep[j]);
      R.col(R.cols() - 1) = e;
      Xe = R;
    }
  }
  return Xe;
}

// The input checks identify_noise and noise_confidence_set share; `who` names the caller.
void check_series(const char* who, const std::vector<double>& t, const std::vector<double>& h, const Eigen::VectorXd& e,
                  const Eigen::MatrixXd& X, const NoiseIdOptions& o, const std::vector<char>* skip) {
  const auto n = static_cast<Eigen::Index>(t.size());
  const std::string w = who;
  if (e.size() != n || (X.size() > 0 && X.rows() != n) || (!h.empty() && h.size() != t.size()))
    throw std::invalid_argument(w + ": sizes differ");
  if (skip && !skip->empty() && skip->size() != t.size()) throw std::invalid_argument(w + ": skip mask of the wrong size");
  if (!(o.nominal_share >= 0 && o.nominal_share < 1) || (o.nominal_share > 0 && !(o.nominal_tau_s > 0)))
    throw std::invalid_argument(w + ": nominal share must be in [0, 1) and its tau > 0");
  if (n < 10) throw std::invalid_argument(w + ": fewer than 10 frames");
}

// The refinement's box in logit lambda: lambda in [0.01, 0.999].
constexpr double kLambdaLo = 0.01, kLambdaHi = 0.999;
// The refinement stops where a step promises a rise in log-likelihood under this: a test's
// 2 log LR moves by under 2e-5, where the decisions' thresholds are units. Where the data
// cannot tell a share or a tau (a flat likelihood) the ascent otherwise climbs by 1e-9 a batch:
// on the 500-plot landing diagnosis the batches per refinement were 6.2 on average without this
// stop (and with a fixed stencil step), 9 % ending at kRefineBatches; with it 4.5 and 4 %.
constexpr double kRefineRise = 1e-5;
// The refinement's batches at most (box_ascent's): the first stencil and 11 steps; on a ridge
// the trust radius doubles up to 8 grid steps a batch.
constexpr int kRefineBatches = 12;

// The (lambda, log tau) maximising crit(lambda, tau): the grid, then refined.
// crit_grid(i, tau): crit at each of grid_lambdas at the grid's i-th tau, in their order.
// crit_many(points): crit at each (lambda, tau) given, in their order (at most 6 at once).
//
// The refinement is box_ascent's trust-region Newton ascent in (u, z) = ((log tau - log
// tau_lo) / grid step, logit lambda) from the grid's best point: one grid step is a unit in
// either, the stencil's step 0.005-0.05 of it (half the last step), each batch 6 models in one
// pass of the recursions, and it stops once a step is under kRefineWidth in log tau and in logit
// lambda or promises under kRefineRise. Where a stencil
// meets a model leaving no spread (a value not finite), the coordinate line searches (Brent)
// finish from where it stopped.
template <class F, class G, class M>
std::pair<double, double> search_lambda_tau(F crit, G crit_grid, M crit_many, double ltau_lo, double ltau_hi,
                                            double f_out) {
  // grid
  double best_ll = -INFINITY, best_lt = ltau_lo, best_lam = 0.9;
  for (int i = 0; i < n_tau; ++i) {
    const double lt = ltau_lo + (ltau_hi - ltau_lo) * i / (n_tau - 1);
    const std::vector<double> lls = crit_grid(i, std::exp(lt));
    for (std::size_t j = 0; j < std::size(grid_lambdas); ++j) {
      const double ll = lls[j], lam = grid_lambdas[j];
      if (ll > best_ll) best_ll = ll, best_lt = lt, best_lam = lam;
    }
  }
  const double dlt = (ltau_hi - ltau_lo) / (n_tau - 1);
  auto logit = [](double x) { return std::log(x / (1 - x)); };
  auto expit = [](double z) { return 1 / (1 + std::exp(-z)); };
  if (dlt > 0 && std::isfinite(best_ll)) {
    // refine: the trust-region ascent in (u, z)
    auto lt_of = [&](double u) { return ltau_lo + u * dlt; };
    const BatchFunction f = [&](const std::vector<Eigen::Vector2d>& pts) {
      std::vector<std::pair<double, double>> lt;
      for (const Eigen::Vector2d& p : pts) lt.emplace_back(expit(p(1)), std::exp(lt_of(p(0))));
      return crit_many(lt);
    };
    BoxAscentOptions bo;
    bo.tol = Eigen::Vector2d(kRefineWidth / dlt, kRefineWidth);
    bo.max_batches = kRefineBatches;
    bo.f_tol = kRefineRise;
    bo.f_out = f_out;
    const Eigen::Vector2d lo(0, logit(kLambdaLo)), hi(n_tau - 1, logit(kLambdaHi));
    const Eigen::Vector2d x0(std::clamp((best_lt - ltau_lo) / dlt, lo(0), hi(0)), std::clamp(logit(best_lam), lo(1), hi(1)));
    // (the grid's value there: the same model but for the rounding of logit and expit)
    const BoxAscentResult r = box_ascent(f, x0, best_ll, lo, hi, bo);
    if (r.finite || r.out_of_reach) return {expit(r.x(1)), lt_of(r.x(0))};
    best_lam = expit(r.x(1)), best_lt = lt_of(r.x(0));
  }
  // refine (where the ascent met a model leaving no spread): log tau, then logit lambda, twice
  for (int it = 0; it < 2; ++it) {
    best_lt = brent_max([&](double lt) { return crit(best_lam, std::exp(lt)); },
                         std::max(ltau_lo, best_lt - dlt), std::min(ltau_hi, best_lt + dlt), kRefineWidth);
    const double z = brent_max([&](double z) { return crit(expit(z), std::exp(best_lt)); },
                                logit(kLambdaLo), logit(kLambdaHi), kRefineWidth);
    best_lam = expit(z);
  }
  return {best_lam, best_lt};
}

// The frames flagged as outliers under fit.params (sets fit.z_outlier); skip: the frames left out of the fit.
std::vector<char> outlier_flags(const Series& sr, const NoiseIdOptions& o, const std::vector<char>& skip,
                                NoiseFit& fit) {
  const std::vector<double>& t = sr.t;
  const Eigen::MatrixXd& Xe = sr.Xe;
  const auto n = static_cast<Eigen::Index>(t.size());
  // flag: standardized innovations of the GLS residual under the chosen model
  Eigen::MatrixXd W = Xe;
  whiten(t, sr.h, fit.params, skip, W);
  const Eigen::Index k = Xe.cols() - 1;
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(W.leftCols(k));
  const Eigen::VectorXd beta = qr.solve(W.col(k));
  // raw residual of the mean model, then its innovations over all frames (flags re-decided)
  const Eigen::VectorXd raw = Xe.col(k) - Xe.leftCols(k) * beta;
  const NoiseParams& pr = fit.params;
  fit.z_outlier = z_two_sided(std::min(0.5, o.expected_false_flags / static_cast<double>(n)));
  // innovations conditioned on the non-flagged past (a flagged frame does not update the state)
  std::vector<char> next(static_cast<std::size_t>(n), 0);
  {
    NoiseFilter f(pr, sr.h);
    for (Eigen::Index i = 0; i < n; ++i) {
      const auto ui = static_cast<std::size_t>(i);
      NoiseFilter trial = f;
      const double S = trial.predict(ui, t[ui]), nu = raw(i) - trial.mean();
      if (std::abs(nu) / std::sqrt(S) > fit.z_outlier) {
        next[ui] = 1;
        continue;
      }
      trial.update(nu);
      f = trial;
    }
  }
  return next;
}

// The outliers of fit (the n frames' flags skip): their count, share and spread in e.
void set_outliers(const std::vector<char>& skip, const Eigen::VectorXd& e, Eigen::Index n, NoiseFit& fit) {
  fit.outlier = skip;
  fit.n = 0;
  for (char s : skip) fit.n += !s;
  const int flagged = static_cast<int>(n) - fit.n;
  if (flagged > 0) {
    fit.params.p_out = std::min(0.49, static_cast<double>(flagged) / static_cast<double>(n));
    // outlier spread: their residuals about the mean model's level (robust to a few)
    std::vector<double> r;
    for (Eigen::Index i = 0; i < n; ++i)
      if (skip[static_cast<std::size_t>(i)]) r.push_back(e(i));
    double ss = 0;
    for (double x : r) ss += x * x;
    fit.params.s_out2 = std::max(ss / static_cast<double>(r.size()), 4 * fit.params.s2);
  }
}

// identify_noise; grid (profile_ml mode with fixed_skip only): its grid stage, precomputed.
NoiseFit identify(const std::vector<double>& t, const std::vector<double>& h, const Eigen::VectorXd& e,
                  const Eigen::MatrixXd& X, const NoiseIdOptions& o, const std::vector<char>* fixed_skip,
                  const NoiseGrid* grid) {
  check_series("identify_noise", t, h, e, X, o, fixed_skip);
  const auto n = static_cast<Eigen::Index>(t.size());
  const double t0 = t.front(), span = std::max(t.back() - t0, 1e-6);
  const Eigen::MatrixXd Xe = fixed_effects(t, e, X, o);
  const double mu = o.nominal_share;
  const Series sr{t, h, Xe, mu > 0 ? o.nominal_tau_s : 1.0};
  const auto [ltau_lo, ltau_hi] = log_tau_range(o, span);
  NoiseFit fit;
  std::vector<char> skip(static_cast<std::size_t>(n), 0);
  if (fixed_skip && !fixed_skip->empty()) skip = *fixed_skip;
  // The refinement's evaluations under this round's flags, remembered: the point it settles on
  // was evaluated last or nearly so, and is asked for again below (the same arguments, the same
  // bits).
  struct Evaluated {
    double lam, tau;
    Reml r;
  };
  std::vector<Evaluated> seen;
  auto reml_at = [&](double lam, double tau) {
    for (auto it = seen.rbegin(); it != seen.rend(); ++it)
      if (it->lam == lam && it->tau == tau) return it->r;
    seen.push_back({lam, tau, reml(sr, mu, lam, tau, skip)});
    return seen.back().r;
  };
  // the criterion maximised: REML, or the ML likelihood in profile_ml mode
  auto crit = [&](double lam, double tau) {
    const Reml r = reml_at(lam, tau);
    return o.profile_ml ? r.ml : r.ll;
  };
  // crit at several models, those not yet evaluated in one batch
  auto crit_many = [&](const std::vector<std::pair<double, double>>& lam_tau) {
    std::vector<std::pair<double, double>> todo;
    for (const auto& [lam, tau] : lam_tau) {
      bool known = false;
      for (const Evaluated& s : seen) known = known || (s.lam == lam && s.tau == tau);
      for (const auto& [l, t] : todo) known = known || (l == lam && t == tau);
      if (!known) todo.emplace_back(lam, tau);
    }
    if (!todo.empty()) {
      const std::vector<Reml> rs = reml_points(sr, mu, todo, skip);
      for (std::size_t k = 0; k < todo.size(); ++k) seen.push_back({todo[k].first, todo[k].second, rs[k]});
    }
    std::vector<double> out;
    for (const auto& [lam, tau] : lam_tau) out.push_back(crit(lam, tau));
    return out;
  };
  // this round's grid (unless given): the REML at every grid model
  std::vector<std::vector<Reml>> this_grid;
  auto crit_grid = [&](int i, double) {
    std::vector<double> out;
    if (grid) {  // the profile grid's ML values at the i-th tau (point 0 is the null)
      for (std::size_t j = 0; j < std::size(grid_lambdas); ++j)
        out.push_back(grid->points[1 + static_cast<std::size_t>(i) * std::size(grid_lambdas) + j].ml);
      return out;
    }
    if (this_grid.empty()) this_grid = reml_grid(sr, mu, grid_lambdas, std::size(grid_lambdas), grid_taus(ltau_lo, ltau_hi), skip);
    for (const Reml& r : this_grid[static_cast<std::size_t>(i)]) out.push_back(o.profile_ml ? r.ml : r.ll);
    return out;
  };
  for (int round = 0; round < 5; ++round) {
    seen.clear();  // the flags changed
    this_grid.clear();
    const Reml white = reml_null(sr, 0.0, skip);
    if (!std::isfinite(white.ll)) throw DegenerateSeries("identify_noise: degenerate residuals (no spread)");
    const Reml nominal = mu > 0 ? reml_null(sr, mu, skip) : white;
    // Naming a departure from the nominal noise takes the familywise chi2(2) quantile; using the
    // correlated model to whiten takes only Akaike's 2 per parameter: under-modelled slow noise
    // would let slow mean effects through, an unneeded correlated model only costs a little power.
    // The correlated model's tau is scanned (it does not exist under the null), so like a scanned
    // mean effect the test pays for its scan: alpha split over the tau grid (Bonferroni; the
    // chi2(2) quantile at alpha is -2 log alpha).
    const double q_name = 2 * -std::log(o.alpha_correlated / n_tau);
    // REML: the further part's likelihood matters only above the lesser of the two thresholds;
    // the refinement gives up on a hill whose top stays well under it (box_ascent's f_out: 75 %
    // of the landing bench flight's identifications end without a further part). The profile
    // likelihood's value is its result: refined unless the caller needs it only above a value
    // (profile_give_up_below: a test against its threshold).
    const double f_out = o.profile_ml ? o.profile_give_up_below
                                      : std::max(nominal.ll, white.ll) + 0.5 * std::min(q_name, o.use_correlated_lr);
    const auto [best_lam, best_lt] = search_lambda_tau(crit, crit_grid, crit_many, ltau_lo, ltau_hi, f_out);
    const Reml corr = reml_at(best_lam, std::exp(best_lt));
    if (o.profile_ml) {
      // the profile log-likelihood over {nominal, nominal + Gauss-Markov}: the better one
      const Reml& nom = nominal;
      fit.params = NoiseParams{};
      fit.params.nom_share = mu, fit.params.nom_tau_s = sr.tau0;
      fit.correlated = corr.ml > nom.ml;
      fit.params.s2 = fit.correlated ? corr.s2 : nom.s2;
      if (fit.correlated) fit.params.lambda = best_lam, fit.params.tau_s = std::exp(best_lt);
      fit.loglik_ml = std::max(corr.ml, nom.ml);
      fit.loglik_white = white.ml, fit.loglik_correlated = corr.ml, fit.loglik_nominal = nom.ml;
      break;
    }
    fit.loglik_white = white.ll;
    fit.loglik_correlated = corr.ll;
    fit.loglik_nominal = nominal.ll;
    fit.s2_nominal = nominal.s2;
    fit.dof_nominal = nominal.dof;
    const double lr_null = 2 * (corr.ll - std::max(nominal.ll, white.ll));
    fit.departs_nominal = lr_null > q_name;
    fit.correlated = lr_null > o.use_correlated_lr;
    fit.params = NoiseParams{};
    if (mu > 0) fit.params.nom_share = mu, fit.params.nom_tau_s = sr.tau0;
    if (mu > 0 && !fit.correlated) {
      // the nominal correlated model stands (its scale fitted)
      fit.correlated = true;
      fit.params.s2 = nominal.s2;
      fit.se_tau_s = 0;
    } else if (fit.correlated) {
      fit.params.s2 = corr.s2;
      fit.params.lambda = best_lam;
      fit.params.tau_s = std::exp(best_lt);
      fit.se_tau_s = 0;
      if (o.se_tau) {
        // SE of log tau from the profile curvature (second difference over +-0.1 in log tau)
        const double dh = 0.1;
        const double lp = reml(sr, mu, best_lam, std::exp(best_lt + dh), skip).ll,
                     lm = reml(sr, mu, best_lam, std::exp(best_lt - dh), skip).ll;
        const double curv = -(lp - 2 * corr.ll + lm) / (dh * dh);
        fit.se_tau_s = curv > 0 ? fit.params.tau_s / std::sqrt(curv) : fit.params.tau_s;
      }
    } else {
      fit.params.s2 = white.s2;
      fit.params.lambda = 0;
      fit.params.tau_s = 1;
    }
    // the ML log-likelihood of the model chosen: one of the three evaluated above (a further
    // part: corr's model; the nominal one alone: nominal's; else white's)
    fit.loglik_ml = fit.params.lambda > 0 ? corr.ml : mu > 0 ? nominal.ml : white.ml;
    if (!o.flag_outliers || fixed_skip) break;
    const std::vector<char> next = outlier_flags(sr, o, skip, fit);
    if (next == skip) break;
    skip = next;
  }
  set_outliers(skip, e, n, fit);
  return fit;
}

// The profile grid's Series: fixed effects exactly X (profile_ml mode, no trend).
NoiseGrid grid_of(const std::vector<double>& t, const std::vector<double>& h, const Eigen::VectorXd& e,
                  const Eigen::MatrixXd& X, const NoiseIdOptions& o, const std::vector<char>& skip) {
  NoiseIdOptions ro = o;
  ro.profile_ml = true;  // fixed effects exactly X (no trend)
  const Eigen::MatrixXd Xe = fixed_effects(t, e, X, ro);
  const double mu = o.nominal_share;
  const Series sr{t, h, Xe, mu > 0 ? o.nominal_tau_s : 1.0};
  const auto [ltau_lo, ltau_hi] = log_tau_range(o, std::max(t.back() - t.front(), 1e-6));
  NoiseGrid g;
  auto keep = [&](double lam, double tau, double lt, const Reml& r) {
    NoiseGrid::Point pt;
    pt.p.s2 = r.s2, pt.p.lambda = lam, pt.p.tau_s = tau, pt.p.nom_share = mu, pt.p.nom_tau_s = sr.tau0;
    pt.ll = r.ll, pt.ml = r.ml, pt.log_tau = lt;
    g.points.push_back(pt);
  };
  keep(0.0, 1.0, 0.0, reml_null(sr, mu, skip));
  const std::vector<double> taus = grid_taus(ltau_lo, ltau_hi);
  const std::vector<std::vector<Reml>> rs = reml_grid(sr, mu, grid_lambdas, std::size(grid_lambdas), taus, skip);
  for (int i = 0; i < n_tau; ++i) {
    const double lt = ltau_lo + (ltau_hi - ltau_lo) * i / (n_tau - 1);
    const auto ui = static_cast<std::size_t>(i);
    for (std::size_t j = 0; j < rs[ui].size(); ++j) keep(grid_lambdas[j], taus[ui], lt, rs[ui][j]);
  }
  return g;
}

}  // namespace

NoiseFit identify_noise(const std::vector<double>& t, const std::vector<double>& h, const Eigen::VectorXd& e,
                        const Eigen::MatrixXd& X, const NoiseIdOptions& o, const std::vector<char>* fixed_skip) {
  return identify(t, h, e, X, o, fixed_skip, nullptr);
}

NoiseGrid profile_noise_grid(const std::vector<double>& t, const std::vector<double>& h, const Eigen::VectorXd& e,
                             const Eigen::MatrixXd& X, const NoiseIdOptions& o, const std::vector<char>& skip) {
  check_series("profile_noise_grid", t, h, e, X, o, &skip);
  return grid_of(t, h, e, X, o, skip);
}

NoiseFit identify_noise_profile(const std::vector<double>& t, const std::vector<double>& h, const Eigen::VectorXd& e,
                                const Eigen::MatrixXd& X, const NoiseIdOptions& o, const std::vector<char>& skip,
                                const NoiseGrid& g) {
  if (!o.profile_ml) throw std::invalid_argument("identify_noise_profile: the options must be in profile_ml mode");
  if (g.points.size() != 1 + n_tau * std::size(grid_lambdas))
    throw std::invalid_argument("identify_noise_profile: the grid is not a profile_noise_grid");
  return identify(t, h, e, X, o, &skip, &g);
}

std::vector<std::size_t> confidence_indices(const NoiseGrid& g, double q) {
  if (!(q > 0)) throw std::invalid_argument("noise_confidence_set: q must be > 0");
  // every model with spread left, ranked by REML log-likelihood (the null first among equals)
  std::vector<std::size_t> all;
  double best = -INFINITY;
  for (std::size_t i = 0; i < g.points.size(); ++i)
    if (std::isfinite(g.points[i].ll)) all.push_back(i), best = std::max(best, g.points[i].ll);
  std::stable_sort(all.begin(), all.end(), [&](std::size_t a, std::size_t b) { return g.points[a].ll > g.points[b].ll; });
  std::vector<std::size_t> out;
  for (std::size_t i : all)
    if (2 * (best - g.points[i].ll) <= q) out.push_back(i);
  return out;
}

std::vector<NoiseParams> noise_confidence_set(const std::vector<double>& t, const std::vector<double>& h,
                                              const Eigen::VectorXd& e, const Eigen::MatrixXd& X, const NoiseIdOptions& o,
                                              const std::vector<char>& skip, double q) {
  check_series("noise_confidence_set", t, h, e, X, o, &skip);
  if (!(q > 0)) throw std::invalid_argument("noise_confidence_set: q must be > 0");
  return confidence_set_of(grid_of(t, h, e, X, o, skip), q);
}

std::vector<NoiseParams> confidence_set_of(const NoiseGrid& g, double q) {
  std::vector<NoiseParams> out;
  for (std::size_t i : confidence_indices(g, q)) out.push_back(g.points[i].p);
  if (out.empty()) throw DegenerateSeries("noise_confidence_set: degenerate residuals (no spread)");
  return out;
}

std::vector<char> outliers_beyond_noise_set(const std::vector<double>& t, const std::vector<double>& h,
                                            const Eigen::VectorXd& e, const Eigen::MatrixXd& X, const NoiseIdOptions& o,
                                            const std::vector<char>& flags, double q) {
  check_series("outliers_beyond_noise_set", t, h, e, X, o, &flags);
  std::vector<char> kept = flags;
  if (std::none_of(flags.begin(), flags.end(), [](char f) { return f != 0; })) return kept;
  NoiseIdOptions fo = o;
  fo.profile_ml = false;  // flags as identify_noise decides them: X and the trend
  const Eigen::MatrixXd Xe = fixed_effects(t, e, X, fo);
  const double mu = o.nominal_share;
  const Series sr{t, h, Xe, mu > 0 ? o.nominal_tau_s : 1.0};
  for (const NoiseParams& p : noise_confidence_set(t, h, e, X, o, flags, q)) {
    NoiseFit fit;
    fit.params = p;
    fit.params.s2 = reml(sr, mu, p.lambda, p.tau_s, flags).s2;
    const std::vector<char> under = outlier_flags(sr, o, flags, fit);
    bool any = false;
    for (std::size_t i = 0; i < kept.size(); ++i) {
      kept[i] = kept[i] && under[i];
      any = any || kept[i];
    }
    if (!any) break;
  }
  return kept;
}

double loglik_ml_at(const std::vector<double>& t, const std::vector<double>& h, const Eigen::VectorXd& e,
                    const Eigen::MatrixXd& X, const NoiseParams& p, const std::vector<char>& skip) {
  NoiseIdOptions ro;
  ro.profile_ml = true;  // fixed effects exactly X
  const Eigen::MatrixXd Xe = fixed_effects(t, e, X, ro);
  const Series sr{t, h, Xe, p.nom_share > 0 ? p.nom_tau_s : 1.0};
  return reml(sr, p.nom_share, p.lambda, p.tau_s, skip).ml;
}

}  // namespace rnav
