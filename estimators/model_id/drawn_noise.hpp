// Internal to the effect search: the noise a simulation of each channel draws
// (ChannelNoise::drawn): the residual under the final model,
//   e = y - N beta_N - C beta_C   (res.nuisance_fit + res.effect_fit),
// identified by maximum likelihood with no fixed effect but those given (the named ones are
// subtracted) and tau up to four spans (a shorter cap takes a wander as slow as the series for
// a faster, smaller one: test_model_id measures it), the outlier flags of the channel's fit
// kept; the identified noise where no correlated part beats the nominal one by
// use_correlated_lr.
#pragma once

#include "estimators/model_id/entry_tests.hpp"

namespace rnav::search_detail {

/// Channel c's residual under the final model (res's fits), in its time order.
Eigen::VectorXd final_residual(const Design& d, std::size_t c, const SearchResult& res);

/// The drawn noise of channel c on residual e with fixed effects X (n x k, may have no
/// columns), starting from its identified fit; throws DegenerateSeries where X leaves no spread.
NoiseFit drawn_model(const Design& d, const SearchOptions& o, std::size_t c, const SearchResult& res, const Eigen::VectorXd& e,
                     const Eigen::MatrixXd& X);

/// Whether cn.drawn has a correlated part slower than cn.fit may hold (tau > span /
/// tau_span_divisor) that raises its sigma over fit's by more than 10 %: a slow wander no named
/// effect explains.
bool slow_wander(const ChannelNoise& cn, const std::vector<double>& t, const NoiseIdOptions& no);

/// res.noise[c].drawn, drawn_ok and slow_wander of every channel (o.threads at once; the same
/// result whatever the scheduling).
void drawn_noise(const Design& d, const SearchOptions& o, SearchResult& res);

}  // namespace rnav::search_detail
