// Internal to the effect search: the noise identified on one channel with given fixed-effect
// columns and outlier flags, remembered for the rest of one search (or of the searches sharing
// it: SearchOptions::noise_memo).
#pragma once

#include "estimators/model_id/noise_id.hpp"

#include <Eigen/Dense>
#include <cstdint>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

namespace rnav::search_detail {

/// identify_noise is a pure function of (times, gains, residuals, columns, options, flags). In
/// one search the times, gains and residuals of a channel never change, and a candidate's test
/// re-identifies its touched channels with the same columns at every selection step until an
/// entry touching that channel is chosen (a per-target entry changes one or two of 50 channels),
/// and again when the selection is repeated (after a refusal, in the next noise round). Searches
/// of the same recordings (a pooled diagnosis and its leave-one-out) see the same channels again.
/// The memo returns the stored fit for the same (times, gains, residuals, columns, options,
/// flags), whichever channel or search asks; it is keyed by two independent 64-bit hashes of
/// their bytes (a false match has probability about 2^-128 per pair of keys), and is safe to
/// share between threads and searches. The fit is the same whoever computed it, so results do
/// not depend on scheduling.
class NoiseMemo {
 public:
  /// The fit of identify_noise(t, h, e, X, o, skip), computed on first use.
  /// Rethrows DegenerateSeries as identify_noise threw it.
  NoiseFit fit(const std::vector<double>& t, const std::vector<double>& h, const Eigen::VectorXd& e,
               const Eigen::MatrixXd& X, const NoiseIdOptions& o, const std::vector<char>* skip);
  /// A profile-mode fit with frames kept out (o.profile_ml, skip given) reads its grid stage from
  /// grid(): the same fit, and the grid is then there for the confidence sets of the same columns.
  ///
  /// noise_confidence_set(t, h, e, X, o, skip, q), ranked from grid() (a set at any q costs no
  /// further fit). Rethrows DegenerateSeries.
  std::vector<NoiseParams> confidence_set(const std::vector<double>& t, const std::vector<double>& h,
                                          const Eigen::VectorXd& e, const Eigen::MatrixXd& X, const NoiseIdOptions& o,
                                          const std::vector<char>& skip, double q);
  /// profile_noise_grid(t, h, e, X, o, skip), computed on first use (keyed by what it reads:
  /// options other than the tau range and the nominal component do not split it).
  std::shared_ptr<const NoiseGrid> grid(const std::vector<double>& t, const std::vector<double>& h,
                                        const Eigen::VectorXd& e, const Eigen::MatrixXd& X, const NoiseIdOptions& o,
                                        const std::vector<char>& skip);
  std::size_t hits() const;    ///< calls answered from the memo
  std::size_t misses() const;  ///< calls computed

 private:
  struct Stored {
    bool degenerate = false;
    std::string what;  ///< DegenerateSeries's message
    NoiseFit fit;
    std::shared_ptr<const NoiseGrid> grid;
  };
  template <class Compute>
  Stored lookup(const std::pair<std::uint64_t, std::uint64_t>& key, Compute compute);
  using Key = std::pair<std::uint64_t, std::uint64_t>;
  mutable std::mutex m_;
  std::map<Key, Stored> stored_;
  std::size_t hits_ = 0, misses_ = 0;
};

}  // namespace rnav::search_detail
