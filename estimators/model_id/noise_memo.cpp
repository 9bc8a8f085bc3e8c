#include "estimators/model_id/noise_memo.hpp"

#include "estimators/model_id/byte_hash.hpp"

namespace rnav::search_detail {

namespace {

// The key of one channel's series: what identify_noise and noise_confidence_set read besides
// the set's level (tag: which of the two; q: the set's level, 0 for a fit).
std::pair<std::uint64_t, std::uint64_t> series_key(char tag, double q, const std::vector<double>& t,
                                                   const std::vector<double>& h, const Eigen::VectorXd& e,
                                                   const Eigen::MatrixXd& X, const NoiseIdOptions& o,
                                                   const std::vector<char>* skip) {
  ByteHash k;
  k.value(tag), k.value(q);
  k.value(t.size()), k.value(h.size()), k.value(e.size());
  k.bytes(t.data(), t.size() * sizeof(double));
  k.bytes(h.data(), h.size() * sizeof(double));
  k.bytes(e.data(), static_cast<std::size_t>(e.size()) * sizeof(double));
  // every option that identify_noise and noise_confidence_set read
  k.value(o.tau_min_s), k.value(o.tau_max_s), k.value(o.tau_span_divisor), k.value(o.alpha_correlated);
  k.value(o.flag_outliers), k.value(o.expected_false_flags), k.value(o.nominal_share), k.value(o.nominal_tau_s);
  k.value(o.use_correlated_lr), k.value(o.profile_ml), k.value(o.se_tau), k.value(o.profile_give_up_below);
  k.value(X.rows()), k.value(X.cols());
  k.bytes(X.data(), static_cast<std::size_t>(X.size()) * sizeof(double));
  k.value(skip != nullptr);
  if (skip) {
    k.value(skip->size());
    k.bytes(skip->data(), skip->size());
  }
  return {k.a, k.b};
}

}  // namespace

template <class Compute>
NoiseMemo::Stored NoiseMemo::lookup(const Key& key, Compute compute) {
  {
    std::lock_guard<std::mutex> lock(m_);
    const auto it = stored_.find(key);
    if (it != stored_.end()) {
      ++hits_;
      if (it->second.degenerate) throw DegenerateSeries(it->second.what);
      return it->second;
    }
  }
  Stored s;
  try {
    compute(s);
  } catch (const DegenerateSeries& d) {
    s.degenerate = true;
    s.what = d.what();
  }
  {
    std::lock_guard<std::mutex> lock(m_);
    ++misses_;
    stored_.emplace(key, s);
  }
  if (s.degenerate) throw DegenerateSeries(s.what);
  return s;
}

NoiseFit NoiseMemo::fit(const std::vector<double>& t, const std::vector<double>& h, const Eigen::VectorXd& e,
                        const Eigen::MatrixXd& X, const NoiseIdOptions& o, const std::vector<char>* skip) {
  return lookup(series_key('f', 0.0, t, h, e, X, o, skip),
                [&](Stored& s) {
                  s.fit = o.profile_ml && skip ? identify_noise_profile(t, h, e, X, o, *skip, *grid(t, h, e, X, o, *skip))
                                               : identify_noise(t, h, e, X, o, skip);
                })
      .fit;
}

std::shared_ptr<const NoiseGrid> NoiseMemo::grid(const std::vector<double>& t, const std::vector<double>& h,
                                                 const Eigen::VectorXd& e, const Eigen::MatrixXd& X,
                                                 const NoiseIdOptions& o, const std::vector<char>& skip) {
  // only what the grid reads: the tau range and the nominal component (the rest set to defaults)
  NoiseIdOptions g;
  g.tau_min_s = o.tau_min_s, g.tau_max_s = o.tau_max_s, g.tau_span_divisor = o.tau_span_divisor;
  g.nominal_share = o.nominal_share, g.nominal_tau_s = o.nominal_tau_s;
  return lookup(series_key('g', 0.0, t, h, e, X, g, &skip),
                [&](Stored& s) { s.grid = std::make_shared<const NoiseGrid>(profile_noise_grid(t, h, e, X, g, skip)); })
      .grid;
}

std::vector<NoiseParams> NoiseMemo::confidence_set(const std::vector<double>& t, const std::vector<double>& h,
                                                   const Eigen::VectorXd& e, const Eigen::MatrixXd& X,
                                                   const NoiseIdOptions& o, const std::vector<char>& skip, double q) {
  return confidence_set_of(*grid(t, h, e, X, o, skip), q);
}

std::size_t NoiseMemo::hits() const {
  std::lock_guard<std::mutex> lock(m_);
  return hits_;
}

std::size_t NoiseMemo::misses() const {
  std::lock_guard<std::mutex> lock(m_);
  return misses_;
}

}  // namespace rnav::search_detail
