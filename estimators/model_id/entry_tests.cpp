// The tests of one catalogue entry (entry_tests.hpp) and the noise identified under the null.
#include "estimators/model_id/entry_tests.hpp"

#include "estimators/model_id/parallel_for.hpp"

#include <cmath>
#include <limits>
#include <stdexcept>

namespace rnav::search_detail {

namespace {

// Channel c's rows of the columns `keep` of X.
Eigen::MatrixXd channel_rows(const Design& d, const Eigen::MatrixXd& X, std::size_t c, const std::vector<Eigen::Index>& keep) {
  const auto m = static_cast<Eigen::Index>(d.rows[c].size());
  Eigen::MatrixXd Xk(m, static_cast<Eigen::Index>(keep.size()));
  for (Eigen::Index r = 0; r < m; ++r)
    for (std::size_t j = 0; j < keep.size(); ++j)
      Xk(r, static_cast<Eigen::Index>(j)) = X(static_cast<Eigen::Index>(d.rows[c][static_cast<std::size_t>(r)]), keep[j]);
  return Xk;
}

// The columns of X that touch channel c (not zero on all its rows).
std::vector<Eigen::Index> touching(const Design& d, const Eigen::MatrixXd& X, std::size_t c) {
  std::vector<Eigen::Index> keep;
  for (Eigen::Index j = 0; j < X.cols(); ++j)
    for (std::size_t r : d.rows[c])
      if (X(static_cast<Eigen::Index>(r), j) != 0) {
        keep.push_back(j);
        break;
      }
  return keep;
}

// 2 log LR of adding columns C to X given the Gram matrix G of [X | C | y] (whitened):
// n log(RSS_X / RSS_(X,C)), both from the Schur complement of X in G (columns equilibrated
// first; X's directions with eigenvalue below 1e-12 of a unit column dropped, as Projector's
// rank decision); -1 if C is (nearly) inside span(X). rss_share (if given): RSS_X / |y|^2, how
// much of y's sum of squares the Schur complement keeps (under about 1e-8 it keeps few digits).
double gram_lr(const Eigen::MatrixXd& G, Eigen::Index k, Eigen::Index kc, double n, double* rss_share = nullptr) {
  const Eigen::Index K = G.rows();
  Eigen::VectorXd s(K);
  for (Eigen::Index j = 0; j < K; ++j) s(j) = G(j, j) > 0 ? 1 / std::sqrt(G(j, j)) : 1.0;
  const Eigen::MatrixXd Gs = s.asDiagonal() * G * s.asDiagonal();
  Eigen::MatrixXd S = Gs.bottomRightCorner(kc + 1, kc + 1);
  if (k > 0) {
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(Gs.topLeftCorner(k, k));
    const Eigen::VectorXd& ev = es.eigenvalues();
    Eigen::VectorXd inv = Eigen::VectorXd::Zero(k);
    for (Eigen::Index j = 0; j < k; ++j)
      if (ev(j) > 1e-12) inv(j) = 1 / ev(j);
    const Eigen::MatrixXd T = Gs.bottomLeftCorner(kc + 1, k) * es.eigenvectors();
    S -= T * inv.asDiagonal() * T.transpose();
  }
  if (rss_share) *rss_share = S(kc, kc);  // y's column equilibrated: |y|^2 = 1
  const Eigen::MatrixXd Scc = S.topLeftCorner(kc, kc);
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> ec(Scc);
  if (ec.eigenvalues().minCoeff() < 1e-12) return -1;
  const double rss0 = S(kc, kc);
  if (!(rss0 > 0)) return 0;
  const Eigen::VectorXd b = S.topRightCorner(kc, 1);
  const double drop = b.dot(ec.eigenvectors() * ec.eigenvalues().cwiseInverse().asDiagonal() * ec.eigenvectors().transpose() * b);
  return n * std::log(rss0 / std::max(rss0 - drop, 1e-300 * rss0));
}

// Channel c's share of the Gram matrix of A's columns whitened under each of the models ps (the
// design's outlier flags): the columns `cols` (those touching the channel) whitened over its
// rows, the rest of each K x K matrix 0. The models' gains come in one pass (innovation_gains:
// the recursions interleaved, each model's values bit for bit what whiten() gives it alone).
std::vector<Eigen::MatrixXd> channel_grams(const Design& d, const Eigen::MatrixXd& A, std::size_t c,
                                           const std::vector<Eigen::Index>& cols, const std::vector<NoiseParams>& ps) {
  std::vector<Eigen::MatrixXd> out;
  if (ps.empty()) return out;
  GainTable table;
  innovation_gains(d.times[c], d.gains[c], ps, d.skip[c], table);
  const auto kk = static_cast<Eigen::Index>(cols.size());
  const Eigen::MatrixXd raw = channel_rows(d, A, c, cols);
  for (std::size_t j = 0; j < ps.size(); ++j) {
    Eigen::MatrixXd B = raw;
    whiten(table, j, B);
    const Eigen::MatrixXd Bg = B.transpose() * B;
    Eigen::MatrixXd G = Eigen::MatrixXd::Zero(A.cols(), A.cols());
    for (Eigen::Index a = 0; a < kk; ++a)
      for (Eigen::Index b = 0; b < kk; ++b) G(cols[static_cast<std::size_t>(a)], cols[static_cast<std::size_t>(b)]) = Bg(a, b);
    out.push_back(std::move(G));
  }
  return out;
}

// channel_grams under one model.
Eigen::MatrixXd channel_gram(const Design& d, const Eigen::MatrixXd& A, std::size_t c, const std::vector<Eigen::Index>& cols,
                             const NoiseParams& p) {
  return channel_grams(d, A, c, cols, {p}).front();
}

}  // namespace

// The share of y's sum of squares the null model must leave for fixed()'s Gram path (below it
// the Schur complement keeps under 8 of the residual's digits).
constexpr double kGramRssShare = 1e-8;

// Channel c's rows of the raw columns X, only the columns that touch the channel.
Eigen::MatrixXd channel_columns(const Design& d, const Eigen::MatrixXd& X, std::size_t c) {
  return channel_rows(d, X, c, touching(d, X, c));
}

Eigen::VectorXd channel_y(const Design& d, std::size_t c) {
  Eigen::VectorXd e(static_cast<Eigen::Index>(d.rows[c].size()));
  for (std::size_t r = 0; r < d.rows[c].size(); ++r) e(static_cast<Eigen::Index>(r)) = d.pb->y[d.rows[c][r]];
  return e;
}

NoiseIdOptions channel_options(const Problem& p, std::size_t c, const NoiseIdOptions& no) {
  NoiseIdOptions nc = no;
  const Channel& ch = p.channels[c];
  if (ch.nominal_corr_sigma > 0) {
    nc.nominal_share = ch.nominal_share();
    nc.nominal_tau_s = ch.nominal_corr_tau_s;
  }
  return nc;
}

// Each channel's noise, identified with the nuisance and the chosen effects (restricted to the
// channel) as fixed effects, i.e. under the null of the next test. (Identifying it with every
// catalogue entry as a fixed effect, as before, let a dozen slow columns soak up the slow noise
// in REML, the correlated part fell below its AIC threshold, and each column was then tested
// against white noise: 11 of 40 nominal flights named a mean effect under tau = 30 s noise.)
std::vector<NoiseFit> identify_all(const Design& d, const Chosen& chosen, const NoiseIdOptions& no, int threads) {
  const Eigen::MatrixXd X = raw_model_matrix(d, chosen);
  std::vector<NoiseFit> out(d.rows.size());
  // channels alone, `threads` at once (each fit is a function of its channel alone: the same
  // result whatever the scheduling); a channel no new entry touches is the memo's
  parallel_for(d.rows.size(), threads, [&](std::size_t c) {
    const Eigen::MatrixXd Xc = channel_columns(d, X, c);
    try {
      out[c] = d.memo->fit(d.times[c], d.gains[c], channel_y(d, c), Xc, channel_options(*d.pb, c, no), nullptr);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument("channel " + d.pb->channels[c].name + " (" + std::to_string(d.rows[c].size()) + " frames, " +
                                  std::to_string(Xc.cols()) + " fixed-effect columns): " + e.what());
    }
  });
  return out;
}

// A scanned effect (a step, a manoeuvre, a period) is slow where correlated noise is slow: the
// noise identified without it may have absorbed it, and the noise identified with it may be too
// white (the step absorbed the slow noise). Its test is therefore the profile likelihood ratio:
// the ML likelihood maximised over the noise family (NoiseIdOptions::profile_ml: no trend added,
// no AIC threshold) with and without its columns (same frames kept out),
// 2 sum_c [l(with) - l(without)] over the channels it touches. (Testing it under the noise
// re-identified with it alone gave a glide step 2 log LR 61 where the null noise gave 8;
// comparing ML likelihoods at REML-chosen noise parameters, as before, gave 20 where both GLS
// tests gave 5: neither is a likelihood ratio.)
//
// A non-scanned entry's test (fixed): the GLS 2 log LR of its columns given the chosen ones,
// every channel it touches whitened by its noise re-identified (REML, with the trend) with the
// entry's columns added to the null's fixed effects (a Wald-type test: the noise estimated
// under the alternative, so a physical effect the null noise took for a long correlation is
// not lost). Measured on 300 nominal white-noise flights: 1 alarm (0.33 %); the profile
// likelihood ratio used here instead gave 7 (2.3 %: its single further Gauss-Markov part goes
// to the short correlation and leaves slow misfit to the site offset).

EntryTests::EntryTests(const Design& d, const Chosen& chosen, const std::vector<NoiseFit>& fits, const NoiseIdOptions& no,
                       double null_set_q)
    : d_(d), fits_(fits), no_(no), raw_(raw_model_matrix(d, chosen)), base_(d.rows.size(), std::nan("")), null_set_q_(null_set_q) {
  if (!(null_set_q >= 0)) throw std::invalid_argument("effect search: null_set_q must be >= 0");
  for (std::size_t c = 0; c < d.rows.size(); ++c) X0c_.push_back(channel_columns(d, raw_, c));
}

double EntryTests::profile_ml(std::size_t c, const Eigen::MatrixXd& X, double give_up_below) const {
  NoiseIdOptions pm = no_;
  pm.profile_ml = true;
  pm.profile_give_up_below = give_up_below;
  try {
    return d_.memo->fit(d_.times[c], d_.gains[c], channel_y(d_, c), X, channel_options(*d_.pb, c, pm), &fits_[c].outlier)
        .loglik_ml;
  } catch (const DegenerateSeries&) {
    return std::nan("");  // the columns span the channel
  }
}

double EntryTests::profile_lr(std::size_t e, std::size_t v) {
  Eigen::MatrixXd scratch;
  const Eigen::MatrixXd& C = d_.raw_view(e, v, scratch);
  double lr = 0;
  for (std::size_t c = 0; c < d_.rows.size(); ++c) {
    const Eigen::MatrixXd Cc = channel_columns(d_, C, c);
    if (Cc.cols() == 0) continue;  // the entry does not touch this channel
    const double l1 = profile_ml(c, with(c, Cc));
    if (std::isnan(l1)) continue;  // the entry's and the chosen columns span the channel: no evidence here
    if (std::isnan(base_[c])) base_[c] = profile_ml(c, X0c_[c]);
    lr += 2 * (l1 - base_[c]);
  }
  return lr;
}

double EntryTests::scanned(std::size_t e, std::size_t v, double need) {
  if (!(null_set_q_ > 0)) return profile_lr(e, v);
  Eigen::MatrixXd scratch;
  const Eigen::MatrixXd& C = d_.raw_view(e, v, scratch);
  std::vector<Eigen::MatrixXd> Ccs;
  int touched = 0;
  for (std::size_t c = 0; c < d_.rows.size(); ++c) {
    Ccs.push_back(channel_columns(d_, C, c));
    touched += Ccs.back().cols() > 0;
  }
  double lr = 0;
  for (std::size_t c = 0; c < d_.rows.size(); ++c) {
    const Eigen::MatrixXd& Cc = Ccs[c];
    if (Cc.cols() == 0) continue;  // the entry does not touch this channel
    const Eigen::MatrixXd X1 = with(c, Cc);
    // the null's noise among the models the data allow with the entry in: a slow correlation
    // that exists only to absorb the step is not among them. The set's models are grid points,
    // and the null's likelihood at each (loglik_ml_at) is the null's own profile grid there.
    // (A column set the channel's frames cannot carry throws here as in the fit: no evidence.)
    const NoiseIdOptions oc = channel_options(*d_.pb, c, no_);
    std::shared_ptr<const NoiseGrid> g1;
    try {
      g1 = d_.memo->grid(d_.times[c], d_.gains[c], channel_y(d_, c), X1, oc, fits_[c].outlier);
    } catch (const DegenerateSeries&) {
      continue;  // the entry's and the chosen columns span the channel: no evidence here
    }
    const auto g0 = d_.memo->grid(d_.times[c], d_.gains[c], channel_y(d_, c), X0c_[c], oc, fits_[c].outlier);
    const std::vector<std::size_t> set = confidence_indices(*g1, null_set_q_);
    if (set.empty()) throw DegenerateSeries("noise_confidence_set: degenerate residuals (no spread)");
    double l0 = -INFINITY;
    for (std::size_t i : set) l0 = std::max(l0, g0->points[i].ml);
    // one channel: the test needs l1 only where 2 (l1 - l0) reaches need
    const double l1 = profile_ml(c, X1, touched == 1 && std::isfinite(need) ? l0 + 0.5 * need : -INFINITY);
    if (std::isnan(l1)) continue;  // the entry's and the chosen columns span the channel: no evidence here
    lr += 2 * (l1 - l0);
  }
  return lr;
}

double EntryTests::fixed(std::size_t e) const {
  Eigen::MatrixXd scratch;
  const Eigen::MatrixXd& C = d_.raw_view(e, 0, scratch);
  // The GLS 2 log LR from the Gram matrix of the whitened [raw_ | C | y] summed over the channels
  // (gram_lr): a channel the entry does not touch keeps its null noise and adds the share of
  // [raw_ | y] it always adds (kept); a touched one is whitened under its re-identified noise.
  // (Whitening every channel and projecting, as before, was about 5 % of the landing
  // diagnosis's CPU; the same 2 log LR to rounding.) Where the model explains y to within 1e-8
  // of its sum of squares (a reference track's fit), the Gram matrix keeps too few digits of
  // the residual and the whitened columns are projected as before.
  const Eigen::Index k = raw_.cols(), kc = C.cols(), K = k + kc + 1;
  const Eigen::Map<const Eigen::VectorXd> y(d_.pb->y.data(), static_cast<Eigen::Index>(d_.pb->size()));
  Eigen::MatrixXd A(raw_.rows(), K);
  A << raw_, C, y;
  if (null_gram_.empty()) null_gram_.resize(d_.rows.size());
  Eigen::MatrixXd G = Eigen::MatrixXd::Zero(K, K);
  std::vector<NoiseParams> nps = d_.noise;
  for (std::size_t c = 0; c < d_.rows.size(); ++c) {
    const Eigen::MatrixXd Cc = channel_columns(d_, C, c);
    NoiseParams& np = nps[c];
    if (Cc.cols() > 0) {
      try {
        np = d_.memo->fit(d_.times[c], d_.gains[c], channel_y(d_, c), with(c, Cc), channel_options(*d_.pb, c, no_),
                          &fits_[c].outlier)
                 .params;
        np.p_out = 0, np.s_out2 = 0;
      } catch (const DegenerateSeries&) {
        // the entry's and the chosen columns span this (short) channel: it says nothing of the
        // entry, and its null noise stays (e.g. a 10-frame channel with a hull offset, a clock
        // and its outlier flags)
      }
      G += channel_gram(d_, A, c, touching(d_, A, c), np);
      continue;
    }
    // untouched: [raw_ | y]'s share under the null noise, placed around C's zero rows and columns
    Eigen::MatrixXd& N = null_gram_[c];
    if (N.size() == 0) {
      Eigen::MatrixXd Ry(raw_.rows(), k + 1);
      Ry << raw_, y;
      N = channel_gram(d_, Ry, c, touching(d_, Ry, c), np);
    }
    G.topLeftCorner(k, k) += N.topLeftCorner(k, k);
    G.block(0, K - 1, k, 1) += N.block(0, k, k, 1);
    G.block(K - 1, 0, 1, k) += N.block(k, 0, 1, k);
    G(K - 1, K - 1) += N(k, k);
  }
  double rss_share = 0;
  const double lr = gram_lr(G, k, kc, d_.n_used, &rss_share);
  if (rss_share > kGramRssShare) return lr;
  const std::vector<GainTable> tables = d_.gain_tables(nps);  // once for the three matrices
  return Projector(d_.whiten_through(raw_, tables), d_.whiten_through(y, tables), d_.n_used).lr(d_.whiten_through(C, tables));
}

// The noise parameters' uncertainty, after Berger and Boos (1994: a p-value maximised over a
// 1 - beta confidence set of the nuisance parameters, plus beta, is valid whatever their true
// value). Here the nuisance is each touched channel's noise (lambda, tau; s^2 profiled), and
// the entry's GLS 2 log LR is minimised over the product of the channels' REML confidence sets
// (fixed effects exactly those of the test, no trend: a trend would make slow noise look
// free). Unlike Berger and Boos, beta is not added to the p-value (q = 4 is an 86 % set, and
// beta = 0.14 would swamp alpha / m); q is chosen by measurement instead (README). Why: the
// plug-in tests take the noise at one estimate, and in a 500 s flight a correlation of 30-90 s
// is poorly determined: the column of a slow effect soaks up the slow noise when the noise is
// re-identified with it (course: tau 68 s without a coupling column, 1.5 s with it). The GLS
// statistic for each candidate noise comes from per-channel Gram matrices (only the changed
// channel is re-whitened; the same 2 log LR as Projector's to rounding).
double EntryTests::least_over_noise(std::size_t e, std::size_t v, double q) const {
  if (!(q > 0)) throw std::invalid_argument("effect search: the noise confidence set's q must be > 0");
  Eigen::MatrixXd scratch;
  const Eigen::MatrixXd& C = d_.raw_view(e, v, scratch);
  const Eigen::Index k = raw_.cols(), kc = C.cols(), K = k + kc + 1;
  Eigen::MatrixXd A(raw_.rows(), K);
  A << raw_, C, Eigen::Map<const Eigen::VectorXd>(d_.pb->y.data(), static_cast<Eigen::Index>(d_.pb->size()));
  const std::size_t n_ch = d_.rows.size();
  std::vector<std::vector<NoiseParams>> sets(n_ch);
  std::vector<std::vector<Eigen::Index>> cols(n_ch);  // per channel: the columns of A that touch it
  for (std::size_t c = 0; c < n_ch; ++c) {
    cols[c] = touching(d_, A, c);
    const Eigen::MatrixXd Cc = channel_columns(d_, C, c);
    if (Cc.cols() == 0) continue;  // the entry does not touch this channel: its null noise stays
    try {
      sets[c] = d_.memo->confidence_set(d_.times[c], d_.gains[c], channel_y(d_, c), with(c, Cc),
                                        channel_options(*d_.pb, c, no_), fits_[c].outlier, q);
    } catch (const DegenerateSeries&) {
      // spanned by the columns: its null noise stays (empty set)
    }
  }
  // channel c's share of the Gram matrix of the whitened [X | C | y] under noise p
  auto gram = [&](std::size_t c, const NoiseParams& p) { return channel_gram(d_, A, c, cols[c], p); };
  std::vector<Eigen::MatrixXd> Gc(n_ch);
  std::vector<std::vector<Eigen::MatrixXd>> Gset(n_ch);  // per channel: each set member's share, whitened once
  Eigen::MatrixXd G = Eigen::MatrixXd::Zero(K, K);
  for (std::size_t c = 0; c < n_ch; ++c) {
    Gset[c] = channel_grams(d_, A, c, cols[c], sets[c]);
    // start from each set's most likely member; an untouched channel keeps its null noise
    G += (Gc[c] = sets[c].empty() ? gram(c, d_.noise[c]) : Gset[c].front());
  }
  double best = gram_lr(G, k, kc, d_.n_used);
  for (int sweep = 0; sweep < 2; ++sweep)
    for (std::size_t c = 0; c < n_ch; ++c)
      for (const Eigen::MatrixXd& Gn : Gset[c]) {
        const Eigen::MatrixXd Gt = G - Gc[c] + Gn;
        const double lr = gram_lr(Gt, k, kc, d_.n_used);
        if (lr >= 0 && lr < best) best = lr, G = Gt, Gc[c] = Gn;
      }
  return best;
}

Eigen::MatrixXd EntryTests::with(std::size_t c, const Eigen::MatrixXd& Cc) const {
  Eigen::MatrixXd Xc(Cc.rows(), X0c_[c].cols() + Cc.cols());
  Xc << X0c_[c], Cc;
  return Xc;
}

}  // namespace rnav::search_detail
