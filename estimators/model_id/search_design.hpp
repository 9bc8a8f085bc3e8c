// Internal to the effect search: the problem's columns whitened under the channels' noise
// models (one whitening per noise model), and least squares on whitened columns.
#pragma once

#include "estimators/model_id/effect_search.hpp"
#include "estimators/model_id/noise_memo.hpp"

#include <map>
#include <memory>
#include <mutex>
#include <utility>
#include <vector>

namespace rnav::search_detail {

/// Least squares of y on X with column equilibration and a rank-revealing QR; rows with
/// mask 0 (when mask is non-empty) are left out. A rank-deficient X fails (ok false) unless
/// basic is set: then the columns the QR finds dependent get 0 (a basic solution; no cov).
struct Ols {
  Eigen::VectorXd beta;
  Eigen::MatrixXd cov_unscaled;  ///< (X' X)^-1 (multiply by the residual variance)
  double rss = 0;
  double n = 0;
  int rank = 0;
  bool ok = false;
};
Ols ols(const Eigen::MatrixXd& X, const Eigen::VectorXd& y, const std::vector<char>& mask = {}, bool basic = false);

/// The 2 log LRs of catalogue grid points given a model (Projector::entry_lr), kept under one
/// noise: the search asks the same model about the same entries in several places (forward
/// selection's ranking; the rivals in the swap and in the report's confounding, given the other
/// chosen entries) and each time computed the same numbers again (the projections were a third
/// of a pooled multi-sensor diagnosis). Per model (the chosen (entry, grid point) pairs spanning
/// it, in order), per entry, per grid point; NaN: not computed yet.
struct LrMemo {
  std::mutex m;
  std::map<std::vector<std::pair<std::size_t, std::size_t>>, std::vector<std::vector<double>>> lr;
};

/// A whitened block C's columns scaled to unit norm, U = C diag(inv_norm): what a projection of
/// them needs besides their products with the model's basis and residual (Projector::lr), the
/// same under every model.
struct UnitGram {
  Eigen::VectorXd inv_norm;  ///< 1 / |C_j| (0 for a zero column)
  Eigen::MatrixXd UU;        ///< U' U
  Eigen::Index lo = 0, hi = 0;  ///< C is 0 outside rows [lo, hi) (lo = hi = 0: everywhere)
};
UnitGram unit_gram(const Eigen::MatrixXd& C);
/// The same where C is known to be 0 in rows [0, zero_below) and [zero_from, rows) (they are not
/// scanned: the same result when they are 0). Throws std::logic_error unless
/// 0 <= zero_below <= zero_from <= rows.
UnitGram unit_gram(const Eigen::MatrixXd& C, Eigen::Index zero_below, Eigen::Index zero_from);

struct Design {
  const Problem* pb = nullptr;
  std::vector<std::vector<std::size_t>> rows;   ///< per channel: observation indices in time order
  std::vector<std::vector<double>> times;       ///< per channel: their times
  std::vector<std::vector<double>> gains;       ///< per channel: the nominal component's gains (empty: 1)
  std::vector<NoiseParams> noise;               ///< per channel
  std::vector<std::vector<char>> skip;          ///< per channel: frames kept out (outliers)
  Eigen::VectorXd yw;                           ///< whitened residuals
  Eigen::MatrixXd Nw;                           ///< whitened nuisance
  std::vector<std::vector<Eigen::MatrixXd>> Cw; ///< [entry][grid point] whitened columns
  std::vector<std::vector<UnitGram>> Cg;        ///< [entry][grid point] unit_gram(Cw)
  std::vector<char> used;                       ///< per observation: not skipped
  double n_used = 0;
  /// the noise fits of this search's tests, remembered (shared by copies and threads)
  std::shared_ptr<NoiseMemo> memo = std::make_shared<NoiseMemo>();
  /// the 2 log LRs given each model under the current noise (a fresh one at each set_noise)
  std::shared_ptr<LrMemo> lr_memo = std::make_shared<LrMemo>();

  /// Index the channels (checks sizes, finiteness and time order).
  explicit Design(const Problem& p);
  /// Whiten everything under these noise models and outlier flags.
  void set_noise(const std::vector<NoiseParams>& np, const std::vector<std::vector<char>>& sk);
  /// A raw n_obs x k matrix whitened channel by channel.
  Eigen::MatrixXd whiten(const Eigen::MatrixXd& raw) const;
  /// The same under other noise models (one per channel; the design's outlier flags).
  Eigen::MatrixXd whiten_with(const Eigen::MatrixXd& raw, const std::vector<NoiseParams>& np) const;
  /// Each channel's filter gains under np[c] (the design's outlier flags), to whiten many
  /// matrices under the same models (whiten_through).
  std::vector<GainTable> gain_tables(const std::vector<NoiseParams>& np) const;
  /// A raw n_obs x k matrix whitened channel by channel through gain_tables' tables: whiten_with's
  /// result, bit for bit.
  Eigen::MatrixXd whiten_through(const Eigen::MatrixXd& raw, const std::vector<GainTable>& tables) const;
  /// Per channel: whether raw's columns are not all 0 on its observations.
  std::vector<char> touches(const Eigen::MatrixXd& raw) const;
  /// Raw columns of entry e at grid point v (checked shape).
  Eigen::MatrixXd raw_columns(std::size_t e, std::size_t v) const;
  /// The same without a copy where the entry's columns are kept (Candidate::kept_columns,
  /// checked when kept); else raw_columns(e, v) put in scratch. Valid while both live.
  const Eigen::MatrixXd& raw_view(std::size_t e, std::size_t v, Eigen::MatrixXd& scratch) const;
  /// touches(raw_columns(e, v)) where the entry's columns are kept, else nullptr.
  const std::vector<char>* kept_touches(std::size_t e, std::size_t v) const;

 private:
  /// Cw: every entry's columns at every grid point whitened through the channels' tables
  /// (whiten_through's values, bit for bit), and their Cg.
  void whiten_catalogue(const std::vector<GainTable>& tables);
  /// Cw laid out for the catalogue: every grid point's matrix, 0 on the rows of the channels it
  /// does not touch (cat_touched_), the other rows left for whiten_catalogue.
  void lay_out_catalogue();
  /// Channel c's rows of the n_obs-long columns src[j] whitened through table into the same rows
  /// of dst[j] (dst[j] = src[j]: in place), all at once: where the channel's rows are one block,
  /// where they are; else gathered, whitened and put back.
  void whiten_channel(std::size_t c, const GainTable& table, const std::vector<const double*>& src,
                      const std::vector<double*>& dst) const;
  /// Whether channel c's rows are one block of consecutive observations.
  bool one_block(std::size_t c) const;
  /// Whether lay_out_catalogue has run, and which channels each grid point touches:
  /// [entry][variant * channels + channel].
  bool catalogue_laid_out_ = false;
  std::vector<std::vector<char>> cat_touched_;
};

/// [Nw | whitened columns of the chosen (entry, grid point) pairs].
Eigen::MatrixXd model_matrix(const Design& d, const std::vector<std::pair<std::size_t, std::size_t>>& chosen);
/// The same in raw (unwhitened) columns.
Eigen::MatrixXd raw_model_matrix(const Design& d, const std::vector<std::pair<std::size_t, std::size_t>>& chosen);

/// The model spanned by M (whitened) with y projected off it: 2 log LR of adding columns,
/// scale profiled: n log(RSS_M / RSS_(M,C)); -1 if C is (nearly) inside span(M).
struct Projector {
  Eigen::MatrixXd Q;   ///< orthonormal basis of span(M)
  Eigen::VectorXd r;   ///< y minus its projection
  Eigen::VectorXd Qr;  ///< Q' r: r's rounding inside span(M)
  double rss = 0;      ///< |r|^2
  double n = 0;
  Projector(const Eigen::MatrixXd& M, const Eigen::VectorXd& y, double n_used);
  double lr(const Eigen::MatrixXd& C) const;
  /// lr(C) with C's unit_gram given.
  double lr(const Eigen::MatrixXd& C, const UnitGram& g) const;
  /// lr of entry e's whitened columns at grid point v (d.Cw[e][v], with d.Cg[e][v]), remembered
  /// in the design's LrMemo when the projector was made by projector_of (the same number either way).
  double entry_lr(const Design& d, std::size_t e, std::size_t v) const;
  std::shared_ptr<LrMemo> memo;                            ///< where entry_lr remembers (none: it does not)
  std::vector<std::pair<std::size_t, std::size_t>> model;  ///< the chosen pairs M is made of (memo's key)

 private:
  /// lr by the Householder QR of the projected unit columns (any conditioning).
  double lr_qr(const Eigen::MatrixXd& C) const;
};

/// The projector of model_matrix(d, model), its entry_lr remembered in d.lr_memo.
Projector projector_of(const Design& d, const std::vector<std::pair<std::size_t, std::size_t>>& model);

/// 2 log LR of adding columns C to the model spanned by M (whitened), scale profiled:
/// n log(RSS_M / RSS_(M,C)); -1 if C is (nearly) inside span(M).
double added_lr(const Eigen::MatrixXd& M, const Eigen::VectorXd& y, const Eigen::MatrixXd& C, double n);

/// Largest canonical correlation of the column spaces of A and B after projecting out M.
double canonical_corr(const Eigen::MatrixXd& M, const Eigen::MatrixXd& A, const Eigen::MatrixXd& B);
/// The same with Q an orthonormal basis of span(M) (Projector::Q) given instead of M.
double canonical_corr_given(const Eigen::MatrixXd& Q, const Eigen::MatrixXd& A, const Eigen::MatrixXd& B);
/// The same with A's and B's unit_gram given (a design's grid points have theirs: Design::Cg).
double canonical_corr_given(const Eigen::MatrixXd& Q, const Eigen::MatrixXd& A, const UnitGram& ga,
                            const Eigen::MatrixXd& B, const UnitGram& gb);

/// The best grid point of entry e given the model P projects off: its 2 log LR (-1: none
/// adds anything) and index.
std::pair<double, std::size_t> best_variant(const Design& d, const Projector& P, std::size_t e);

/// What "explains as well" allows in 2 log LR between two entries, the larger of whose grids has
/// `grid` points: strong evidence (6 on the Kass-Raftery scale) or that scan's look-elsewhere
/// cost (2 log grid), whichever is larger.
double as_well_margin(std::size_t grid);

/// Entry f as a rival of the chosen entry (e, v) given the model M (whitened, the other chosen
/// entries; P projects off it): f at its best grid point explains the same residual when their
/// columns' canonical correlation given M exceeds confound_corr, or when f passes its own
/// plug-in test (Bonferroni over m_family and its grid at alpha) and its 2 log LR falls short of
/// e's by less than as_well_margin of the larger grid.
struct Rival {
  std::size_t v = 0;   ///< f's best grid point
  double lr = -1;      ///< its plug-in 2 log LR given M
  double corr = 0;     ///< canonical correlation with e's columns given M
  bool same = false;   ///< explains the same residual
};
Rival rival(const Design& d, const Projector& P, std::size_t e, std::size_t v, std::size_t f,
            double alpha, double confound_corr, double m_family);

}  // namespace rnav::search_detail
