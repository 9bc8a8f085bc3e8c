// Internal to the effect search: each channel's noise identified under the null of the next
// test, and the tests of one catalogue entry against the model chosen so far.
#pragma once

#include "estimators/model_id/search_design.hpp"

#include <utility>
#include <vector>

namespace rnav::search_detail {

using Chosen = std::vector<std::pair<std::size_t, std::size_t>>;  ///< (catalogue entry, grid point)

/// Channel c's rows of the raw columns X, only the columns that touch the channel (not zero on
/// all its rows).
Eigen::MatrixXd channel_columns(const Design& d, const Eigen::MatrixXd& X, std::size_t c);
/// Channel c's residuals (the problem's y on its rows).
Eigen::VectorXd channel_y(const Design& d, std::size_t c);
/// The noise options for channel c: no with the channel's nominal correlated component.
NoiseIdOptions channel_options(const Problem& p, std::size_t c, const NoiseIdOptions& no);

/// Each channel's noise, identified (REML, noise_id.hpp) with the nuisance and the chosen
/// effects, restricted to the channel, as fixed effects; `threads` channels at once.
std::vector<NoiseFit> identify_all(const Design& d, const Chosen& chosen, const NoiseIdOptions& no, int threads = 1);

/// The tests of one entry against the model `chosen` (fits: the channels' noise under it).
class EntryTests {
 public:
  /// null_set_q: the noise models the null may use in a scanned entry's test (scanned()); 0: any.
  EntryTests(const Design& d, const Chosen& chosen, const std::vector<NoiseFit>& fits, const NoiseIdOptions& no,
             double null_set_q = 0);
  /// 2 log LR of scanned entry e at grid point v: the likelihood ratio with the noise maximised
  /// under both hypotheses, the null's over the noise models the data allow once the entry is in
  /// the model (each touched channel's REML confidence set at null_set_q, fixed effects with the
  /// entry's columns); with null_set_q = 0 over the whole noise family (the profile LR).
  /// need: the 2 log LR the caller's test needs (its threshold): where the entry touches one
  /// channel, its profile refinement may then give up once the LR cannot reach need, and the
  /// value returned is under need (NoiseIdOptions::profile_give_up_below). -inf: the exact value.
  double scanned(std::size_t e, std::size_t v, double need = -INFINITY);
  /// The profile 2 log LR of entry e at grid point v: the ML likelihood maximised over the
  /// whole noise family (NoiseIdOptions::profile_ml) with and without its columns, summed over
  /// the channels it touches (scanned()'s statistic when null_set_q = 0).
  double profile_lr(std::size_t e, std::size_t v);
  /// 2 log LR of non-scanned entry e: Wald-type GLS under the noise re-identified with its columns.
  double fixed(std::size_t e) const;
  /// The least GLS 2 log LR of entry e at grid point v over the noise models the data allow:
  /// each channel it touches ranges over its noise confidence set (noise_confidence_set at q,
  /// the fixed effects with the entry's columns), by coordinate descent from the channels'
  /// most likely. q > 0.
  double least_over_noise(std::size_t e, std::size_t v, double q) const;

 private:
  Eigen::MatrixXd with(std::size_t c, const Eigen::MatrixXd& Cc) const;  ///< channel c's fixed effects and Cc
  /// channel c's ML l over the noise family (refined unless under give_up_below: NoiseIdOptions)
  double profile_ml(std::size_t c, const Eigen::MatrixXd& X, double give_up_below = -INFINITY) const;
  const Design& d_;
  const std::vector<NoiseFit>& fits_;
  NoiseIdOptions no_;
  Eigen::MatrixXd raw_;               ///< nuisance and chosen columns, raw
  std::vector<Eigen::MatrixXd> X0c_;  ///< per channel: its fixed-effect columns
  std::vector<double> base_;          ///< per channel: profile l without the entry (when first needed)
  double null_set_q_ = 0;
  /// per channel: the Gram matrix of [raw_ | y] whitened under the null's noise over its rows
  /// (fixed()'s share of a channel the entry does not touch; when first needed)
  mutable std::vector<Eigen::MatrixXd> null_gram_;
};

}  // namespace rnav::search_detail
