#include "estimators/model_id/noise_model.hpp"

#include <emmintrin.h>

#include <array>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

namespace rnav {



NoiseFilter::NoiseFilter(const NoiseParams& p, const std::vector<double>& gain)
    : q0_(p.nom_share * p.s2),
      q_((1 - p.nom_share) * p.lambda * p.s2),
      r_((1 - p.nom_share) * (1 - p.lambda) * p.s2),
      tau0_(p.nom_tau_s),
      tau_(p.tau_s),
      gain_(&gain) {
  check_noise_params(p);
  P_ << q0_, 0, 0, q_;  // stationary start
}

double NoiseFilter::predict(std::size_t i, double t) {
  if (!gain_->empty() && i >= gain_->size()) throw std::invalid_argument("NoiseFilter: frame index beyond the gain profile");
  H_ << (gain_->empty() ? 1.0 : (*gain_)[i]), 1.0;
  if (started_) {
    // x- = Phi x+, P- = Phi P+ Phi + diag(q0 (1 - phi0^2), q (1 - phi^2))
    const double dt = t - t_prev_;
    const double f0 = q0_ > 0 ? std::exp(-dt / tau0_) : 0.0, f = q_ > 0 ? std::exp(-dt / tau_) : 0.0;
    x_(0) *= f0;
    x_(1) *= f;
    P_(0, 0) = f0 * f0 * P_(0, 0) + q0_ * (1 - f0 * f0);
    P_(1, 1) = f * f * P_(1, 1) + q_ * (1 - f * f);
    P_(0, 1) = P_(1, 0) = f0 * f * P_(0, 1);
  }
  t_prev_ = t;
  S_ = std::max(H_ * P_ * H_.transpose() + r_, 1e-300);
  return S_;
}

double NoiseFilter::mean() const { return H_(0) * x_(0) + H_(1) * x_(1); }

void NoiseFilter::update(double nu) {
  // K = P- H' / S; x+ = x- + K nu; P+ = (I - K H) P-, symmetrised
  const Eigen::Vector2d K = P_ * H_.transpose() / S_;
  x_ += K * nu;
  P_ = (Eigen::Matrix2d::Identity() - K * H_) * P_;
  P_ = 0.5 * (P_ + P_.transpose()).eval();
  started_ = true;
}

namespace {

using Gain = InnovationGain;

// Two doubles in one SSE2 register (GCC's vector extension; element-wise IEEE arithmetic, each
// lane's result what the scalar operation gives), and a lane mask of two.
typedef double v2d __attribute__((vector_size(16)));
typedef long long v2di __attribute__((vector_size(16)));

// Whiten's pass 2 on the B columns of M from column c on, through the gains g:
// x- = Phi x+; nu = m - H x-; x+ = x- + K nu; m = nu / sqrt(S). Each recursion is a chain of
// dependent operations; B of them interleaved overlap in the processor (four at once run about
// as fast as one). Each column's arithmetic is the same whatever B (the same results, bit for bit).
// One frame of it on one column, state (x0, x1): the whitened value (0 for a frame kept out).
inline double whiten_step(const Gain& G, double m, double& x0, double& x1) {
  if (G.skip) return 0;
  if (G.started) x0 *= G.f0, x1 *= G.f;
  const double nu = m - (G.H0 * x0 + 1.0 * x1);
  x0 += G.K0 * nu, x1 += G.K1 * nu;
  return nu / G.sq;
}

// The first frame at which one of the B columns m[k] is not zero (n: none). Before it a column's
// state stays +0 and each whitened value is its input, +0 or -0 (whiten_step: nu = m - 0 keeps
// m's sign, nu / sq too, and x += K nu stays +0; a frame kept out gives +0), so the recursion
// may start there: the same values, bit for bit. (A step's column is zero before its
// time: set_noise whitens a grid of them.)
template <int B>
Eigen::Index first_nonzero(const double* const* m, Eigen::Index n) {
  for (Eigen::Index i = 0; i < n; ++i)
    for (int k = 0; k < B; ++k)
      if (m[k][i] != 0) return i;
  return n;
}

// whiten_step on the B columns src[0 .. B - 1] at once, into dst[0 .. B - 1] (dst = src: in
// place), in pairs (one pair per vector register, an odd last column alone): each lane's
// arithmetic is whiten_step's, the same results bit for bit.
template <int B>
void whiten_columns(const std::vector<Gain>& g, const double* const* src, double* const* dst) {
  constexpr int P = B / 2;
  constexpr bool odd = B % 2 == 1;
  v2d x0[P > 0 ? P : 1] = {}, x1[P > 0 ? P : 1] = {};  // the pairs' states (a, g)
  double y0 = 0, y1 = 0;                               // the odd column's
  const auto n = static_cast<Eigen::Index>(g.size());
  const Eigen::Index i0 = first_nonzero<B>(src, n);
  for (Eigen::Index i = 0; i < i0; ++i) {  // the input itself; a frame kept out whitens to +0 (its input may be -0)
    const bool skip = g[static_cast<std::size_t>(i)].skip;
    for (int k = 0; k < B; ++k) dst[k][i] = skip ? 0.0 : src[k][i];
  }
  for (Eigen::Index i = i0; i < n; ++i) {
    const Gain& G = g[static_cast<std::size_t>(i)];
    if (G.skip) {
      for (int k = 0; k < B; ++k) dst[k][i] = 0;
      continue;
    }
    const v2d f0 = {G.f0, G.f0}, f = {G.f, G.f}, H0 = {G.H0, G.H0}, K0 = {G.K0, G.K0}, K1 = {G.K1, G.K1},
              sq = {G.sq, G.sq};
    for (int p = 0; p < P; ++p) {
      if (G.started) x0[p] *= f0, x1[p] *= f;
      const v2d nu = v2d{src[2 * p][i], src[2 * p + 1][i]} - (H0 * x0[p] + x1[p]);
      x0[p] += K0 * nu, x1[p] += K1 * nu;
      const v2d w = nu / sq;
      dst[2 * p][i] = w[0], dst[2 * p + 1][i] = w[1];
    }
    if (odd) dst[B - 1][i] = whiten_step(G, src[B - 1][i], y0, y1);
  }
}

// Pass 2 on the columns src[0 .. count - 1] (each g.size() long) into dst (dst = src: in
// place), eight at a time (whiten_columns; a lone column's recursion is a chain of dependent
// operations, eight of them keep the processor busy).
void whiten_through(const std::vector<Gain>& g, const double* const* src, double* const* dst, std::size_t count) {
  std::size_t c = 0;
  for (; c + 8 <= count; c += 8) whiten_columns<8>(g, src + c, dst + c);
  switch (count - c) {
    case 7: whiten_columns<7>(g, src + c, dst + c); break;
    case 6: whiten_columns<6>(g, src + c, dst + c); break;
    case 5: whiten_columns<5>(g, src + c, dst + c); break;
    case 4: whiten_columns<4>(g, src + c, dst + c); break;
    case 3: whiten_columns<3>(g, src + c, dst + c); break;
    case 2: whiten_columns<2>(g, src + c, dst + c); break;
    case 1: whiten_columns<1>(g, src + c, dst + c); break;
    default: break;
  }
}

// Pass 2 on every column of M, in place.
void whiten_through(const std::vector<Gain>& g, Eigen::Ref<Eigen::MatrixXd> M) {
  thread_local std::vector<double*> cols;
  cols.resize(static_cast<std::size_t>(M.cols()));
  for (Eigen::Index c = 0; c < M.cols(); ++c) cols[static_cast<std::size_t>(c)] = M.col(c).data();
  whiten_through(g, cols.data(), cols.data(), cols.size());
}

// One column m through the gains of J models (J <= kMaxEach), frame-major: w[i * J + j] under
// model j. Whiten's pass 2 (whiten_step) on each model, the models in pairs (one pair per vector
// register, an odd last one alone; each lane's arithmetic is whiten_step's, bit for bit). The
// models of one table share their frames kept out.
constexpr std::size_t kMaxEach = 16;
template <std::size_t J>
void whiten_each(const std::vector<std::vector<Gain>>& g, const double* m, Eigen::Index n, double* w) {
  constexpr std::size_t P = J / 2;
  v2d x0[P > 0 ? P : 1] = {}, x1[P > 0 ? P : 1] = {};
  double y0 = 0, y1 = 0;  // the odd model's state
  Eigen::Index i0 = 0;  // before the first non-zero value each whitened value is the input (first_nonzero)
  for (; i0 < n && m[i0] == 0; ++i0) {
    const auto ui = static_cast<std::size_t>(i0);
    for (std::size_t j = 0; j < J; ++j) w[ui * J + j] = g[j][ui].skip ? 0.0 : m[i0];  // kept out: +0
  }
  for (Eigen::Index i = i0; i < n; ++i) {
    const auto ui = static_cast<std::size_t>(i);
    double* wi = w + ui * J;
    if (g[0][ui].skip) {
      for (std::size_t j = 0; j < J; ++j) wi[j] = 0;
      continue;
    }
    const v2d mv = {m[i], m[i]};
    for (std::size_t p = 0; p < P; ++p) {
      const Gain& A = g[2 * p][ui];
      const Gain& B = g[2 * p + 1][ui];
      if (A.started) x0[p] *= v2d{A.f0, B.f0}, x1[p] *= v2d{A.f, B.f};
      const v2d nu = mv - (v2d{A.H0, B.H0} * x0[p] + x1[p]);
      x0[p] += v2d{A.K0, B.K0} * nu, x1[p] += v2d{A.K1, B.K1} * nu;
      const v2d wv = nu / v2d{A.sq, B.sq};
      wi[2 * p] = wv[0], wi[2 * p + 1] = wv[1];
    }
    if (J % 2 == 1) wi[J - 1] = whiten_step(g[J - 1][ui], m[i], y0, y1);
  }
}

// A packed frame's flag (GainTable::packed).
constexpr double kPackedSkip = 0, kPackedStarted = 1, kPackedFirst = 2;

// whiten_each on a packed table (pack_gains): each lane's arithmetic is whiten_step's, the same
// values bit for bit.
template <std::size_t J>
void whiten_each_packed(const double* pk, const double* m, Eigen::Index n, double* w) {
  constexpr std::size_t P = (J + 1) / 2, Jp = 2 * P, stride = 4 + 3 * Jp;
  v2d x0[P] = {}, x1[P] = {};
  auto load = [](const double* a) { return v2d{a[0], a[1]}; };
  Eigen::Index i0 = 0;  // before the first non-zero value each whitened value is the input (first_nonzero)
  for (; i0 < n && m[i0] == 0; ++i0) {
    const bool skip = pk[static_cast<std::size_t>(i0) * stride + 3] == kPackedSkip;
    for (std::size_t j = 0; j < J; ++j) w[static_cast<std::size_t>(i0) * J + j] = skip ? 0.0 : m[i0];  // kept out: +0
  }
  for (Eigen::Index i = i0; i < n; ++i) {
    const auto ui = static_cast<std::size_t>(i);
    const double* b = pk + ui * stride;
    double* wi = w + ui * J;
    if (b[3] == kPackedSkip) {
      for (std::size_t j = 0; j < J; ++j) wi[j] = 0;
      continue;
    }
    if (b[3] == kPackedStarted) {
      const v2d f0 = {b[0], b[0]}, f = {b[1], b[1]};
      for (std::size_t p = 0; p < P; ++p) x0[p] *= f0, x1[p] *= f;
    }
    const v2d mv = {m[i], m[i]}, H0 = {b[2], b[2]};
    for (std::size_t p = 0; p < P; ++p) {
      const v2d nu = mv - (H0 * x0[p] + x1[p]);
      x0[p] += load(b + 4 + 2 * p) * nu, x1[p] += load(b + 4 + Jp + 2 * p) * nu;
      const v2d wv = nu / load(b + 4 + 2 * Jp + 2 * p);
      wi[2 * p] = wv[0];
      if (2 * p + 1 < J) wi[2 * p + 1] = wv[1];
    }
  }
}

// whiten_each<J> for J = 1 .. kMaxEach, the models' count fixed at compile time (their states
// stay in registers).
using WhitenEachFn = void (*)(const std::vector<std::vector<Gain>>&, const double*, Eigen::Index, double*);
template <std::size_t... Js>
constexpr std::array<WhitenEachFn, sizeof...(Js)> whiten_each_table(std::index_sequence<Js...>) {
  return {&whiten_each<Js + 1>...};
}
constexpr auto kWhitenEach = whiten_each_table(std::make_index_sequence<kMaxEach>{});
using WhitenPackedFn = void (*)(const double*, const double*, Eigen::Index, double*);
template <std::size_t... Js>
constexpr std::array<WhitenPackedFn, sizeof...(Js)> whiten_packed_table(std::index_sequence<Js...>) {
  return {&whiten_each_packed<Js + 1>...};
}
constexpr auto kWhitenPacked = whiten_packed_table(std::make_index_sequence<kMaxEach>{});

}  // namespace

// One noise model: the batch of one.
void whiten(const std::vector<double>& t, const std::vector<double>& h, const NoiseParams& p,
            const std::vector<char>& skip, Eigen::Ref<Eigen::MatrixXd> M, Eigen::VectorXd* logS) {
  std::vector<Eigen::VectorXd> ls;
  whiten_batch(t, h, {p}, skip, {M}, logS ? &ls : nullptr);
  if (logS) *logS = std::move(ls[0]);
}

namespace {

// whiten_batch's and whitened_grams' input checks.
void check_batch(const std::vector<double>& t, const std::vector<double>& h, const std::vector<NoiseParams>& ps,
                 const std::vector<char>& skip) {
  if (ps.empty()) throw std::invalid_argument("whiten: at least one noise model");
  if (!h.empty() && h.size() != t.size()) throw std::invalid_argument("whiten: gains != number of times");
  if (!skip.empty() && skip.size() != t.size()) throw std::invalid_argument("whiten: skip mask != number of times");
  for (const NoiseParams& p : ps) {
    check_noise_params(p);
    if (p.nom_tau_s != ps[0].nom_tau_s)
      throw std::invalid_argument("whiten: the noise models of one batch must share their nominal correlation time");
  }
}

// sum_i log S_i kept as a product: a mantissa renormalised (frexp) whenever it leaves
// [2^-300, 2^300], and a count of powers of 2. One log per model instead of one per frame (the
// logarithm was a sixth of a noise identification's time); the sum differs from the sum of the
// logs by rounding only (about n eps relative in the product, n eps absolute in the log).
struct LogProduct {
  double m = 1;
  long e2 = 0;
  void add(double S) {
    m *= S;
    if (m > 0x1p300 || m < 0x1p-300) {
      int ex = 0;
      m = std::frexp(m, &ex);
      e2 += ex;
    }
  }
  double log() const { return std::log(m) + static_cast<double>(e2) * std::log(2.0); }
};

// One model's Riccati recursion: its noise parts and the covariance P of its state (a, g).
struct Riccati {
  double q0 = 0, q = 0, r = 0;           // mu s^2, (1 - mu) lambda s^2, (1 - mu) (1 - lambda) s^2
  double P00 = 0, P01 = 0, P10 = 0, P11 = 0;
  Riccati() = default;
  explicit Riccati(const NoiseParams& p)
      : q0(p.nom_share * p.s2), q((1 - p.nom_share) * p.lambda * p.s2), r((1 - p.nom_share) * (1 - p.lambda) * p.s2),
        P00(q0), P11(q) {}  // stationary start

  // One frame with gain h_i = H0 (after a frame that updated the state when `started`, the
  // transitions e0, e from it): every field of G, and S_i returned.
  double step(Gain& G, double H0, bool started, double e0, double e) {
    const double H1 = 1.0;
    G.H0 = H0;
    G.started = started;
    G.skip = false;
    const double f0 = started && q0 > 0 ? e0 : 0.0, f = started && q > 0 ? e : 0.0;
    G.f0 = f0, G.f = f;
    if (started) {
      // x- = Phi x+, P- = Phi P+ Phi + diag(q0 (1 - phi0^2), q (1 - phi^2))
      P00 = f0 * f0 * P00 + q0 * (1 - f0 * f0);
      P11 = f * f * P11 + q * (1 - f * f);
      P01 = P10 = f0 * f * P01;
    }
    // S = H P- H' + r; K = P- H' / S
    const double HP0 = H0 * P00 + H1 * P10, HP1 = H0 * P01 + H1 * P11;
    const double S = std::max(HP0 * H0 + HP1 * H1 + r, 1e-300);
    const double K0 = (P00 * H0 + P01 * H1) / S, K1 = (P10 * H0 + P11 * H1) / S;
    G.K0 = K0, G.K1 = K1;
    G.sq = std::sqrt(S);
    // P+ = (I - K H) P-, symmetrised
    const double A00 = 1 - K0 * H0, A01 = -K0 * H1, A10 = -K1 * H0, A11 = 1 - K1 * H1;
    const double N00 = A00 * P00 + A01 * P10, N01 = A00 * P01 + A01 * P11, N10 = A10 * P00 + A11 * P10,
                 N11 = A10 * P01 + A11 * P11;
    P00 = N00, P11 = N11, P01 = P10 = 0.5 * (N01 + N10);
    return S;
  }
};

// Two models' Riccati recursions in one vector register per quantity (v2d): each lane's
// arithmetic is Riccati::step's, operation for operation (element-wise IEEE arithmetic, and
// SSE2's square root, correctly rounded as std::sqrt): the same gains bit for bit, in about
// half the instructions. (P10 is not kept: Riccati's P01 and P10 are always equal.)
struct RiccatiPair {
  v2d q0, q, r, P00, P01, P11;
  v2di has0, has;  // lanes with a nominal part, with a further part (all bits set)
  RiccatiPair(const Riccati& a, const Riccati& b)
      : q0{a.q0, b.q0}, q{a.q, b.q}, r{a.r, b.r}, P00{a.P00, b.P00}, P01{a.P01, b.P01}, P11{a.P11, b.P11} {
    has0 = q0 > v2d{0, 0}, has = q > v2d{0, 0};
  }

  // Riccati::step on both lanes, e the lanes' transitions; S returned.
  v2d step(Gain& ga, Gain& gb, double H0s, bool started, double e0s, v2d e) {
    const v2d zero = {0, 0}, one = {1, 1}, H0 = {H0s, H0s}, H1 = one, tiny = {1e-300, 1e-300};
    const v2d f0 = started ? (has0 ? v2d{e0s, e0s} : zero) : zero, f = started ? (has ? e : zero) : zero;
    if (started) {
      P00 = f0 * f0 * P00 + q0 * (one - f0 * f0);
      P11 = f * f * P11 + q * (one - f * f);
      P01 = f0 * f * P01;
    }
    const v2d HP0 = H0 * P00 + H1 * P01, HP1 = H0 * P01 + H1 * P11;
    const v2d x = HP0 * H0 + HP1 * H1 + r;
    const v2d S = x < tiny ? tiny : x;  // std::max(x, 1e-300)
    const v2d K0 = (P00 * H0 + P01 * H1) / S, K1 = (P01 * H0 + P11 * H1) / S;
    const v2d sq = _mm_sqrt_pd(S);
    const v2d A00 = one - K0 * H0, A01 = -K0 * H1, A10 = -K1 * H0, A11 = one - K1 * H1;
    const v2d N00 = A00 * P00 + A01 * P01, N01 = A00 * P01 + A01 * P11, N10 = A10 * P00 + A11 * P01,
              N11 = A10 * P01 + A11 * P11;
    P00 = N00, P11 = N11, P01 = 0.5 * (N01 + N10);
    ga.H0 = gb.H0 = H0s;
    ga.started = gb.started = started;
    ga.skip = gb.skip = false;
    ga.f0 = f0[0], gb.f0 = f0[1];
    ga.f = f[0], gb.f = f[1];
    ga.K0 = K0[0], gb.K0 = K0[1];
    ga.K1 = K1[0], gb.K1 = K1[1];
    ga.sq = sq[0], gb.sq = sq[1];
    return S;
  }
};

// The frames of a series and the transitions between them, shared by its models.
struct Frames {
  const std::vector<double>& t;
  const std::vector<double>& h;
  const std::vector<char>& skip;
  double nom_tau_s;              // the models' common nominal correlation time
  const NoiseParams* ps;         // the models (their further part's correlation times tau_s)
  bool any_q0, any_q;            // some model has a nominal part, a further part

  // The models' recursions through the frames, interleaved (each a chain of dependent
  // operations: the processor overlaps them; each model's arithmetic is what it is alone). N > 0:
  // J = N models, their states copied to the stack (off the gains' memory, which the compiler
  // must otherwise assume a gain's store may change); N = 0: any J, in place.
  template <std::size_t... Ps>
  static std::array<RiccatiPair, sizeof...(Ps)> make_pairs(const Riccati* st, std::index_sequence<Ps...>) {
    return {RiccatiPair(st[2 * Ps], st[2 * Ps + 1])...};
  }

  template <std::size_t N>
  void run(Riccati* models, std::size_t J, std::vector<std::vector<Gain>>& g, std::vector<Eigen::VectorXd>* logS,
           std::vector<LogProduct>& prod) const {
    Riccati local[N > 0 ? N : 1];
    Riccati* st = models;
    if (N > 0) {
      for (std::size_t j = 0; j < N; ++j) local[j] = models[j];
      st = local;
    }
    const std::size_t JJ = N > 0 ? N : J;
    // N > 1: the models in pairs (RiccatiPair), an odd last one alone
    constexpr std::size_t NP = N / 2;
    std::array<RiccatiPair, NP> pairs = make_pairs(st, std::make_index_sequence<NP>{});
    const auto n = static_cast<Eigen::Index>(t.size());
    // one transition exp(-dt / tau) per model, computed once per distinct tau: model j takes
    // model same[j]'s, the first of its tau (the grid's shares at one tau share one; a
    // refinement's batch of six has three)
    double e_local[N > 0 ? N : 1] = {};
    std::size_t same_local[N > 0 ? N : 1] = {};
    std::vector<double> e_any(N > 0 ? 0 : JJ, 0.0);
    std::vector<std::size_t> same_any(N > 0 ? 0 : JJ, 0);
    double* e = N > 0 ? e_local : e_any.data();
    std::size_t* same = N > 0 ? same_local : same_any.data();
    for (std::size_t j = 0; j < JJ; ++j) {
      same[j] = j;
      for (std::size_t k = 0; k < j; ++k)
        if (ps[k].tau_s == ps[j].tau_s) {
          same[j] = k;
          break;
        }
    }
    double t_prev = 0, dt_prev = NAN, e0 = 0;
    bool started = false;
    for (Eigen::Index i = 0; i < n; ++i) {
      const auto ui = static_cast<std::size_t>(i);
      if (!skip.empty() && skip[ui]) {  // no sample of the noise process: no update
        for (std::size_t j = 0; j < JJ; ++j) g[j][ui] = Gain{}, g[j][ui].skip = true;
        continue;
      }
      const double H0 = h.empty() ? 1.0 : h[ui];
      if (started) {
        const double dt = t[ui] - t_prev;
        if (dt != dt_prev) {  // regular sampling: the transitions of the last step again
          e0 = any_q0 ? std::exp(-dt / nom_tau_s) : 0.0;
          for (std::size_t j = 0; j < JJ; ++j) e[j] = !any_q ? 0.0 : same[j] < j ? e[same[j]] : std::exp(-dt / ps[j].tau_s);
          dt_prev = dt;
        }
      }
      t_prev = t[ui];
      auto keep = [&](std::size_t j, double S) {
        if (logS) (*logS)[j](i) = std::log(S);
        if (!prod.empty()) prod[j].add(S);
      };
      std::size_t j = 0;
      for (std::size_t p = 0; p < NP; ++p, j += 2) {
        const v2d S = pairs[p].step(g[j][ui], g[j + 1][ui], H0, started, e0, v2d{e[j], e[j + 1]});
        keep(j, S[0]), keep(j + 1, S[1]);
      }
      for (; j < JJ; ++j) keep(j, st[j].step(g[j][ui], H0, started, e0, e[j]));
      started = true;
    }
  }
};

// Frames::run<N> for N = 1 .. kMaxRun (a noise confidence set has any count of models).
constexpr std::size_t kMaxRun = 16;
using RunFn = void (*)(const Frames&, Riccati*, std::size_t, std::vector<std::vector<Gain>>&,
                       std::vector<Eigen::VectorXd>*, std::vector<LogProduct>&);
template <std::size_t N>
void run_n(const Frames& fr, Riccati* models, std::size_t J, std::vector<std::vector<Gain>>& g,
           std::vector<Eigen::VectorXd>* logS, std::vector<LogProduct>& prod) {
  fr.run<N>(models, J, g, logS, prod);
}
template <std::size_t... Ns>
constexpr std::array<RunFn, sizeof...(Ns)> run_table(std::index_sequence<Ns...>) {
  return {&run_n<Ns + 1>...};
}
constexpr auto kRun = run_table(std::make_index_sequence<kMaxRun>{});

// Pass 1, the gains (they depend on the times and h only): per frame the transitions, H0, K and
// sqrt(S), into g[j] for model j. The models' recursions run interleaved (each is a chain of
// dependent operations, the processor overlaps them) and share the transitions exp(-dt / tau):
// each model's arithmetic is what it is alone (the same results, bit for bit). Each model's
// log S_i per frame (logS), or only their sum (sum_logS, as a LogProduct).
void gains(const std::vector<double>& t, const std::vector<double>& h, const std::vector<NoiseParams>& ps,
           const std::vector<char>& skip, std::vector<std::vector<Gain>>& g, std::vector<Eigen::VectorXd>* logS,
           std::vector<double>* sum_logS) {
  const auto n = static_cast<Eigen::Index>(t.size());
  const std::size_t J = ps.size();
  if (logS) {
    logS->resize(J);
    for (Eigen::VectorXd& l : *logS) l.setZero(n);
  }
  std::vector<LogProduct> prod(sum_logS ? J : 0);
  std::vector<Riccati> models(J);
  bool any_q0 = false, any_q = false;
  for (std::size_t j = 0; j < J; ++j) {
    models[j] = Riccati(ps[j]);
    any_q0 = any_q0 || models[j].q0 > 0, any_q = any_q || models[j].q > 0;
  }
  if (g.size() < J) g.resize(J);
  for (std::size_t j = 0; j < J; ++j) g[j].resize(static_cast<std::size_t>(n));  // every field written below
  Frames fr{t, h, skip, ps[0].nom_tau_s, ps.data(), any_q0, any_q};
  // the models' count fixed at compile time up to kMaxRun (their states stay off the gains'
  // memory, in pairs)
  if (J >= 1 && J <= kMaxRun)
    kRun[J - 1](fr, models.data(), J, g, logS, prod);
  else
    fr.run<0>(models.data(), J, g, logS, prod);
  if (sum_logS) {
    sum_logS->resize(J);
    for (std::size_t j = 0; j < J; ++j) (*sum_logS)[j] = prod[j].log();
  }
}

// The Gram matrix W' W of the K columns of M whitened through the gains g (whiten_columns'
// recursion, each whitened value the same bit for bit), accumulated as the rows are whitened:
// W itself is never stored. The columns run in pairs, one pair per vector register (an odd last
// column alone); per frame the products of pairs p <= q accumulate as
// (w_2p w_2q, w_2p+1 w_2q+1) and (w_2p w_2q+1, w_2p+1 w_2q): every entry of the upper triangle
// once (the diagonal pair's second product twice, read once).
template <int K>
void gram_columns(const std::vector<Gain>& g, const Eigen::MatrixXd& M, double* G) {
  constexpr int P = K / 2;           // column pairs
  constexpr bool odd = K % 2 == 1;   // a last column alone
  constexpr int NP = P * (P + 1) / 2;
  const double* m[K];
  for (int k = 0; k < K; ++k) m[k] = M.col(k).data();
  v2d x0[P > 0 ? P : 1] = {}, x1[P > 0 ? P : 1] = {}, same[NP > 0 ? NP : 1] = {}, cross[NP > 0 ? NP : 1] = {},
      last[P > 0 ? P : 1] = {};
  double y0 = 0, y1 = 0, last2 = 0;  // the odd column's state and its square's sum
  const auto n = static_cast<Eigen::Index>(g.size());
  for (Eigen::Index i = 0; i < n; ++i) {
    const Gain& Gi = g[static_cast<std::size_t>(i)];
    if (Gi.skip) continue;  // a zero row
    v2d w[P > 0 ? P : 1];
    const v2d f0 = {Gi.f0, Gi.f0}, f = {Gi.f, Gi.f}, H0 = {Gi.H0, Gi.H0}, K0 = {Gi.K0, Gi.K0}, K1 = {Gi.K1, Gi.K1},
              sq = {Gi.sq, Gi.sq}, one = {1.0, 1.0};
    for (int p = 0; p < P; ++p) {
      if (Gi.started) x0[p] *= f0, x1[p] *= f;
      const v2d mv = {m[2 * p][i], m[2 * p + 1][i]};
      const v2d nu = mv - (H0 * x0[p] + one * x1[p]);
      x0[p] += K0 * nu, x1[p] += K1 * nu;
      w[p] = nu / sq;
    }
    double wl = 0;
    if (odd) {
      if (Gi.started) y0 *= Gi.f0, y1 *= Gi.f;
      const double nu = m[K - 1][i] - (Gi.H0 * y0 + 1.0 * y1);
      y0 += Gi.K0 * nu, y1 += Gi.K1 * nu;
      wl = nu / Gi.sq;
      last2 += wl * wl;
    }
    int a = 0;
    for (int p = 0; p < P; ++p) {
      for (int q = p; q < P; ++q, ++a) {
        const v2d sw = {w[q][1], w[q][0]};
        same[a] += w[p] * w[q];
        cross[a] += w[p] * sw;
      }
      if (odd) last[p] += w[p] * v2d{wl, wl};
    }
  }
  auto set = [&](int r, int c, double v) { G[r * K + c] = G[c * K + r] = v; };
  int a = 0;
  for (int p = 0; p < P; ++p) {
    for (int q = p; q < P; ++q, ++a) {
      set(2 * p, 2 * q, same[a][0]);
      set(2 * p + 1, 2 * q + 1, same[a][1]);
      set(2 * p, 2 * q + 1, cross[a][0]);
      if (q != p) set(2 * p + 1, 2 * q, cross[a][1]);
    }
    if (odd) set(2 * p, K - 1, last[p][0]), set(2 * p + 1, K - 1, last[p][1]);
  }
  if (odd) set(K - 1, K - 1, last2);
}

}  // namespace

// The filter of NoiseFilter written out on scalars, the same operations in the same order, for
// every column at once without temporaries: the gains depend on the times and h alone.
void whiten_batch(const std::vector<double>& t, const std::vector<double>& h, const std::vector<NoiseParams>& ps,
                  const std::vector<char>& skip, const std::vector<Eigen::Ref<Eigen::MatrixXd>>& Ms,
                  std::vector<Eigen::VectorXd>* logS) {
  const auto n = static_cast<Eigen::Index>(t.size());
  const std::size_t J = ps.size();
  if (Ms.size() != J || J == 0) throw std::invalid_argument("whiten: one matrix per noise model, at least one");
  for (const auto& M : Ms)
    if (M.rows() != n) throw std::invalid_argument("whiten: rows != number of times");
  check_batch(t, h, ps, skip);
  // (the tables kept per thread between calls: allocating them on every call, a channel of
  // 2 000 frames made the kernel map and unmap pages for a third of the run's time)
  thread_local std::vector<std::vector<Gain>> g;
  gains(t, h, ps, skip, g, logS, nullptr);
  // Pass 2, each model's columns through its gains.
  for (std::size_t j = 0; j < J; ++j) whiten_through(g[j], Ms[j]);
}

void innovation_gains(const std::vector<double>& t, const std::vector<double>& h, const std::vector<NoiseParams>& ps,
                      const std::vector<char>& skip, GainTable& table) {
  check_batch(t, h, ps, skip);
  table.models = ps;
  table.packed.clear();  // (a table given again: its packing was the gains before)
  gains(t, h, ps, skip, table.gains, nullptr, &table.sum_logS);
  table.gains.resize(ps.size());
}

void whitened_grams(const GainTable& table, const Eigen::MatrixXd& M, std::vector<Eigen::MatrixXd>& grams) {
  const Eigen::Index K = M.cols();
  grams.resize(table.models.size());
  for (std::size_t j = 0; j < table.models.size(); ++j) {
    const std::vector<Gain>& g = table.gains[j];
    if (M.rows() != static_cast<Eigen::Index>(g.size())) throw std::invalid_argument("whiten: rows != number of times");
    Eigen::MatrixXd& G = grams[j];
    G.resize(K, K);
    switch (K) {
      case 1: gram_columns<1>(g, M, G.data()); break;
      case 2: gram_columns<2>(g, M, G.data()); break;
      case 3: gram_columns<3>(g, M, G.data()); break;
      case 4: gram_columns<4>(g, M, G.data()); break;
      case 5: gram_columns<5>(g, M, G.data()); break;
      case 6: gram_columns<6>(g, M, G.data()); break;
      case 7: gram_columns<7>(g, M, G.data()); break;
      case 8: gram_columns<8>(g, M, G.data()); break;
      default: {  // wider: whitened and multiplied
        Eigen::MatrixXd W = M;
        whiten_through(g, W);
        G.setZero();
        G.selfadjointView<Eigen::Lower>().rankUpdate(W.transpose());
        G = G.selfadjointView<Eigen::Lower>();  // symmetric, bit for bit
      }
    }
  }
}

void whiten_each_model(const GainTable& table, const Eigen::Ref<const Eigen::VectorXd>& m, double* w) {
  const std::size_t J = table.gains.size();
  const Eigen::Index n = m.size();
  for (const auto& g : table.gains)
    if (static_cast<Eigen::Index>(g.size()) != n) throw std::invalid_argument("whiten: rows != number of times");
  if (J > kMaxEach) throw std::invalid_argument("whiten: at most " + std::to_string(kMaxEach) + " models at once");
  if (J == 0) return;
  if (!table.packed.empty())
    kWhitenPacked[J - 1](table.packed.data(), m.data(), n, w);
  else
    kWhitenEach[J - 1](table.gains, m.data(), n, w);
}

void pack_gains(GainTable& table) {
  table.packed.clear();
  const std::size_t J = table.gains.size();
  if (J == 0 || J > kMaxEach) return;
  const std::size_t n = table.gains[0].size(), Jp = J + J % 2, stride = 4 + 3 * Jp;
  for (const auto& g : table.gains)
    if (g.size() != n) throw std::logic_error("pack_gains: the models' gains differ in length");
  for (std::size_t i = 0; i < n; ++i) {
    const InnovationGain& G = table.gains[0][i];
    for (std::size_t j = 1; j < J; ++j) {
      const InnovationGain& Gj = table.gains[j][i];
      if (Gj.skip != G.skip || Gj.started != G.started)
        throw std::logic_error("pack_gains: the models differ in the frames they keep out or start at");
      if (!G.skip && G.started && (Gj.f0 != G.f0 || Gj.f != G.f)) return;  // transitions of their own: not packed
    }
  }
  std::vector<double>& pk = table.packed;
  pk.assign(n * stride, 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    double* b = pk.data() + i * stride;
    const InnovationGain& G = table.gains[0][i];
    b[0] = G.f0, b[1] = G.f, b[2] = G.H0;
    b[3] = G.skip ? kPackedSkip : G.started ? kPackedStarted : kPackedFirst;
    for (std::size_t j = 0; j < Jp; ++j) {
      const bool pad = j >= J;
      b[4 + j] = pad ? 0.0 : table.gains[j][i].K0;
      b[4 + Jp + j] = pad ? 0.0 : table.gains[j][i].K1;
      b[4 + 2 * Jp + j] = pad ? 1.0 : table.gains[j][i].sq;
    }
  }
}

void whiten_each_model(const GainTable& table, const Eigen::Ref<const Eigen::VectorXd>& m, std::vector<double>& w) {
  w.resize(static_cast<std::size_t>(m.size()) * table.gains.size());
  whiten_each_model(table, m, w.data());
}

void whiten(const GainTable& table, std::size_t j, Eigen::Ref<Eigen::MatrixXd> M) {
  if (j >= table.gains.size()) throw std::invalid_argument("whiten: no model " + std::to_string(j) + " in the gain table");
  if (M.rows() != static_cast<Eigen::Index>(table.gains[j].size())) throw std::invalid_argument("whiten: rows != number of times");
  whiten_through(table.gains[j], M);
}

void whiten(const GainTable& table, std::size_t j, const std::vector<const double*>& src, const std::vector<double*>& dst) {
  if (j >= table.gains.size()) throw std::invalid_argument("whiten: no model " + std::to_string(j) + " in the gain table");
  if (src.size() != dst.size()) throw std::invalid_argument("whiten: one destination per column");
  whiten_through(table.gains[j], src.data(), dst.data(), src.size());
}

std::size_t GainTable::bytes() const {
  std::size_t b = sizeof(GainTable) + models.size() * sizeof(NoiseParams) + sum_logS.size() * sizeof(double);
  for (const auto& g : gains) b += g.capacity() * sizeof(InnovationGain);
  b += packed.capacity() * sizeof(double);
  return b;
}

double predictive_loglik(const std::vector<double>& t, const std::vector<double>& h, const std::vector<double>& e,
                         const NoiseParams& p, const std::vector<char>& score) {
  if (!h.empty() && h.size() != t.size()) throw std::invalid_argument("predictive_loglik: gains != number of times");
  if (e.size() != t.size()) throw std::invalid_argument("predictive_loglik: residuals != number of times");
  NoiseFilter f(p, h);
  double ll = 0;
  for (std::size_t i = 0; i < e.size(); ++i) {
    // predicted to t_i from the last frame that updated the state (an outlier does not)
    NoiseFilter trial = f;
    const double S = trial.predict(i, t[i]), nu = e[i] - trial.mean();
    const double l_in = -0.5 * (nu * nu / S + std::log(2 * M_PI * S));
    bool outlier = false;
    double l = l_in;
    if (p.p_out > 0) {
      const double So = S + p.s_out2;
      const double l_out = -0.5 * (nu * nu / So + std::log(2 * M_PI * So));
      const double a = std::log1p(-p.p_out) + l_in, b = std::log(p.p_out) + l_out;
      const double m = std::max(a, b);
      l = m + std::log(std::exp(a - m) + std::exp(b - m));
      outlier = b > a;
    }
    if (score.empty() || score[i]) ll += l;
    if (!outlier) {
      trial.update(nu);
      f = trial;
    }
  }
  return ll;
}


}  // namespace rnav

