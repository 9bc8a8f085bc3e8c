// The noise model of one channel (a time series of residuals) and its innovations form.
//
// Model: e_i = h_i a(t_i) + g(t_i) + w_i with three independent parts,
//   a  the nominal correlated component (e.g. a navigation solution's Gauss-Markov error seen
//      through the measurement geometry): stationary Gauss-Markov, E a(t) a(t') =
//      mu s^2 exp(-|t - t'| / tau0), seen with a known per-frame gain h_i (RMS 1 over the
//      channel; h = 1 when no profile is given) - the part the nominal model already has;
//   g  a further Gauss-Markov part: E g(t) g(t') = (1 - mu) lambda s^2 exp(-|t - t'| / tau);
//   w  white: E w^2 = (1 - mu) (1 - lambda) s^2,
// so s^2 is the (gain-RMS) marginal variance, mu the nominal component's share (0: none),
// lambda the share of the rest that is correlated (0: white; near 1: AR(1) sampled at the frame
// times) and tau [s] its correlation time. Irregular sampling and gaps are exact: between frames
// the transitions are phi = exp(-(t_i - t_(i-1)) / tau) and phi0 likewise with tau0.
// Heavy tails: with probability p_out a frame is an outlier ~ N(0, S_i + s_out^2) instead
// (a contaminated normal: the outlier does not update the state).
//
// Innovations form (the Kalman filter of x = (a, g), H_i = (h_i, 1)):
//   x-_i = Phi_i x+_(i-1),      P-_i = Phi_i P+ Phi_i + diag(q0 (1 - phi0^2), q (1 - phi^2)),
//   nu_i = e_i - H_i x-_i,      S_i  = H_i P-_i H_i' + r,
//   K_i  = P-_i H_i' / S_i,     x+_i = x-_i + K_i nu_i,   P+_i = (I - K_i H_i) P-_i,
// q0 = mu s^2, q = (1 - mu) lambda s^2, r = (1 - mu) (1 - lambda) s^2. The map e -> nu / sqrt(S)
// is linear with gains that depend only on the times and h, so applying it to the regressor
// columns as well turns generalised least squares into ordinary least squares (whiten()). The
// log-likelihood is -1/2 sum (nu^2 / S + log(2 pi S)).
#pragma once

#include "common/physics/noise_process.hpp"

#include <Eigen/Dense>

#include <random>
#include <string>
#include <vector>

namespace rnav {



/// The innovations filter of one channel (see the model above) for one series (whiten() runs
/// the same recursion on many columns at once). gain: h_i per frame (empty: 1); it must outlive
/// the filter. Fixed-size state: copying it (a trial step) allocates nothing.
class NoiseFilter {
 public:
  NoiseFilter(const NoiseParams& p, const std::vector<double>& gain);
  /// Predict to frame i at time t [s] (frames in time order; skipped frames simply not
  /// predicted); returns the innovation variance S_i.
  double predict(std::size_t i, double t);
  /// The predicted mean H_i x-_i (after predict()).
  double mean() const;
  /// Update with the innovation nu of the frame just predicted.
  void update(double nu);

 private:
  double q0_, q_, r_, tau0_, tau_;
  const std::vector<double>* gain_;
  Eigen::Vector2d x_ = Eigen::Vector2d::Zero();  ///< state (a, g)
  Eigen::Matrix2d P_;
  Eigen::RowVector2d H_ = Eigen::RowVector2d::Ones();  ///< set by each predict()
  double S_ = 1, t_prev_ = 0;
  bool started_ = false;
};

/// Whiten the rows of M (rows = frames of one channel in time order at times t, nominal
/// component gains h, empty: 1) in place: row i becomes (M_i - predicted from rows before) /
/// sqrt(S_i). Rows with skip[i] (outliers, empty when none) become zero and do not update the
/// state. logS (if given) receives log S_i (0 for skipped rows).
void whiten(const std::vector<double>& t, const std::vector<double>& h, const NoiseParams& p,
            const std::vector<char>& skip, Eigen::Ref<Eigen::MatrixXd> M, Eigen::VectorXd* logS = nullptr);

/// whiten() under several noise models at once: Ms[j] whitened in place under ps[j], logS (if
/// given) receives each model's log S_i. The models must share nom_tau_s; their tau_s may
/// differ (the REML grid's shares lambda at one correlation time share one transition per step,
/// a refinement's batch has one per model). Each model's result is whiten()'s, bit for bit, in
/// less time (the models' recursions interleaved). Throws std::invalid_argument on sizes that
/// differ or models that do not share their nominal correlation time.
void whiten_batch(const std::vector<double>& t, const std::vector<double>& h, const std::vector<NoiseParams>& ps,
                  const std::vector<char>& skip, const std::vector<Eigen::Ref<Eigen::MatrixXd>>& Ms,
                  std::vector<Eigen::VectorXd>* logS = nullptr);

/// The innovations filter's gains at one frame under one model (whiten's first pass): they
/// depend on the frame times, h, the model and the frames kept out alone, never on what is
/// whitened.
struct InnovationGain {
  double f0 = 0, f = 0;  ///< the transitions phi0, phi from the frame before (0 for a part with no variance)
  double H0 = 1;         ///< h_i
  double K0 = 0, K1 = 0; ///< the Kalman gain
  double sq = 1;         ///< sqrt(S_i)
  bool skip = false;     ///< kept out: whitened to 0, no update
  bool started = false;  ///< a frame before it updated the state
};

/// The gains of several models on one series, kept to whiten many matrices (whitened_grams).
struct GainTable {
  std::vector<NoiseParams> models;
  /// [model][frame]; a frame's skip and started are the same for every model (innovation_gains
  /// writes them so: the frames kept out are the table's; whiten_each_model relies on it)
  std::vector<std::vector<InnovationGain>> gains;
  std::vector<double> sum_logS;  ///< per model: sum over the frames kept of log S_i (one product: the sum of the logs to about n eps)
  /// The same gains packed for whiten_each_model (pack_gains; empty: not packed): per frame a
  /// block of 4 + 3 Jp values, Jp = J rounded up to even: f0, f, H0 and a flag (0 kept out, 1
  /// started, 2 not yet), then K0, K1 and sqrt(S) of each model (a last padding model: 0, 0, 1).
  std::vector<double> packed;
  std::size_t bytes() const;     ///< memory held [B]
};

/// Packs table.gains into table.packed where every model of a frame shares its transitions f0
/// and f (a grid's models at one tau, their shares > 0); otherwise leaves packed empty. A packed
/// table's frames are about half as many bytes: whiten_each_model reads them instead (the same
/// values bit for bit; the grid's whitening waited on memory more than on arithmetic).
void pack_gains(GainTable& table);

/// The gain table of the models ps (which must share nom_tau_s) at frame times t
/// (gains h, empty: 1; frames skip kept out, empty: none), as whiten_batch computes it. Throws
/// std::invalid_argument as whiten_batch.
void innovation_gains(const std::vector<double>& t, const std::vector<double>& h, const std::vector<NoiseParams>& ps,
                      const std::vector<char>& skip, GainTable& table);

/// M whitened in place under table.models[j]: whiten()'s result, bit for bit, without computing
/// the gains again. Throws std::invalid_argument when M's rows are not the table's frames.
void whiten(const GainTable& table, std::size_t j, Eigen::Ref<Eigen::MatrixXd> M);
/// The same on columns given by where they start, src[k] whitened into dst[k] (dst[k] = src[k]:
/// in place; otherwise they must not overlap), each as long as the table's frames (the caller's
/// duty: lengths are not checked); at once, eight at a time (one column's recursion is a chain
/// of dependent operations: eight keep the processor busy). Throws std::invalid_argument unless
/// src and dst are as many.
void whiten(const GainTable& table, std::size_t j, const std::vector<const double*>& src, const std::vector<double*>& dst);

/// Column m whitened under every model of the table, frame-major: w[i * J + j] under
/// table.models[j] (J models, at most 16), each value whiten(table, j, m)'s bit for bit.
/// Throws std::invalid_argument when m's rows are not the table's frames or J > 16.
void whiten_each_model(const GainTable& table, const Eigen::Ref<const Eigen::VectorXd>& m, std::vector<double>& w);
/// The same into w, room for m.size() x J values (written, never read: it need not be initialised).
void whiten_each_model(const GainTable& table, const Eigen::Ref<const Eigen::VectorXd>& m, double* w);

/// What a likelihood of M's last column given the others needs, without forming the whitened
/// matrices: grams[j] = W_j' W_j, W_j being M whitened under table.models[j] (each whitened value
/// whiten_batch's, bit for bit; the sums in another order). Throws std::invalid_argument when
/// M's rows are not the table's frames.
void whitened_grams(const GainTable& table, const Eigen::MatrixXd& M, std::vector<Eigen::MatrixXd>& grams);

/// Sequential (one-step-ahead predictive) log-likelihood of residuals e at times t (gains h,
/// empty: 1) under p, summed over frames with score[i] (all when empty); every frame conditions
/// the later ones except those the mixture judges outliers (posterior outlier probability > 1/2).
double predictive_loglik(const std::vector<double>& t, const std::vector<double>& h, const std::vector<double>& e,
                         const NoiseParams& p, const std::vector<char>& score = {});



}  // namespace rnav
