// The effect-search engine (estimators/model_id) on problems it did not make: reference values
// of its distribution functions, the innovations form against dense GLS, the noise model's
// identification, familywise false alarms under coloured noise from a generator that is not a
// Gauss-Markov process, preference of a physical cause over a scanned one, and outliers.
#include "estimators/model_id/effect_search.hpp"
#include "estimators/model_id/generation_store.hpp"
#include "estimators/model_id/gram_memo.hpp"
#include "estimators/model_id/injected_limits.hpp"
#include "estimators/model_id/ladder_curve.hpp"
#include "estimators/model_id/noise_id.hpp"
#include "estimators/model_id/noise_memo.hpp"
#include "estimators/model_id/parallel_for.hpp"
#include "estimators/model_id/progress_clock.hpp"
#include "estimators/model_id/search_design.hpp"
#include "test/coloured_noise.hpp"
#include "estimators/model_id/shown_unit.hpp"
#include "estimators/model_id/stats.hpp"
#include "test/stat_bands.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cmath>
#include <mutex>
#include <random>
#include <set>
#include <thread>
#include <tuple>

using namespace rnav;
using rnav::test::CascadeNoise;
using rnav::test::cascade_norm;

TEST_CASE("stats: reference values") {
  CHECK(chi2_sf(3.841458820694124, 1) == Approx(0.05).epsilon(1e-10));
  CHECK(chi2_sf(9.21034037197618, 2) == Approx(0.01).epsilon(1e-10));
  // chi2(2) tail is exp(-x/2): the log tail stays exact where the tail underflows
  CHECK(log_chi2_sf(3000, 2) == Approx(-1500).epsilon(1e-12));
  CHECK(normal_upper_quantile(0.025) == Approx(1.959963984540054).epsilon(1e-12));
  CHECK(z_two_sided(0.01) == Approx(2.5758293035489).epsilon(1e-12));
  const Interval a = clopper_pearson(0, 10, 0.95);
  CHECK(a.lo == 0);
  CHECK(a.hi == Approx(1 - std::pow(0.025, 0.1)).epsilon(1e-9));
  const Interval b = clopper_pearson(5, 10, 0.95);  // tables: 0.1871, 0.8129
  CHECK(b.lo == Approx(0.187086).epsilon(1e-5));
  CHECK(b.hi == Approx(0.812914).epsilon(1e-5));
  CHECK(poisson_upper_tail(3, 1.0) == Approx(1 - std::exp(-1.0) * 2.5).epsilon(1e-12));
}

TEST_CASE("stats: DerSimonian-Laird pooling against values worked by hand") {
  // b = (0, 1, 3), v = (1, 0.5, 2): w = (1, 2, 0.5), m_w = 3.5 / 3.5 = 1, Q = 1 + 0 + 0.5 * 4 = 3,
  // tau^2 = (3 - 2) / (3.5 - 5.25 / 3.5) = 0.5, w* = (1/1.5, 1, 1/2.5): sum 31/15, mean 2.2 / (31/15)
  const RandomEffects r = dersimonian_laird({0, 1, 3}, {1, 0.5, 2});
  CHECK(r.fixed_mean == Approx(1).epsilon(1e-14));
  CHECK(r.q == Approx(3).epsilon(1e-14));
  CHECK(r.tau2 == Approx(0.5).epsilon(1e-14));
  CHECK(r.sum_w == Approx(31.0 / 15).epsilon(1e-14));
  CHECK(r.mean == Approx(33.0 / 31).epsilon(1e-14));
  // Q below its degrees of freedom: no between-estimate variance, the fixed-effect mean
  const RandomEffects h = dersimonian_laird({1, 1.1, 0.9}, {1, 1, 1});
  CHECK(h.tau2 == 0);
  CHECK(h.mean == Approx(1).epsilon(1e-14));
  CHECK_THROWS_AS(dersimonian_laird({1}, {1}), std::invalid_argument);
  CHECK_THROWS_AS(dersimonian_laird({1, 2}, {1, 0}), std::invalid_argument);
  CHECK_THROWS_AS(dersimonian_laird({1, 2}, {1, std::nan("")}), std::invalid_argument);
}

namespace {
// The whitening tests' series: eleven irregular frames with a gap, and a nominal component's
// gains growing along them.
const std::vector<double> kWhitenT = {0, 0.3, 0.9, 1.0, 1.7, 4.0, 4.2, 4.9, 5.5, 6.0, 6.4};
const std::vector<double> kWhitenH = {0.4, 0.5, 0.6, 0.65, 0.8, 1.0, 1.1, 1.3, 1.6, 2.5, 2.6};
}  // namespace

TEST_CASE("noise model: whitened columns are the same, bit for bit, however many are whitened together") {
  // whiten() runs its columns through the filter several at a time (interleaved recursions); each
  // column's arithmetic must be what it is alone: 1 to 17 columns (two blocks of eight and every
  // remainder), a skipped frame, a gain; and the same columns given by where they start.
  const std::vector<double>& t = kWhitenT;
  const std::vector<double>& h = kWhitenH;
  const std::vector<char> skip = {0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0};
  NoiseParams p;
  p.s2 = 2.0, p.lambda = 0.7, p.tau_s = 1.5, p.nom_share = 0.35, p.nom_tau_s = 5.0;
  const auto n = static_cast<Eigen::Index>(t.size());
  GainTable table;
  innovation_gains(t, h, {p}, skip, table);
  for (Eigen::Index cols = 1; cols <= 17; ++cols) {
    Eigen::MatrixXd M(n, cols);
    for (Eigen::Index i = 0; i < n; ++i)
      for (Eigen::Index c = 0; c < cols; ++c) M(i, c) = std::sin(0.7 * static_cast<double>(i) + static_cast<double>(c)) + 0.1 * c;
    Eigen::MatrixXd together = M;
    whiten(t, h, p, skip, together);
    Eigen::MatrixXd pointed = M, into(n, cols);  // the columns in reverse order, by pointer: in place, and into another matrix
    std::vector<const double*> from;
    std::vector<double*> starts, to;
    for (Eigen::Index c = cols - 1; c >= 0; --c) {
      from.push_back(pointed.col(c).data()), starts.push_back(pointed.col(c).data());
      to.push_back(into.col(c).data());
    }
    whiten(table, 0, from, to);
    whiten(table, 0, from, starts);
    for (Eigen::Index c = 0; c < cols; ++c) {
      Eigen::MatrixXd alone = M.col(c);
      whiten(t, h, p, skip, alone);
      INFO(cols << " columns, column " << c);
      CHECK((alone.col(0).array() == together.col(c).array()).all());
      CHECK((alone.col(0).array() == pointed.col(c).array()).all());
      CHECK((alone.col(0).array() == into.col(c).array()).all());
    }
  }
  std::vector<const double*> none;
  std::vector<double*> one = {nullptr};
  CHECK_THROWS_WITH(whiten(table, 1, none, {}), Catch::Contains("no model 1"));
  CHECK_THROWS_WITH(whiten(table, 0, none, one), Catch::Contains("one destination per column"));
}

TEST_CASE("noise model: whiten_batch gives each model what whiten gives it alone, bit for bit") {
  // The REML grid whitens under its shares lambda at one tau at once (interleaved recursions,
  // shared transitions): each model's columns and log S must be whiten()'s exactly, including a
  // white share (lambda 0, no transition of its own) beside correlated ones, and a model without
  // the nominal component beside ones with it.
  const std::vector<double>& t = kWhitenT;
  const std::vector<double>& h = kWhitenH;
  const std::vector<char> skip = {0, 0, 1, 0, 0, 0, 0, 0, 0, 0, 0};
  const auto n = static_cast<Eigen::Index>(t.size());
  std::vector<NoiseParams> ps;
  for (double lam : {0.0, 0.3, 0.9, 0.995})
    for (double mu : {0.0, 0.35}) {
      NoiseParams p;
      p.s2 = 1.5, p.lambda = lam, p.tau_s = 2.5, p.nom_share = mu, p.nom_tau_s = 5.0;
      ps.push_back(p);
    }
  Eigen::MatrixXd M(n, 6);
  for (Eigen::Index i = 0; i < n; ++i)
    for (Eigen::Index c = 0; c < M.cols(); ++c) M(i, c) = std::cos(0.9 * static_cast<double>(i) - static_cast<double>(c)) + 0.2 * c;
  std::vector<Eigen::MatrixXd> Ws(ps.size(), M);
  std::vector<Eigen::Ref<Eigen::MatrixXd>> refs;
  for (auto& W : Ws) refs.emplace_back(W);
  std::vector<Eigen::VectorXd> logs;
  whiten_batch(t, h, ps, skip, refs, &logs);
  REQUIRE(logs.size() == ps.size());
  for (std::size_t j = 0; j < ps.size(); ++j) {
    Eigen::MatrixXd alone = M;
    Eigen::VectorXd logS;
    whiten(t, h, ps[j], skip, alone, &logS);
    INFO("model " << j << ": lambda " << ps[j].lambda << ", mu " << ps[j].nom_share);
    CHECK((alone.array() == Ws[j].array()).all());
    CHECK((logS.array() == logs[j].array()).all());
  }
  // models of different correlation times tau in one batch (a refinement's): each what it
  // gives alone, bit for bit (a transition of one model's tau given to another fails this)
  NoiseParams other = ps[1];
  other.tau_s = 3.0;
  std::vector<Eigen::MatrixXd> two(2, M);
  std::vector<Eigen::Ref<Eigen::MatrixXd>> two_refs(two.begin(), two.end());
  whiten_batch(t, h, {ps[1], other}, skip, two_refs);
  for (std::size_t j = 0; j < 2; ++j) {
    Eigen::MatrixXd alone = M;
    whiten(t, h, j == 0 ? ps[1] : other, skip, alone);
    INFO("model " << j << " of two with different tau");
    CHECK((alone.array() == two[j].array()).all());
  }
  // models that do not share their nominal correlation time, or a matrix per model missing: refused
  NoiseParams other_nominal = ps[1];
  other_nominal.nom_share = 0.3, other_nominal.nom_tau_s = ps[1].nom_tau_s + 1.0;
  CHECK_THROWS_WITH(whiten_batch(t, h, {ps[1], other_nominal}, skip, two_refs), Catch::Contains("nominal correlation time"));
  CHECK_THROWS_WITH(whiten_batch(t, h, {ps[1]}, skip, two_refs), Catch::Contains("one matrix per noise model"));
}

TEST_CASE("noise model: whitened_grams is W' W of whiten_batch's W, and its log S sum theirs") {
  // The REML computes from the Gram matrix accumulated while whitening, never forming W: each
  // entry must be W' W's to rounding (the same whitened values, summed in another order: a
  // relative 1e-13 is some 100 times the rounding of 11 terms), and the sum of log S, kept as
  // one product, the sum of the logs to 1e-13 absolute. Widths 1 to 10 cover the unrolled
  // kernels (1-8) and the general one; a skipped frame and a model without correlated part too.
  const std::vector<double>& t = kWhitenT;
  const std::vector<double>& h = kWhitenH;
  const std::vector<char> skip = {0, 0, 0, 0, 1, 0, 0, 0, 0, 0, 0};
  const auto n = static_cast<Eigen::Index>(t.size());
  std::vector<NoiseParams> ps;
  for (double lam : {0.0, 0.6, 0.98}) {
    NoiseParams p;
    p.s2 = 1.0, p.lambda = lam, p.tau_s = 1.2, p.nom_share = 0.3, p.nom_tau_s = 4.0;
    ps.push_back(p);
  }
  GainTable table;
  innovation_gains(t, h, ps, skip, table);
  REQUIRE(table.sum_logS.size() == ps.size());
  for (Eigen::Index cols = 1; cols <= 10; ++cols) {
    Eigen::MatrixXd M(n, cols);
    for (Eigen::Index i = 0; i < n; ++i)
      for (Eigen::Index c = 0; c < cols; ++c) M(i, c) = std::sin(1.3 * static_cast<double>(i) * (1 + 0.1 * c) + static_cast<double>(c));
    std::vector<Eigen::MatrixXd> grams;
    whitened_grams(table, M, grams);
    for (std::size_t j = 0; j < ps.size(); ++j) {
      Eigen::MatrixXd W = M;
      Eigen::VectorXd logS;
      whiten(t, h, ps[j], skip, W, &logS);
      const Eigen::MatrixXd G = W.transpose() * W;
      INFO(cols << " columns, model " << j);
      CHECK((grams[j] - G).cwiseAbs().maxCoeff() <= 1e-13 * G.cwiseAbs().maxCoeff());
      CHECK(grams[j] == grams[j].transpose());
      CHECK(std::abs(table.sum_logS[j] - logS.sum()) < 1e-13);
    }
  }
  Eigen::MatrixXd wrong(n - 1, 2);
  std::vector<Eigen::MatrixXd> grams;
  CHECK_THROWS_WITH(whitened_grams(table, wrong, grams), Catch::Contains("rows != number of times"));
}

namespace {
// Models of one correlation time for the gain tables below: shares lambda (nominal share 0.3).
std::vector<NoiseParams> models_at(std::initializer_list<double> lambdas) {
  std::vector<NoiseParams> ps;
  for (double lam : lambdas) {
    NoiseParams p;
    p.s2 = 1.0, p.lambda = lam, p.tau_s = 1.2, p.nom_share = 0.3, p.nom_tau_s = 4.0;
    ps.push_back(p);
  }
  return ps;
}
}  // namespace

TEST_CASE("noise model: a column that starts with zeros is whitened as the full recursion whitens it, bit for bit") {
  // The filter starts at a column's first non-zero frame (the state is +0 before it and each
  // whitened value is its input): a step's column, zero before its time, must get exactly what
  // the recursion from frame 0 gives, -0 inputs and a frame kept out among the zeros included.
  // The reference: the column whitened beside one that is not zero at frame 0 (no frame skipped
  // then; columns whitened together are whitened as alone, by the test above).
  const std::vector<char> skip = {0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0};
  const auto n = static_cast<Eigen::Index>(kWhitenT.size());
  NoiseParams p;
  p.s2 = 2.0, p.lambda = 0.7, p.tau_s = 1.5, p.nom_share = 0.35, p.nom_tau_s = 5.0;
  for (Eigen::Index start : {Eigen::Index{0}, Eigen::Index{3}, Eigen::Index{7}, n}) {
    Eigen::MatrixXd pair(n, 2);
    for (Eigen::Index i = 0; i < n; ++i) {
      pair(i, 0) = i < start ? (i % 2 == 1 ? -0.0 : 0.0) : 1.0 + 0.1 * static_cast<double>(i);
      pair(i, 1) = std::cos(0.3 * static_cast<double>(i)) + 2;
    }
    Eigen::MatrixXd alone = pair.col(0);
    Eigen::MatrixXd beside = pair;
    whiten(kWhitenT, kWhitenH, p, skip, alone);
    whiten(kWhitenT, kWhitenH, p, skip, beside);
    INFO("first non-zero frame " << start);
    for (Eigen::Index i = 0; i < n; ++i) {
      CHECK(alone(i, 0) == beside(i, 0));
      CHECK(std::signbit(alone(i, 0)) == std::signbit(beside(i, 0)));
    }
    // under each of several models at once
    GainTable table;
    innovation_gains(kWhitenT, kWhitenH, models_at({0.0, 0.5, 0.9}), skip, table);
    std::vector<double> w;
    whiten_each_model(table, pair.col(0), w);
    for (std::size_t j = 0; j < table.models.size(); ++j) {
      Eigen::MatrixXd ref = pair;
      whiten(table, j, ref);
      for (Eigen::Index i = 0; i < n; ++i) {
        const double x = w[static_cast<std::size_t>(i) * table.models.size() + j];
        CHECK(x == ref(i, 0));
        CHECK(std::signbit(x) == std::signbit(ref(i, 0)));
      }
    }
  }
}

TEST_CASE("noise model: whiten_each_model gives whiten()'s values under each model, bit for bit") {
  // Frame-major, the models' recursions interleaved: the arithmetic of each model must still be
  // whiten()'s (GramMemo's sums rely on it). One model, seven (the grid's and the refinement's
  // counts) and three; a skipped frame is whitened to 0.
  const std::vector<char> skip = {0, 0, 0, 1, 0, 0, 0, 0, 0, 0, 0};
  const auto n = static_cast<Eigen::Index>(kWhitenT.size());
  Eigen::VectorXd m(n);
  for (Eigen::Index i = 0; i < n; ++i) m(i) = std::sin(0.7 * static_cast<double>(i)) + 0.1 * static_cast<double>(i);
  for (const auto& ps : {models_at({0.5}), models_at({0.0, 0.3, 0.6, 0.8, 0.9, 0.98, 0.995}), models_at({0.2, 0.7, 0.9})}) {
    GainTable table;
    innovation_gains(kWhitenT, kWhitenH, ps, skip, table);
    std::vector<double> w;
    whiten_each_model(table, m, w);
    REQUIRE(w.size() == static_cast<std::size_t>(n) * ps.size());
    for (std::size_t j = 0; j < ps.size(); ++j) {
      Eigen::MatrixXd alone = m;
      whiten(table, j, alone);
      INFO(ps.size() << " models, model " << j);
      for (Eigen::Index i = 0; i < n; ++i) CHECK(w[static_cast<std::size_t>(i) * ps.size() + j] == alone(i, 0));
    }
  }
  GainTable table;
  innovation_gains(kWhitenT, kWhitenH, models_at({0.5}), skip, table);
  std::vector<double> w;
  CHECK_THROWS_WITH(whiten_each_model(table, Eigen::VectorXd::Zero(n - 1), w), Catch::Contains("rows != number of times"));
}

TEST_CASE("noise model: a packed gain table whitens as the unpacked one, bit for bit") {
  // pack_gains lays a table's gains out frame by frame in pairs of models for the grid's
  // whitening (whiten_each_model reads the packing when there is one): every value must be the
  // unpacked table's, with one model, an even and an odd count (a padding model), frames kept
  // out, and a column that starts with zeros (-0 among them). Models with transitions of their
  // own (another tau) are not packed; a table computed again drops its packing.
  const std::vector<char> skip = {0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0};
  const auto n = static_cast<Eigen::Index>(kWhitenT.size());
  Eigen::VectorXd m(n), lead(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    m(i) = std::sin(0.7 * static_cast<double>(i)) + 0.1 * static_cast<double>(i);
    lead(i) = i < 5 ? (i % 2 == 1 ? -0.0 : 0.0) : m(i);
  }
  for (const auto& ps : {models_at({0.5}), models_at({0.3, 0.6, 0.8, 0.9, 0.95, 0.98}),
                         models_at({0.3, 0.6, 0.8, 0.9, 0.95, 0.98, 0.995})}) {
    GainTable plain, packed;
    innovation_gains(kWhitenT, kWhitenH, ps, skip, plain);
    innovation_gains(kWhitenT, kWhitenH, ps, skip, packed);
    pack_gains(packed);
    REQUIRE(!packed.packed.empty());
    for (const Eigen::VectorXd* col : {&m, &lead}) {
      std::vector<double> a, b;
      whiten_each_model(plain, *col, a);
      whiten_each_model(packed, *col, b);
      REQUIRE(a.size() == b.size());
      INFO(ps.size() << " models" << (col == &lead ? ", leading zeros" : ""));
      for (std::size_t k = 0; k < a.size(); ++k) {
        CHECK(a[k] == b[k]);
        CHECK(std::signbit(a[k]) == std::signbit(b[k]));
      }
    }
    innovation_gains(kWhitenT, kWhitenH, ps, skip, packed);
    CHECK(packed.packed.empty());
  }
  std::vector<NoiseParams> mixed = models_at({0.5, 0.8});
  mixed[1].tau_s = 3.0;
  GainTable own;
  innovation_gains(kWhitenT, kWhitenH, mixed, skip, own);
  pack_gains(own);
  CHECK(own.packed.empty());
}

// n frame times dt apart moved by wobble sin(i) (irregular sampling) and gains h0 + dh i.
std::pair<std::vector<double>, std::vector<double>> wobbly_frames(Eigen::Index n, double dt, double wobble, double h0,
                                                                  double dh) {
  std::vector<double> t, h;
  for (Eigen::Index i = 0; i < n; ++i) {
    t.push_back(dt * static_cast<double>(i) + wobble * std::sin(static_cast<double>(i)));
    h.push_back(h0 + dh * static_cast<double>(i));
  }
  return {t, h};
}

TEST_CASE("gram memo: its Gram matrices are whitened_grams', bit for bit, whether computed or read") {
  // The landing diagnosis's likelihoods come from these matrices; a memo that changed one bit
  // would change its reports. Each width 1-8 (whitened_grams' unrolled kernels, whose sums
  // GramMemo's must repeat in the same order), with 7 models (two per register, the last alone)
  // and 3; then the
  // same matrices with one column changed (the others' entries read, the new ones computed), a
  // column twice, and a memo so small that its generations turn on every call.
  // The memo serves series of kMinFrames frames and more: irregular times, gains h, two frames
  // kept out.
  const Eigen::Index n = GramMemo::kMinFrames + 40;
  const auto [t, h] = wobbly_frames(n, 0.5, 0.2, 0.5, 0.002);
  std::vector<char> skip(static_cast<std::size_t>(n), 0);
  skip[4] = skip[100] = 1;
  for (const auto& ps : {models_at({0.0, 0.3, 0.6, 0.8, 0.9, 0.98, 0.995}), models_at({0.2, 0.7, 0.9})}) {
    GainTable table;
    innovation_gains(t, h, ps, skip, table);
    const GramMemo::Key table_key{ps.size(), 17};  // any key naming this table
    GramMemo memo(std::size_t{1} << 20), tiny(1);
    for (Eigen::Index cols = 1; cols <= GramMemo::kMaxColumns; ++cols) {
      Eigen::MatrixXd M(n, cols);
      for (Eigen::Index i = 0; i < n; ++i)
        for (Eigen::Index c = 0; c < cols; ++c) M(i, c) = std::sin(1.3 * static_cast<double>(i) * (1 + 0.1 * c) + static_cast<double>(c));
      Eigen::MatrixXd changed = M, twice = M;
      changed.col(cols - 1) *= 1.7;
      twice.col(0) = M.col(cols - 1);
      for (const Eigen::MatrixXd* X : {&M, &changed, &twice}) {
        std::vector<GramMemo::Key> keys;
        for (Eigen::Index c = 0; c < cols; ++c) keys.push_back(GramMemo::column_key(*X, c));
        std::vector<Eigen::MatrixXd> expected, got, got_tiny;
        whitened_grams(table, *X, expected);
        const std::size_t read_before = memo.entries_read();
        memo.grams(table, table_key, *X, keys, got);
        tiny.grams(table, table_key, *X, keys, got_tiny);
        INFO(ps.size() << " models, " << cols << " columns, matrix " << (X == &M ? "first" : X == &changed ? "changed" : "twice"));
        if (X == &changed && cols > 1) CHECK(memo.entries_read() > read_before);  // the unchanged columns' entries
        REQUIRE(got.size() == ps.size());
        for (std::size_t j = 0; j < ps.size(); ++j) {
          CHECK((got[j].array() == expected[j].array()).all());
          CHECK((got_tiny[j].array() == expected[j].array()).all());
        }
      }
    }
    // refused: too wide, too short, a key missing
    Eigen::MatrixXd wide = Eigen::MatrixXd::Ones(n, GramMemo::kMaxColumns + 1);
    std::vector<GramMemo::Key> keys(static_cast<std::size_t>(wide.cols()));
    std::vector<Eigen::MatrixXd> got;
    CHECK_FALSE(GramMemo::serves(table, wide));
    CHECK(GramMemo::serves(table, wide.leftCols(3)));
    CHECK_FALSE(GramMemo::serves(table, wide.topLeftCorner(GramMemo::kMinFrames - 1, 3)));
    CHECK_THROWS_WITH(memo.grams(table, table_key, wide, keys, got), Catch::Contains("are served"));
    keys.resize(2);
    CHECK_THROWS_WITH(memo.grams(table, table_key, wide.leftCols(3), keys, got), Catch::Contains("one key per column"));
  }
}

TEST_CASE("gram memo: a grid's Gram matrices are grams()' per table, bit for bit, computed or read", "[model_id][memo]") {
  // The noise identification's grid asks for 28 tables at once (one lookup per pair of columns
  // instead of 28): every matrix must be what grams() gives table by table, when its entries
  // are computed, read, or partly read (one column changed), with a memo whose generations turn
  // on every call (missing entries that share a column are summed in one pass, each as alone);
  // a table of another model count is refused.
  const Eigen::Index n = GramMemo::kMinFrames + 25;
  const auto [t, h] = wobbly_frames(n, 0.4, 0.1, 0.8, 0.001);
  std::vector<char> skip(static_cast<std::size_t>(n), 0);
  skip[9] = 1;
  const std::vector<double> taus = {0.3, 2.0, 11.0, 60.0};
  std::vector<GainTable> tables(taus.size());
  for (std::size_t i = 0; i < taus.size(); ++i) {
    std::vector<NoiseParams> ps = models_at({0.0, 0.3, 0.6, 0.8, 0.9, 0.95, 0.995});  // the grid's count: pairs and one alone
    for (NoiseParams& p : ps) p.tau_s = taus[i];
    innovation_gains(t, h, ps, skip, tables[i]);
  }
  std::size_t asked = 0;
  const GramMemo::TableOf table_of = [&](std::size_t i) {
    ++asked;
    return std::make_pair(GramMemo::Key{i, 5}, static_cast<const GainTable*>(&tables[i]));
  };
  Eigen::MatrixXd M(n, 5);
  for (Eigen::Index i = 0; i < n; ++i)
    for (Eigen::Index c = 0; c < M.cols(); ++c) M(i, c) = std::cos(0.7 * static_cast<double>(i) * (1 + 0.2 * c) + static_cast<double>(c));
  Eigen::MatrixXd changed = M;
  changed.col(2) *= -1.3;
  GramMemo memo(std::size_t{1} << 22), tiny(1), each(std::size_t{1} << 22);
  int pass = 0;
  for (const Eigen::MatrixXd* X : {&M, &M, &changed}) {
    ++pass;
    std::vector<GramMemo::Key> keys;
    for (Eigen::Index c = 0; c < X->cols(); ++c) keys.push_back(GramMemo::column_key(*X, c));
    std::vector<std::vector<Eigen::MatrixXd>> got, got_tiny;
    asked = 0;
    const std::size_t read_before = memo.entries_read();
    memo.grid_grams(taus.size(), table_of, {77, 1}, *X, keys, got);
    const std::size_t asked_memo = asked;
    tiny.grid_grams(taus.size(), table_of, {77, 1}, *X, keys, got_tiny);
    INFO("matrix " << (X == &changed ? "changed" : "first or again"));
    if (X == &changed) CHECK(memo.entries_read() > read_before);  // the unchanged columns' pairs
    REQUIRE(got.size() == taus.size());
    for (std::size_t i = 0; i < taus.size(); ++i) {
      std::vector<Eigen::MatrixXd> expected;
      each.grams(tables[i], GramMemo::Key{i, 5}, *X, keys, expected);
      REQUIRE(got[i].size() == expected.size());
      for (std::size_t j = 0; j < expected.size(); ++j) {
        CHECK((got[i][j].array() == expected[j].array()).all());
        CHECK((got_tiny[i][j].array() == expected[j].array()).all());
      }
    }
    if (pass == 2) {  // the same matrix again: its 15 pairs read, no table asked for
      CHECK(memo.entries_read() == read_before + 15);
      CHECK(asked_memo == 0);
    } else {
      CHECK(asked_memo == taus.size());  // entries missing: each table asked for once
    }
  }
  // a grid whose tables differ in their count of models: refused
  GainTable two;
  innovation_gains(t, h, models_at({0.3, 0.8}), skip, two);
  const GramMemo::TableOf mixed = [&](std::size_t i) {
    return std::make_pair(GramMemo::Key{i, 9}, static_cast<const GainTable*>(i == 0 ? &tables[0] : &two));
  };
  std::vector<GramMemo::Key> keys;
  for (Eigen::Index c = 0; c < M.cols(); ++c) keys.push_back(GramMemo::column_key(M, c));
  std::vector<std::vector<Eigen::MatrixXd>> got;
  CHECK_THROWS_WITH(GramMemo(1 << 20).grid_grams(2, mixed, {78, 1}, M, keys, got), Catch::Contains("differ in their count"));
}

TEST_CASE("parallel_for: each index once, nested calls, the lowest index's error, helpers kept between calls") {
  // Each index once, also with calls nested inside (a call that finds no idle helper starts one,
  // so nested calls cannot wait for each other).
  std::vector<std::atomic<int>> seen(40);
  parallel_for(seen.size(), 2, [&](std::size_t i) {
    parallel_for(3, 2, [&](std::size_t) { ++seen[i]; });
  });
  for (std::size_t i = 0; i < seen.size(); ++i) CHECK(seen[i] == 3);
  // The error of the lowest index, whatever the scheduling.
  for (int rep = 0; rep < 20; ++rep)
    CHECK_THROWS_WITH(parallel_for(6, 3, [](std::size_t i) { if (i >= 2) throw std::runtime_error("index " + std::to_string(i)); }),
                      "index 2");
  // A helper keeps what it keeps per thread between calls (why the pool exists: a noise
  // identification's gain tables and Gram entries). Two indices that wait for each other run on
  // two threads: this one and a helper; the helper's thread-local count of its calls reaches 2
  // in the second call only if it is the same thread (a thread started per call counts 1).
  thread_local int calls_here = 0;
  const auto main_id = std::this_thread::get_id();
  int helper_calls = 0;
  for (int call = 0; call < 2; ++call) {
    std::mutex m;
    std::condition_variable cv;
    int arrived = 0;
    parallel_for(2, 2, [&](std::size_t) {
      std::unique_lock<std::mutex> lock(m);
      ++calls_here;
      if (std::this_thread::get_id() != main_id) helper_calls = calls_here;
      ++arrived;
      cv.notify_all();
      cv.wait(lock, [&] { return arrived == 2; });
    });
  }
  CHECK(helper_calls == 2);
}

TEST_CASE("kept values: a value used since the last turn stays, one unused for two turns goes") {
  // GenerationStore's two generations: budget 100 B, so the young one turns once it would pass 50 B.
  GenerationStore<int> store(100);
  auto key = [](int i) { return GenerationStore<int>::Key{static_cast<std::uint64_t>(i), 1}; };
  for (int i = 0; i < 5; ++i) store.insert(key(i), i, 10);  // young: 0-4 (50 B)
  CHECK(store.bytes() == 50);
  store.insert(key(5), 5, 10);  // a turn: 0-4 old, 5 young
  REQUIRE(store.find(key(1)) != nullptr);  // used: back into the young generation
  CHECK(*store.find(key(1)) == 1);
  CHECK(store.insert(key(1), 99, 10) == 1);  // a key kept keeps its value
  for (int i = 6; i < 9; ++i) store.insert(key(i), i, 10);  // young: 5, 1, 6, 7, 8 (50 B)
  store.insert(key(9), 9, 10);  // a turn: the old 0, 2, 3, 4 go
  CHECK(store.find(key(0)) == nullptr);
  CHECK(store.find(key(4)) == nullptr);
  CHECK(store.find(key(1)) != nullptr);
  CHECK(store.find(key(8)) != nullptr);
  CHECK(store.size() == 6);
  CHECK(store.bytes() == 60);
}

namespace {
// The noise model's covariance built densely (noise_model.hpp):
// C_ij = mu s2 h_i h_j exp(-|dt| / tau0) + (1 - mu) lambda s2 exp(-|dt| / tau) + delta_ij (1 - mu)(1 - lambda) s2
Eigen::MatrixXd dense_cov(const std::vector<double>& t, const std::vector<double>& h, const NoiseParams& p) {
  const auto n = static_cast<Eigen::Index>(t.size());
  Eigen::MatrixXd C(n, n);
  for (Eigen::Index i = 0; i < n; ++i)
    for (Eigen::Index j = 0; j < n; ++j) {
      const double dt = std::abs(t[i] - t[j]);
      const double hi = h.empty() ? 1.0 : h[i], hj = h.empty() ? 1.0 : h[j];
      C(i, j) = p.nom_share * p.s2 * hi * hj * std::exp(-dt / p.nom_tau_s) +
                (1 - p.nom_share) * p.lambda * p.s2 * std::exp(-dt / p.tau_s) +
                (i == j ? (1 - p.nom_share) * (1 - p.lambda) * p.s2 : 0.0);
    }
  return C;
}

// Whitening gives the GLS estimate and log det C, and the predictive log-likelihood is the
// Gaussian density, against the dense covariance (exact up to rounding).
void check_against_dense(const std::vector<double>& t, const std::vector<double>& h, const NoiseParams& p) {
  const auto n = static_cast<Eigen::Index>(t.size());
  const Eigen::MatrixXd C = dense_cov(t, h, p);
  Eigen::MatrixXd X(n, 2);
  Eigen::VectorXd y(n);
  for (Eigen::Index i = 0; i < n; ++i) X(i, 0) = 1, X(i, 1) = t[i], y(i) = std::sin(t[i]) + 0.1 * i;
  const Eigen::MatrixXd Ci = C.inverse();
  const Eigen::VectorXd beta_gls = (X.transpose() * Ci * X).ldlt().solve(X.transpose() * Ci * y);
  Eigen::MatrixXd W(n, 3);
  W << X, y;
  Eigen::VectorXd logS;
  whiten(t, h, p, {}, W, &logS);
  const Eigen::VectorXd beta_w = W.leftCols(2).colPivHouseholderQr().solve(W.col(2));
  CHECK((beta_w - beta_gls).norm() < 1e-10 * beta_gls.norm());
  CHECK(logS.sum() == Approx(std::log(C.determinant())).epsilon(1e-10));
  const std::vector<double> e(y.data(), y.data() + n);
  const double ll_dense = -0.5 * (y.dot(Ci * y) + std::log(C.determinant()) + static_cast<double>(n) * std::log(2 * M_PI));
  CHECK(predictive_loglik(t, h, e, p) == Approx(ll_dense).epsilon(1e-10));
}
}  // namespace

TEST_CASE("noise model: the innovations form is generalised least squares") {
  // irregular times with a gap
  const std::vector<double> t = {0, 0.3, 0.9, 1.0, 1.7, 4.0, 4.2, 4.9, 5.5, 6.0};
  NoiseParams p;
  p.s2 = 2.0, p.lambda = 0.7, p.tau_s = 1.5;
  SECTION("Gauss-Markov plus white") { check_against_dense(t, {}, p); }
  SECTION("a nominal component seen with a per-frame gain, a further Gauss-Markov part and white") {
    const std::vector<double> h = {0.4, 0.5, 0.6, 0.65, 0.8, 1.0, 1.1, 1.3, 1.6, 2.5};  // e.g. 1 / range
    p.nom_share = 0.35, p.nom_tau_s = 5.0, p.tau_s = 0.8;
    check_against_dense(t, h, p);
    Eigen::MatrixXd W = Eigen::MatrixXd::Ones(static_cast<Eigen::Index>(t.size()), 1);
    CHECK_THROWS_AS(whiten(t, {1.0, 2.0}, p, {}, W), std::invalid_argument);  // gains of the wrong length
  }
}

namespace {
// The mean and the sample sd (n - 1) of x.
std::pair<double, double> mean_and_sd(const std::vector<double>& x) {
  double m = 0, s = 0;
  for (double v : x) m += v;
  m /= static_cast<double>(x.size());
  for (double v : x) s += (v - m) * (v - m);
  return std::make_pair(m, std::sqrt(s / static_cast<double>(x.size() - 1)));
}

// One radar-like channel over 200 s with irregular frames and a gap: y = effects + noise.
// The range channel's nuisance (a range bias) and two catalogue entries: the physical
// range_gain (column: the range) and the scanned bias_step (41 times, 20 ... 180 s).
void add_gain_and_step(Problem& pb, const std::vector<double>& range) {
  const auto n = static_cast<Eigen::Index>(pb.y.size());
  pb.nuisance = Eigen::MatrixXd::Ones(n, 1);
  pb.nuisance_names = {"range_bias_m"};
  pb.catalogue.push_back({"range_gain", {"radar", ""}, {"1"}, "the range", "", {}, [range, n](std::size_t) {
                            Eigen::MatrixXd C(n, 1);
                            for (Eigen::Index i = 0; i < n; ++i) C(i, 0) = range[static_cast<std::size_t>(i)];
                            return C;
                          }});
  std::vector<double> grid;
  for (double ts = 20; ts <= 180; ts += 4) grid.push_back(ts);
  const auto t_s = pb.t_s;
  pb.catalogue.push_back({"bias_step", {"radar", ""}, {"m"}, "a jump at one time", "t_s", grid, [t_s, grid, n](std::size_t v) {
                            Eigen::MatrixXd C(n, 1);
                            for (Eigen::Index i = 0; i < n; ++i) C(i, 0) = t_s[static_cast<std::size_t>(i)] >= grid[v];
                            return C;
                          }});
}

struct Synthetic {
  Problem pb;
  std::vector<double> range;
};
Synthetic make(std::uint64_t seed, double gain, double step, double tau, double out_frac, double white, double step_t_s = 120) {
  Synthetic s;
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> N(0, 1);
  std::uniform_real_distribution<double> U(0, 1);
  CascadeNoise cn(tau > 0 ? tau : 1);
  cn.norm = tau > 0 ? cascade_norm(tau) : 1;
  Problem& pb = s.pb;
  pb.channels.push_back({"radar:1:range", "radar", "1", "m", 1.0});
  for (double t = 0; t < 200;) {
    t += 0.3 + 0.4 * U(rng);
    if (t > 80 && t < 95) continue;
    double e = white * N(rng) + (tau > 0 ? cn.at(t, rng) : 0.0);
    if (U(rng) < out_frac) e += 20 * (U(rng) - 0.5) * 2;
    const double r = 3000 + 1000 * std::sin(2 * M_PI * t / 150);
    s.range.push_back(r);
    pb.channel.push_back(0);
    pb.t_s.push_back(t);
    pb.y.push_back(gain * r + (t > step_t_s ? step : 0.0) + e);
    pb.estimation.push_back(t < 130);
  }
  add_gain_and_step(pb, s.range);
  const auto n = static_cast<Eigen::Index>(pb.y.size());
  const auto t_s = pb.t_s;
  pb.catalogue.push_back({"bias_drift", {"radar", ""}, {"m_per_s"}, "time", "", {}, [t_s, n](std::size_t) {
                            Eigen::MatrixXd C(n, 1);
                            for (Eigen::Index i = 0; i < n; ++i) C(i, 0) = t_s[static_cast<std::size_t>(i)] - 100;
                            return C;
                          }});
  s.pb.catalogue.back().shape = true;
  return s;
}
}  // namespace

TEST_CASE("effect search: familywise false alarms under coloured noise stay within alpha") {
  // 40 nominal flights per noise (white; cascade tau 0.5 s, 8 s, 30 s), alpha = 0.01. With a
  // true familywise rate <= 1 %, P(>= 4 alarms in 40) <= 8e-4 (binomial), so <= 3 alarms each.
  for (double tau : {0.0, 0.5, 8.0, 30.0}) {
    int alarms = 0;
    for (std::uint64_t seed = 1; seed <= 40; ++seed) {
      const Synthetic s = make(1000 + seed, 0, 0, tau, 0, 0.5);
      const SearchResult r = search_effects(s.pb, SearchOptions{});
      alarms += !r.effects.empty();
    }
    INFO("tau " << tau << " s: " << alarms << " of 40 flights named a mean effect");
    CHECK(alarms <= 3);
  }
}

TEST_CASE("effect search: the physical cause is named, the scanned step listed as confounded") {
  // range_gain 3e-3 (3 m per km; about 6 SE under this noise) under cascade noise tau 8 s:
  // named, within 3 SE; no bias_step.
  int named = 0;
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    const Synthetic s = make(seed, 3e-3, 0, 8.0, 0, 0.5);
    const SearchResult r = search_effects(s.pb, SearchOptions{});
    REQUIRE(!r.effects.empty());
    CHECK(r.effects[0].name == "range_gain");
    CHECK(std::abs(r.effects[0].estimate[0] - 3e-3) < 3 * r.effects[0].stderr_[0]);
    for (const auto& e : r.effects) CHECK(e.name != "bias_step");
    named += r.effects[0].name == "range_gain";
    CHECK(r.gain[0].extended_rms < r.gain[0].nominal_rms);
  }
  CHECK(named == 5);
}

TEST_CASE("effect search: a confounding note names each entry's scope where their signatures read the same",
          "[model_id]") {
  // Two entries of one kind on different scopes share their signature text ("... of this
  // target" in the multi-sensor catalogue): "Data in which the range and the range vary
  // differently" would not say which is which. A range gain on a second scope whose column is
  // the range with a slow 1 % ripple is confounded with the first; the note names both scopes.
  Synthetic s = make(3, 3e-3, 0, 8.0, 0, 0.5);
  const auto n = static_cast<Eigen::Index>(s.pb.y.size());
  const std::vector<double> range = s.range, t_s = s.pb.t_s;
  s.pb.catalogue.push_back({"range_gain", {"radar", "2"}, {"1"}, "the range", "", {}, [range, t_s, n](std::size_t) {
                              Eigen::MatrixXd C(n, 1);
                              for (Eigen::Index i = 0; i < n; ++i) {
                                const auto ui = static_cast<std::size_t>(i);
                                C(i, 0) = range[ui] * (1 + 0.01 * std::sin(t_s[ui] / 40));
                              }
                              return C;
                            }});
  const SearchResult r = search_effects(s.pb, SearchOptions{});
  REQUIRE(!r.effects.empty());
  const FoundEffect& fe = r.effects[0];
  INFO(fe.name << " (" << fe.scope.label() << "): " << fe.note);
  CHECK(fe.name == "range_gain");
  REQUIRE_FALSE(fe.confounded_with.empty());
  CHECK(fe.note.find("vary differently") != std::string::npos);
  CHECK(fe.note.find("the range and the range vary") == std::string::npos);
  CHECK(fe.note.find("the range (sensor radar)") != std::string::npos);
  CHECK(fe.note.find("the range (radar:2)") != std::string::npos);
}

TEST_CASE("effect search: effects_only reports the same effects and confounding, and nothing else", "[model_id][injection]") {
  // What an injected search reads (named effects and confounded_with) must not depend on the
  // report's later parts it skips: a range gain that lists the step as confounded, and a step.
  for (const Synthetic& s : {make(3, 3e-3, 0, 8.0, 0, 0.5), make(7, 0, 3.0, 8.0, 0, 0.5)}) {
    SearchOptions full, only;
    full.score_holdout = only.score_holdout = false;
    only.effects_only = true;
    const SearchResult a = search_effects(s.pb, full), b = search_effects(s.pb, only);
    REQUIRE(!a.effects.empty());
    REQUIRE(a.effects.size() == b.effects.size());
    for (std::size_t i = 0; i < a.effects.size(); ++i) {
      INFO(a.effects[i].name);
      CHECK(a.effects[i].entry == b.effects[i].entry);
      CHECK(a.effects[i].variant == b.effects[i].variant);
      CHECK(a.effects[i].estimate == b.effects[i].estimate);
      CHECK(a.effects[i].kept_lr == b.effects[i].kept_lr);
      REQUIRE(a.effects[i].confounded_with.size() == b.effects[i].confounded_with.size());
      for (std::size_t k = 0; k < a.effects[i].confounded_with.size(); ++k)
        CHECK(a.effects[i].confounded_with[k].entry == b.effects[i].confounded_with[k].entry);
    }
    CHECK(!a.detection_limits.empty());  // the full report has its limits and noise findings
    CHECK(!a.noise.empty());
    CHECK(b.detection_limits.empty());   // effects_only: none
    CHECK(b.noise.empty());
  }
}

TEST_CASE("effect search: a projector's remembered 2 log LRs are its own, and a new noise starts afresh", "[model_id]") {
  // Projector::entry_lr remembers each answer in the design's LrMemo (the search asks the same
  // model about the same entries in several places): the numbers must be exactly lr's, the same
  // on a second ask, and a set_noise must not hand the projections of the noise before to a
  // projector made under the new one.
  const Synthetic s = make(3, 3e-3, 3.0, 8.0, 0, 0.5);
  search_detail::Design d(s.pb);
  const std::size_t n_ch = d.rows.size();
  NoiseParams white;
  white.s2 = 1;
  NoiseParams slow = white;
  slow.lambda = 0.9, slow.tau_s = 20;
  d.set_noise(std::vector<NoiseParams>(n_ch, white), std::vector<std::vector<char>>(n_ch));
  const search_detail::Projector P = search_detail::projector_of(d, {});
  const search_detail::Projector plain(search_detail::model_matrix(d, {}), d.yw, d.n_used);
  std::vector<std::vector<double>> before(d.Cw.size());
  for (std::size_t e = 0; e < d.Cw.size(); ++e)
    for (std::size_t v = 0; v < d.Cw[e].size(); ++v) {
      const double first = P.entry_lr(d, e, v);
      CHECK(first == plain.lr(d.Cw[e][v]));
      CHECK(P.entry_lr(d, e, v) == first);  // the memo's answer
      before[e].push_back(first);
    }
  d.set_noise(std::vector<NoiseParams>(n_ch, slow), std::vector<std::vector<char>>(n_ch));
  const search_detail::Projector P2 = search_detail::projector_of(d, {});
  const search_detail::Projector plain2(search_detail::model_matrix(d, {}), d.yw, d.n_used);
  int differ = 0;
  for (std::size_t e = 0; e < d.Cw.size(); ++e)
    for (std::size_t v = 0; v < d.Cw[e].size(); ++v) {
      const double now = P2.entry_lr(d, e, v);
      CHECK(now == plain2.lr(d.Cw[e][v]));
      differ += now != before[e][v];
    }
  CHECK(differ > 0);  // the slow noise changes the answers: the memo of the white one was not read
  // a model with an entry in it is its own key
  const search_detail::Projector P3 = search_detail::projector_of(d, {{0, 0}});
  const search_detail::Projector plain3(search_detail::model_matrix(d, {{0, 0}}), d.yw, d.n_used);
  CHECK(P3.entry_lr(d, 1, 0) == plain3.lr(d.Cw[1][0]));
}

TEST_CASE("effect search: the design's whitened catalogue is each grid point whitened alone, bit for bit", "[model_id]") {
  // set_noise whitens every grid point's columns channel by channel, all at once (in place where
  // a channel's rows are one block, gathered where they are not): each column must be what
  // whiten_through gives it alone, 0 on the channels it does not touch, and its unit_gram (which
  // skips the untouched channels' rows) the one scanned over every row. Three channels of 60
  // frames, laid out channel by channel and interleaved; frames kept out on one; an entry on all
  // channels, a scanned step on one (zero before its time), two columns on two channels, and
  // one that touches nothing; with the columns computed on each call and kept (KeptColumns).
  const std::size_t n_ch = 3, frames = 60;
  for (bool interleaved : {false, true})
    for (bool kept : {false, true}) {
      Problem pb;
      for (std::size_t c = 0; c < n_ch; ++c) pb.channels.push_back({"radar:1:ch" + std::to_string(c), "radar", "1", "m", 1.0});
      std::mt19937_64 rng(7);
      std::normal_distribution<double> N(0, 1);
      std::vector<std::size_t> ch_of;
      for (std::size_t k = 0; k < n_ch * frames; ++k) {
        const std::size_t c = interleaved ? k % n_ch : k / frames, i = interleaved ? k / n_ch : k % frames;
        ch_of.push_back(c);
        pb.channel.push_back(static_cast<int>(c));
        pb.t_s.push_back(0.5 * static_cast<double>(i) + 0.01 * static_cast<double>(c));
        pb.y.push_back(N(rng));
        pb.estimation.push_back(1);
      }
      const auto n = static_cast<Eigen::Index>(pb.y.size());
      const std::vector<double> t_s = pb.t_s;
      auto on = [&](std::vector<std::size_t> chs) {
        return [ch_of, chs](std::size_t k) { return std::find(chs.begin(), chs.end(), ch_of[k]) != chs.end(); };
      };
      auto everywhere = on({0, 1, 2});
      pb.catalogue.push_back({"drift", {"radar", ""}, {"m_per_s"}, "time", "", {}, [t_s, n, everywhere](std::size_t) {
                                Eigen::MatrixXd C(n, 1);
                                for (Eigen::Index k = 0; k < n; ++k) C(k, 0) = everywhere(static_cast<std::size_t>(k)) ? t_s[static_cast<std::size_t>(k)] - 15 : 0.0;
                                return C;
                              }});
      auto only1 = on({1});
      const std::vector<double> steps = {3, 11, 20, 27};
      pb.catalogue.push_back({"step", {"radar", "1"}, {"m"}, "step", "t_s", steps, [t_s, n, only1, steps](std::size_t v) {
                                Eigen::MatrixXd C = Eigen::MatrixXd::Zero(n, 1);
                                for (Eigen::Index k = 0; k < n; ++k)
                                  if (only1(static_cast<std::size_t>(k)) && t_s[static_cast<std::size_t>(k)] > steps[v]) C(k, 0) = 1;
                                return C;
                              }});
      auto two = on({0, 2});
      pb.catalogue.push_back({"pair", {"radar", ""}, {"a", "b"}, "sin", "", {}, [t_s, n, two](std::size_t) {
                                Eigen::MatrixXd C = Eigen::MatrixXd::Zero(n, 2);
                                for (Eigen::Index k = 0; k < n; ++k)
                                  if (two(static_cast<std::size_t>(k)))
                                    C(k, 0) = std::sin(0.2 * t_s[static_cast<std::size_t>(k)]), C(k, 1) = std::cos(0.3 * t_s[static_cast<std::size_t>(k)]);
                                return C;
                              }});
      pb.catalogue.push_back({"nothing", {"radar", ""}, {"m"}, "zero", "", {}, [n](std::size_t) { return Eigen::MatrixXd::Zero(n, 1); }});
      search_detail::Design d(pb);
      if (kept)
        for (std::size_t e = 0; e < pb.catalogue.size(); ++e) {
          auto kc = std::make_shared<KeptColumns>();
          for (std::size_t v = 0; v < pb.catalogue[e].variants(); ++v) {
            kc->columns.push_back(pb.catalogue[e].columns(v));
            kc->touches.push_back(d.touches(kc->columns.back()));
          }
          pb.catalogue[e].kept_columns = kc;
        }
      NoiseParams np;
      np.s2 = 1.5, np.lambda = 0.8, np.tau_s = 4;
      std::vector<std::vector<char>> skip(n_ch, std::vector<char>(frames, 0));
      skip[1][5] = skip[1][30] = 1;
      // a first noise, then a second (its storage kept from the first: the untouched rows stay 0)
      NoiseParams white;
      white.s2 = 0.7;
      for (int round = 0; round < 2; ++round) {
        d.set_noise(std::vector<NoiseParams>(n_ch, round == 0 ? np : white), skip);
        skip[2][0] = 1;
        const std::vector<GainTable> tables = d.gain_tables(d.noise);
        for (std::size_t e = 0; e < pb.catalogue.size(); ++e)
          for (std::size_t v = 0; v < pb.catalogue[e].variants(); ++v) {
            INFO((interleaved ? "interleaved" : "channel by channel") << (kept ? ", kept columns" : "") << ", noise "
                                                                       << round << ": entry " << pb.catalogue[e].name
                                                                       << ", grid point " << v);
            const Eigen::MatrixXd alone = d.whiten_through(d.raw_columns(e, v), tables);
            const Eigen::MatrixXd& C = d.Cw[e][v];
            REQUIRE(C.rows() == alone.rows());
            REQUIRE(C.cols() == alone.cols());
            CHECK((C.array() == alone.array()).all());
            const search_detail::UnitGram full = search_detail::unit_gram(C), got = d.Cg[e][v];
            CHECK(got.lo == full.lo);
            CHECK(got.hi == full.hi);
            CHECK((got.inv_norm.array() == full.inv_norm.array()).all());
            CHECK((got.UU.array() == full.UU.array()).all());
          }
      }
      CHECK(d.Cg[3][0].lo == d.Cg[3][0].hi);  // the column that touches nothing
      CHECK(d.Cg[1][0].lo > 0);               // the step on one channel: not from row 0
    }
  // rows said to be zero that are not a prefix and a suffix: refused
  CHECK_THROWS_WITH(search_detail::unit_gram(Eigen::MatrixXd::Ones(4, 1), 3, 2), Catch::Contains("prefix and a suffix"));
}

TEST_CASE("effect search: a real step is found at its time") {
  const Synthetic s = make(7, 0, 3.0, 8.0, 0, 0.5);
  const SearchResult r = search_effects(s.pb, SearchOptions{});
  REQUIRE(!r.effects.empty());
  CHECK(r.effects[0].name == "bias_step");
  CHECK(std::abs(r.effects[0].estimate[0] - 3.0) < 3 * r.effects[0].stderr_[0]);
  CHECK(std::abs(r.effects[0].scan_value - 120) < 3 * r.effects[0].scan_se + 4);  // grid step 4 s
}

TEST_CASE("effect search: of grid points the data cannot tell apart, the first is reported", "[model_id][scan]") {
  // A scanned entry whose grid points give columns of one span in different units (the step
  // at 95 s, scaled by the grid's value): their 2 log LR agree but for rounding, which differs
  // between them, and must not choose the reported point. A 3 m step (6 sigma) is reported at
  // the grid's first value. (Two points of a real grid do this when the data cannot tell them
  // apart: a step time or a sweep's end bearing where no observation falls between them.)
  Synthetic s = make(7, 0, 3.0, 0, 0, 0.5, 88);
  auto& cat = s.pb.catalogue;
  cat.erase(std::remove_if(cat.begin(), cat.end(), [](const Candidate& c) { return c.name == "bias_step"; }), cat.end());
  const std::vector<double> grid{1.7, 2.3, 3.1, 4.9, 6.7, 7.3, 9.1, 11.3};
  const auto t_s = s.pb.t_s;
  const auto n = static_cast<Eigen::Index>(t_s.size());
  cat.push_back({"scaled_step", {"radar", ""}, {"m"}, "a jump", "scale", grid, [t_s, grid, n](std::size_t v) {
                   Eigen::MatrixXd C(n, 1);
                   for (Eigen::Index i = 0; i < n; ++i) C(i, 0) = grid[v] * (t_s[static_cast<std::size_t>(i)] >= 95 ? 1.0 : 0.0);
                   return C;
                 }});
  const SearchResult r = search_effects(s.pb, SearchOptions{});
  REQUIRE(!r.effects.empty());
  CHECK(r.effects[0].name == "scaled_step");
  CHECK(r.effects[0].scan_value == grid[0]);
}

TEST_CASE("added_lr: the likelihood ratio of nested least-squares fits, -1 for columns inside the model", "[model_id]") {
  // n log(RSS_M / RSS_(M,C)) against the two fits solved directly (QR), to 1e-9 relative: the
  // projection is exact algebra, its rounding ~1e-14 at these sizes.
  std::mt19937_64 rng(11);
  std::normal_distribution<double> N(0, 1);
  const Eigen::Index n = 300;
  Eigen::MatrixXd M(n, 3), C(n, 2);
  Eigen::VectorXd y(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const double t = static_cast<double>(i) / static_cast<double>(n);
    M(i, 0) = 1, M(i, 1) = t, M(i, 2) = std::sin(7 * t);
    C(i, 0) = 1e5 * t * t;            // a column in large units beside
    C(i, 1) = 0.1 * std::cos(11 * t);  // one in small units: the rank must not depend on them
    y(i) = C(i, 1) / 0.1 + N(rng);
  }
  auto rss = [&](const Eigen::MatrixXd& X) {
    return (y - X * X.colPivHouseholderQr().solve(y)).squaredNorm();
  };
  Eigen::MatrixXd MC(n, 5);
  MC << M, C;
  const double want = static_cast<double>(n) * std::log(rss(M) / rss(MC));
  const double got = search_detail::added_lr(M, y, C, static_cast<double>(n));
  INFO("added_lr " << got << ", by the two fits " << want);
  CHECK(want > 10);  // the data hold the second column's effect
  CHECK(std::abs(got - want) < 1e-9 * want);
  // a column inside span(M) (to rounding), beside an independent one: -1
  Eigen::MatrixXd inside(n, 2);
  inside.col(0) = M * Eigen::Vector3d(0.5, -2, 1) + 1e-13 * Eigen::VectorXd::Ones(n);
  inside.col(1) = C.col(1);
  CHECK(search_detail::added_lr(M, y, inside, static_cast<double>(n)) == -1);
  // no column: nothing added
  CHECK(search_detail::added_lr(M, y, Eigen::MatrixXd(n, 0), static_cast<double>(n)) == 0);
  // Projector::lr answers from the Gram matrix of the projected unit columns where that is well
  // conditioned and from their QR elsewhere: each regime against the two fits. A column almost
  // inside span(M) (its projected unit column 0.003 long: the Gram matrix's eigenvalue 1e-5), and
  // columns that explain all but 1e-6 of the residual's sum of squares (RSS_(M,C) = RSS_M - drop
  // would keep 6 fewer digits), each to 1e-9 relative as above.
  Eigen::MatrixXd near(n, 1);
  Eigen::VectorXd wiggle(n);
  for (Eigen::Index i = 0; i < n; ++i) wiggle(i) = std::cos(23.0 * static_cast<double>(i) / static_cast<double>(n));
  const Eigen::VectorXd in_M = M * Eigen::Vector3d(1, 2, -1);
  near.col(0) = in_M + 0.003 * in_M.norm() * wiggle.normalized();
  const Eigen::VectorXd y_near = y + 400 * near.col(0);
  const Eigen::VectorXd y_all = C * Eigen::Vector2d(2e-5, 30) + 1e-3 * y;  // C explains all but the small noise
  for (const auto& [Cx, yx, what] : {std::tuple<Eigen::MatrixXd, Eigen::VectorXd, const char*>{near, y_near, "nearly inside"},
                                     std::tuple<Eigen::MatrixXd, Eigen::VectorXd, const char*>{C, y_all, "explains all"}}) {
    Eigen::MatrixXd MX(n, M.cols() + Cx.cols());
    MX << M, Cx;
    auto rss_of = [&](const Eigen::MatrixXd& X) { return (yx - X * X.colPivHouseholderQr().solve(yx)).squaredNorm(); };
    const double r0 = rss_of(M), r1 = rss_of(MX);
    const double w = static_cast<double>(n) * std::log(r0 / r1);
    const double g = search_detail::added_lr(M, yx, Cx, static_cast<double>(n));
    INFO(what << ": added_lr " << g << ", by the two fits " << w << ", RSS ratio " << r1 / r0);
    CHECK(w > 10);
    CHECK(std::abs(g - w) < 1e-9 * w);
  }
}

TEST_CASE("canonical_corr: the largest canonical correlation of two blocks given a model, against its definition",
          "[model_id]") {
  // The cosine of the least angle between the spans of A and B once span(M) is projected out of
  // both: from thin QR bases of the projected blocks, to 1e-12. Three regimes: blocks well apart
  // from the model, a block nearly inside it (its projected unit column 1e-3 long), and a block
  // inside it (not separable: 1).
  std::mt19937_64 rng(5);
  std::normal_distribution<double> N(0, 1);
  const Eigen::Index n = 400;
  Eigen::MatrixXd M(n, 3), A(n, 2), B(n, 2);
  for (Eigen::Index i = 0; i < n; ++i) {
    const double t = static_cast<double>(i) / static_cast<double>(n);
    M(i, 0) = 1, M(i, 1) = t, M(i, 2) = std::sin(5 * t);
    A(i, 0) = 1e4 * std::cos(9 * t), A(i, 1) = N(rng);
    B(i, 0) = std::cos(9 * t) + 0.7 * N(rng), B(i, 1) = 1e-3 * t * t;
  }
  auto definition = [&](const Eigen::MatrixXd& X, const Eigen::MatrixXd& Y) {
    const Eigen::MatrixXd Qm = Eigen::HouseholderQR<Eigen::MatrixXd>(M).householderQ() * Eigen::MatrixXd::Identity(n, M.cols());
    auto basis = [&](const Eigen::MatrixXd& Z) {
      const Eigen::MatrixXd R = Z - Qm * (Qm.transpose() * Z);
      return Eigen::MatrixXd(Eigen::HouseholderQR<Eigen::MatrixXd>(R).householderQ() * Eigen::MatrixXd::Identity(n, Z.cols()));
    };
    return Eigen::JacobiSVD<Eigen::MatrixXd>(basis(X).transpose() * basis(Y)).singularValues()(0);
  };
  const double want = definition(A, B);
  INFO("well apart: " << search_detail::canonical_corr(M, A, B) << " against " << want);
  CHECK(want > 0.5);
  CHECK(want < 0.99);
  CHECK(std::abs(search_detail::canonical_corr(M, A, B) - want) < 1e-12);
  Eigen::MatrixXd near = A;
  near.col(0) = M * Eigen::Vector3d(2, -1, 3);
  Eigen::VectorXd away(n);
  for (Eigen::Index i = 0; i < n; ++i) away(i) = N(rng);
  near.col(0) += 1e-3 * near.col(0).norm() * (B.col(0).normalized() + away.normalized()).normalized();
  const double want_near = definition(near, B);
  INFO("nearly inside: " << search_detail::canonical_corr(M, near, B) << " against " << want_near);
  CHECK(want_near < 0.99);
  CHECK(std::abs(search_detail::canonical_corr(M, near, B) - want_near) < 1e-9);
  Eigen::MatrixXd inside = A;
  inside.col(0) = M * Eigen::Vector3d(2, -1, 3);
  inside.col(1) = M * Eigen::Vector3d(0, 1, 1);
  CHECK(search_detail::canonical_corr(M, inside, B) == 1.0);
}

TEST_CASE("effect search: each effect reports the statistic it was kept with") {
  // A range gain and a step under tau 8 s noise, five seeds. Every named effect passed the
  // selection, so its kept adjusted p is below alpha; where the plug-in selection (q = 0) names
  // the same effects, the kept 2 log LR under the noise confidence set, the least over a set
  // containing the plug-in noise, is at most the plug-in one.
  SearchOptions plug_in;
  plug_in.noise_set_q = 0;
  int compared = 0;
  for (std::uint64_t seed = 1; seed <= 5; ++seed) {
    const Synthetic s = make(seed, 3e-3, 3.0, 8.0, 0, 0.5);
    const SearchResult r = search_effects(s.pb, SearchOptions{});
    const SearchResult r0 = search_effects(s.pb, plug_in);
    for (const auto* res : {&r, &r0})
      for (const auto& e : res->effects) {
        INFO("seed " << seed << " " << e.name << ": kept at 2 log LR " << e.kept_lr);
        CHECK(e.kept_log10_p < std::log10(0.01));
      }
    if (r.effects.size() != r0.effects.size()) continue;
    for (std::size_t i = 0; i < r.effects.size(); ++i) {
      INFO("seed " << seed << " " << r.effects[i].name << ": kept at 2 log LR " << r.effects[i].kept_lr << " (plug-in "
                   << r0.effects[i].kept_lr << ")");
      REQUIRE(r.effects[i].name == r0.effects[i].name);
      CHECK(r.effects[i].kept_lr <= r0.effects[i].kept_lr + 1e-9);
      ++compared;
    }
  }
  CHECK(compared >= 5);
}

TEST_CASE("effect search: an effect the window cannot separate from one kept before it is left out of the held-out fit") {
  // Two real range-like effects: A = range, B = range plus a 7 s wiggle of 300 m inside the
  // window (canonical correlation with A 1000 / sqrt(1000^2 + 300^2) = 0.96 > 0.9), plus a ramp
  // after it. The full data separate them (both named); the window cannot, so the held-out fit
  // keeps only the first named, instead of extrapolating a difference of two large estimates.
  Synthetic s = make(21, 3e-3, 0, 0, 0, 0.5);
  Problem& pb = s.pb;
  const auto n = static_cast<Eigen::Index>(pb.y.size());
  std::vector<double> b(pb.y.size());
  for (std::size_t i = 0; i < b.size(); ++i) {
    const double t = pb.t_s[i];
    b[i] = s.range[i] + 300 * std::sin(2 * M_PI * t / 7) + (t >= 130 ? 3000 * (t - 130) / 70 : 0.0);
    pb.y[i] += 3e-3 * b[i];
  }
  pb.catalogue.push_back({"range_gain_b", {"radar", ""}, {"1"}, "range b", "", {}, [b, n](std::size_t) {
                            Eigen::MatrixXd C(n, 1);
                            for (Eigen::Index i = 0; i < n; ++i) C(i, 0) = b[static_cast<std::size_t>(i)];
                            return C;
                          }});
  const SearchResult r = search_effects(pb, SearchOptions{});
  std::set<std::string> named;
  for (const auto& e : r.effects) named.insert(e.name);
  CHECK(named.count("range_gain") == 1);
  CHECK(named.count("range_gain_b") == 1);
  REQUIRE(r.holdout_effects.size() == 1);
  CHECK(r.holdout_effects[0] == r.effects[0].name + "@sensor radar");
}

TEST_CASE("effect search: an effect whose held-out part the window leaves open is not extrapolated") {
  // A two-parameter entry: the range (hidden at 3e-3, about 20 SE) and a ramp that starts at
  // t0 (hidden at 0). With t0 = 128 s the window (t < 130 s) sees only a few frames of the ramp,
  // so the ramp's coefficient has an SE of about 0.2 there, and its prediction over the held-out
  // frames (ramp up to 70) is mostly uncertainty: left out. With t0 = 60 s the window
  // determines both parts, and the effect is used. (The range part alone is determined in both:
  // the largest |estimate / SE| is no guard here.)
  for (const double t0 : {128.0, 60.0}) {
    Synthetic s = make(31, 3e-3, 0, 0, 0, 0.5);
    Problem& pb = s.pb;
    const auto n = static_cast<Eigen::Index>(pb.y.size());
    const auto range = s.range;
    const auto t_s = pb.t_s;
    pb.catalogue.push_back({"gain_and_ramp", {"radar", ""}, {"1", "m_per_s"}, "range and a late ramp", "", {},
                            [range, t_s, t0, n](std::size_t) {
                              Eigen::MatrixXd C(n, 2);
                              for (Eigen::Index i = 0; i < n; ++i) {
                                const auto k = static_cast<std::size_t>(i);
                                C(i, 0) = range[k];
                                C(i, 1) = std::max(0.0, t_s[k] - t0);
                              }
                              return C;
                            }});
    pb.catalogue.erase(pb.catalogue.begin());  // without the plain range_gain, the pair is the cause
    const SearchResult r = search_effects(pb, SearchOptions{});
    INFO("ramp from t = " << t0 << " s");
    REQUIRE(!r.effects.empty());
    CHECK(r.effects[0].name == "gain_and_ramp");
    const bool used = std::find(r.holdout_effects.begin(), r.holdout_effects.end(), "gain_and_ramp@sensor radar") !=
                      r.holdout_effects.end();
    CHECK(used == (t0 < 100));
  }
}

TEST_CASE("effect search: outliers are named only when the mixture predicts better") {
  const Synthetic clean = make(11, 0, 0, 0, 0, 0.5);
  const SearchResult r0 = search_effects(clean.pb, SearchOptions{});
  CHECK_FALSE(r0.noise[0].outliers_named);
  const Synthetic dirty = make(11, 0, 0, 0, 0.05, 0.5);
  const SearchResult r1 = search_effects(dirty.pb, SearchOptions{});
  CHECK(r1.noise[0].outliers_named);
  CHECK(r1.noise[0].outlier_gain > 0);
  CHECK(r1.effects.empty());
}

TEST_CASE("noise identification: Gauss-Markov tau recovered, white stays white") {
  std::mt19937_64 rng(5);
  std::normal_distribution<double> N(0, 1);
  std::vector<double> t;
  Eigen::VectorXd e(1500);
  double g = 0, tp = 0;
  for (int i = 0; i < 1500; ++i) {
    const double ti = i * 0.2 + 0.05 * (i % 3);
    const double phi = std::exp(-(ti - tp) / 8.0);
    g = phi * g + std::sqrt(1 - phi * phi) * N(rng);
    tp = ti;
    t.push_back(ti);
    e(i) = g + 0.3 * N(rng);
  }
  const NoiseFit f = identify_noise(t, {}, e, Eigen::MatrixXd(1500, 0), NoiseIdOptions{});
  CHECK(f.correlated);
  CHECK(f.se_tau_s > 0);
  CHECK(std::abs(f.params.tau_s - 8.0) < 3 * f.se_tau_s);
  // without the SE of tau (what the injected searches ask): the same fit, its SE left 0
  NoiseIdOptions no_se;
  no_se.se_tau = false;
  const NoiseFit f0 = identify_noise(t, {}, e, Eigen::MatrixXd(1500, 0), no_se);
  CHECK(f0.se_tau_s == 0);
  CHECK(f0.params.tau_s == f.params.tau_s);
  CHECK(f0.params.lambda == f.params.lambda);
  CHECK(f0.params.s2 == f.params.s2);
  CHECK(f0.loglik_correlated == f.loglik_correlated);
  CHECK(f0.loglik_ml == f.loglik_ml);
  Eigen::VectorXd w(1500);
  for (int i = 0; i < 1500; ++i) w(i) = N(rng);
  const NoiseFit fw = identify_noise(t, {}, w, Eigen::MatrixXd(1500, 0), NoiseIdOptions{});
  CHECK_FALSE(fw.correlated);
}

TEST_CASE("noise identification: the confidence set covers the true noise at its stated level") {
  // 200 series of Gauss-Markov (tau 5 s, share 0.8) plus white noise, 600 frames at 0.5 s, a
  // constant as the fixed effect. The set {2 (l_best - l) <= q}, q = 4, is asymptotically a
  // chi-square(2) region: coverage 1 - exp(-2) = 0.865. The truth counts as covered when the
  // set holds a grid model within one grid step of it (log tau within 0.3, lambda within
  // 0.1). The lower bound is 0.865 minus 3 binomial standard errors of 200 series (0.072);
  // the set must also be informative: white noise outside it in nearly every series (the
  // white model's 2 log LR is about 600 here), and the set a minority of the 197 grid models.
  std::mt19937_64 rng(11);
  std::normal_distribution<double> N(0, 1);
  const int n = 600, series = 200;
  const double tau = 5, share = 0.8, q = 4;
  std::vector<double> t(n);
  for (int i = 0; i < n; ++i) t[static_cast<std::size_t>(i)] = 0.5 * i;
  const Eigen::MatrixXd X = Eigen::MatrixXd::Ones(n, 1);
  int covered = 0, white_in = 0;
  double size = 0;
  for (int k = 0; k < series; ++k) {
    Eigen::VectorXd e(n);
    const double phi = std::exp(-0.5 / tau);
    double g = std::sqrt(share) * N(rng);
    for (int i = 0; i < n; ++i) {
      if (i > 0) g = phi * g + std::sqrt(share * (1 - phi * phi)) * N(rng);
      e(i) = g + std::sqrt(1 - share) * N(rng);
    }
    const auto set = noise_confidence_set(t, {}, e, X, NoiseIdOptions{}, {}, q);
    REQUIRE(!set.empty());
    bool hit = false;
    for (const auto& p : set) {
      hit = hit || (std::abs(std::log(p.tau_s / tau)) <= 0.3 && std::abs(p.lambda - share) <= 0.1);
      white_in += p.lambda == 0;
    }
    covered += hit;
    size += static_cast<double>(set.size()) / series;
  }
  const double nominal = 1 - std::exp(-q / 2), se = std::sqrt(nominal * (1 - nominal) / series);
  INFO("covered " << covered << " of " << series << ", mean set size " << size << ", white inside " << white_in);
  CHECK(covered >= (nominal - 3 * se) * series);
  CHECK(white_in <= series / 100);
  CHECK(size < 197 / 4.0);
}

namespace {
// n frames every dt seconds of unit Gauss-Markov noise (correlation time tau) plus unit white
// noise, from seed.
void gm_plus_white(std::uint64_t seed, int n, double dt, double tau, std::vector<double>& t, Eigen::VectorXd& e) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> N(0, 1);
  t.clear();
  e.resize(n);
  double g = 0;
  for (int i = 0; i < n; ++i) {
    const double phi = std::exp(-dt / tau);
    g = phi * g + std::sqrt(1 - phi * phi) * N(rng);
    t.push_back(i * dt);
    e(i) = g + N(rng);
  }
}
}  // namespace

TEST_CASE("noise identification: a refinement gives up only below the value its caller needs") {
  // Gauss-Markov noise (tau 6 s, half the variance) at 0.4 s over 600 frames, a constant as the
  // fixed effect. Profile mode: with profile_give_up_below far above the likelihood's top the
  // refinement gives up, and loglik_ml is under the exact one and under the value asked for;
  // with it below the top the fit is the exact one, bit for bit (it reached the top). REML mode:
  // the further part is used here (2 log LR over the nominal model far above 4), so its
  // refinement must not give up: the same fit with or without the profile option set.
  std::vector<double> t;
  Eigen::VectorXd e;
  gm_plus_white(4242, 600, 0.4, 6.0, t, e);
  const Eigen::MatrixXd X = Eigen::MatrixXd::Ones(600, 1);
  NoiseIdOptions o;
  o.profile_ml = true;
  o.flag_outliers = false;
  const NoiseFit exact = identify_noise(t, {}, e, X, o);
  REQUIRE(exact.correlated);
  NoiseIdOptions up = o;
  up.profile_give_up_below = exact.loglik_ml + 100;
  const NoiseFit gave_up = identify_noise(t, {}, e, X, up);
  INFO("exact " << exact.loglik_ml << ", given up at " << gave_up.loglik_ml);
  CHECK(gave_up.loglik_ml <= exact.loglik_ml);
  CHECK(gave_up.loglik_ml < up.profile_give_up_below);
  CHECK(gave_up.loglik_ml < exact.loglik_ml - 1e-9);  // it did give up short of the top
  NoiseIdOptions reach = o;
  reach.profile_give_up_below = exact.loglik_ml - 1;
  const NoiseFit reached = identify_noise(t, {}, e, X, reach);
  CHECK(reached.loglik_ml == exact.loglik_ml);
  CHECK(reached.params.tau_s == exact.params.tau_s);
  NoiseIdOptions reml;
  reml.flag_outliers = false;
  const NoiseFit r0 = identify_noise(t, {}, e, X, reml);
  REQUIRE(2 * (r0.loglik_correlated - std::max(r0.loglik_nominal, r0.loglik_white)) > 4 + 10);
  reml.profile_give_up_below = 1e9;  // read in profile mode only
  const NoiseFit r1 = identify_noise(t, {}, e, X, reml);
  CHECK(r1.params.tau_s == r0.params.tau_s);
  CHECK(r1.params.lambda == r0.params.lambda);
  CHECK(r1.loglik_correlated == r0.loglik_correlated);
}

TEST_CASE("noise identification: the profile likelihood ratio of a step is chi-square sized under Gauss-Markov noise") {
  // profile_ml: the ML likelihood maximised over the noise family, without the REML trend. A
  // step column (t >= 120 s) added to a constant: nested, so the maximised likelihood cannot
  // fall (up to the optimiser's tolerance, a grid and golden sections in log tau and logit
  // lambda: 0.01 in log-likelihood); with no step in the data, 2 log LR ~ chi2(1) (mean
  // 1, SD sqrt 2): the mean over 30 series within 3 SE of 1 (1 + 3 sqrt(2 / 30) = 1.78); a real
  // step of 4 x its GLS standard error gives far more.
  NoiseIdOptions o;
  o.profile_ml = true;
  o.flag_outliers = false;
  double sum_lr = 0;
  double lr_step = 0;
  const int n_series = 30;
  for (int k = 0; k <= n_series; ++k) {
    std::mt19937_64 rng(700 + static_cast<std::uint64_t>(k));
    std::normal_distribution<double> N(0, 1);
    std::vector<double> t;
    Eigen::VectorXd e(600);
    Eigen::MatrixXd X0 = Eigen::MatrixXd::Ones(600, 1), X1(600, 2);
    double g = 0, tp = 0;
    for (int i = 0; i < 600; ++i) {
      const double ti = i * 0.4;
      const double phi = std::exp(-(ti - tp) / 6.0);
      g = phi * g + std::sqrt(1 - phi * phi) * N(rng);
      tp = ti;
      t.push_back(ti);
      // the last series carries a step of 1.0 (about 4 GLS SE under this noise)
      e(i) = g + 0.5 * N(rng) + (k == n_series && ti >= 120 ? 1.0 : 0.0);
      X1(i, 0) = 1, X1(i, 1) = ti >= 120;
    }
    const double l0 = identify_noise(t, {}, e, X0, o).loglik_ml, l1 = identify_noise(t, {}, e, X1, o).loglik_ml;
    CHECK(l1 >= l0 - 0.01);
    if (k < n_series) sum_lr += 2 * (l1 - l0);
    else lr_step = 2 * (l1 - l0);
  }
  const double mean = sum_lr / n_series;
  INFO("mean 2 log LR without a step " << mean << ", with one " << lr_step);
  CHECK(mean < 1 + 3 * std::sqrt(2.0 / n_series));
  CHECK(mean > 1 - 3 * std::sqrt(2.0 / n_series));
  CHECK(lr_step > 9);
}

TEST_CASE("effect search: separation limits are the detection limits given the hardest partner") {
  // White noise, so the whitening is (nearly) a constant and the GLS partial correlation of the
  // range with a second range-like column (the range plus a 7 s wiggle) given the intercept is
  // the plain one, rho (about 0.96). Then the separation limit of range_gain is its detection
  // limit / sqrt(1 - rho^2) (the two fits' residual scales differ by one column's share of about
  // 500 frames: 2 % tolerance), its partner that column. An entry that copies another's column
  // can be told from it at no size (infinite).
  Synthetic s = make(41, 0, 0, 0, 0, 0.5);
  Problem& pb = s.pb;
  const auto n = static_cast<Eigen::Index>(pb.y.size());
  const auto t_s = pb.t_s;
  pb.catalogue.push_back({"drift_copy", {"radar", ""}, {"m_per_s"}, "time", "", {}, [t_s, n](std::size_t) {
                            Eigen::MatrixXd C(n, 1);
                            for (Eigen::Index i = 0; i < n; ++i) C(i, 0) = 2 * (t_s[static_cast<std::size_t>(i)] - 100);
                            return C;
                          }});
  std::vector<double> rb(s.range);  // a second range-like regressor: the range plus a 7 s wiggle
  for (std::size_t i = 0; i < rb.size(); ++i) rb[i] += 300 * std::sin(2 * M_PI * t_s[i] / 7);
  pb.catalogue.push_back({"range_gain_b", {"radar", ""}, {"1"}, "range b", "", {}, [rb, n](std::size_t) {
                            Eigen::MatrixXd C(n, 1);
                            for (Eigen::Index i = 0; i < n; ++i) C(i, 0) = rb[static_cast<std::size_t>(i)];
                            return C;
                          }});
  const SearchResult r = search_effects(pb, SearchOptions{});
  // (the noise may be identified with a short correlation, under 1 s: the whitening then acts on
  // these slow columns - a 150 s period and a ramp - nearly as a constant, and rho is kept)
  REQUIRE((r.noise[0].fit.params.lambda == 0 || r.noise[0].fit.params.tau_s < 1));
  const double rho = pearson(s.range, rb);
  const double alone = r.detection_limits.at("range_gain@sensor radar").at("1");
  const SeparationLimit& sep = r.separation_limits.at("range_gain@sensor radar").at("1");
  INFO("rho " << rho << ", alone " << alone << ", separation " << sep.size << " from " << sep.partner);
  CHECK(sep.partner.rfind("range_gain_b", 0) == 0);
  CHECK(sep.size / alone == Approx(1 / std::sqrt(1 - rho * rho)).epsilon(0.02));
  CHECK(sep.rho == Approx(std::abs(rho)).epsilon(0.002));

  // The naming limit, checked against the Neyman-Pearson rule it speaks of, built here from the
  // test's own columns and the true noise (white, sigma 0.5): hide range_gain at the naming limit
  // a, and the partner at b, its least-squares fit to the same signal (after the intercept). The
  // best rule between the two, the likelihood ratio's midpoint, names each with probability
  // Phi(d / 2), d = |a x_e - b x_f| / sigma; the engine says d / 2 = z_0.9 = 1.2816. The engine
  // estimates sigma from about 500 frames (relative SE 1 / sqrt(2 n), 3.2 %) and may whiten with
  // a short correlation: 3 such SE on d. Then 4000 draws under each hypothesis, hit rates within
  // 3 binomial SE of Phi(d / 2) with the test's d (checks the rule and the formula together).
  const double z90 = normal_upper_quantile(0.1);
  auto centred = [](std::vector<double> v) {
    double m = 0;
    for (double x : v) m += x;
    m /= static_cast<double>(v.size());
    for (double& x : v) x -= m;
    return v;
  };
  const std::vector<double> xe = centred(s.range), xf = centred(rb);
  double ef = 0, ff = 0;
  for (std::size_t i = 0; i < xe.size(); ++i) ef += xe[i] * xf[i], ff += xf[i] * xf[i];
  const double a = sep.naming_size, b = a * ef / ff;
  std::vector<double> diff(xe.size());  // mu_e - mu_f
  double d2 = 0;
  for (std::size_t i = 0; i < xe.size(); ++i) diff[i] = a * xe[i] - b * xf[i], d2 += diff[i] * diff[i];
  const double sigma = 0.5, d = std::sqrt(d2) / sigma;
  INFO("naming limit " << a << ": d / 2 = " << d / 2 << " (engine: " << z90 << ")");
  CHECK(d / 2 == Approx(z90).epsilon(3 / std::sqrt(2.0 * static_cast<double>(xe.size()))));
  std::mt19937_64 rng(77);
  std::normal_distribution<double> N(0, 1);
  const int draws = 4000;
  int hit_e = 0, hit_f = 0;
  for (int k = 0; k < draws; ++k)
    for (int truth : {0, 1}) {
      // statistic (y - (mu_e + mu_f) / 2) . (mu_e - mu_f): positive names the entry
      double stat = 0;
      for (std::size_t i = 0; i < xe.size(); ++i) {
        const double mu = truth == 0 ? a * xe[i] : b * xf[i];
        stat += (mu + sigma * N(rng) - 0.5 * (a * xe[i] + b * xf[i])) * diff[i];
      }
      (truth == 0 ? hit_e : hit_f) += truth == 0 ? stat > 0 : stat <= 0;
    }
  const double expect = 0.5 * std::erfc(-d / 2 / std::sqrt(2.0)), band = 3 * std::sqrt(expect * (1 - expect) / draws);
  INFO("hits " << hit_e << ", " << hit_f << " of " << draws << ", Phi(d/2) = " << expect);
  CHECK(std::abs(hit_e / double(draws) - expect) < band);
  CHECK(std::abs(hit_f / double(draws) - expect) < band);
  CHECK(std::isinf(r.separation_limits.at("bias_drift@sensor radar").at("m_per_s").naming_size));
  CHECK(std::isinf(r.separation_limits.at("bias_drift@sensor radar").at("m_per_s").size));
  CHECK(r.separation_limits.at("bias_drift@sensor radar").at("m_per_s").partner.rfind("drift_copy", 0) == 0);
}

TEST_CASE("effect search: bad problems are named") {
  Synthetic s = make(1, 0, 0, 0, 0, 0.5);
  s.pb.y[5] = NAN;
  CHECK_THROWS_WITH(search_effects(s.pb, SearchOptions{}), Catch::Contains("observation 5") && Catch::Contains("not finite"));
  Synthetic u = make(1, 0, 0, 0, 0, 0.5);
  std::swap(u.pb.t_s[3], u.pb.t_s[4]);
  CHECK_THROWS_WITH(search_effects(u.pb, SearchOptions{}), Catch::Contains("time order"));
  SearchOptions bad;
  bad.alpha = 0.7;
  CHECK_THROWS_WITH(search_effects(make(1, 0, 0, 0, 0, 0.5).pb, bad), Catch::Contains("alpha"));
}

TEST_CASE("text reports show angles in degrees, other units as they are", "[model_id][units]") {
  const double deg = 180.0 / M_PI;
  CHECK(shown_unit("rad").name == "deg");
  CHECK(shown_unit("rad").factor == Approx(deg));
  CHECK(shown_unit("k_rad").name == "k_deg");
  CHECK(shown_unit("amplitude_glide_rad").name == "amplitude_glide_deg");
  CHECK(shown_unit("rad_per_s").name == "deg_per_s");
  CHECK(shown_unit("course_radps").name == "course_degps");
  CHECK(shown_unit("course_radps").factor == Approx(deg));
  CHECK(shown_unit("1").name == "ratio");
  for (const char* same : {"m", "tau_s", "along_m", "g", "radar", "t_s"}) {
    CHECK(shown_unit(same).name == same);
    CHECK(shown_unit(same).factor == 1.0);
  }
}

TEST_CASE("noise model: sample_noise draws the model that whiten() whitens", "[model_id][injection]") {
  // 4000 irregular frames of a three-part model (nominal component with a varying gain, a
  // further Gauss-Markov part, white). Whitened under the same model the innovations are iid
  // N(0, 1): their mean square has 4000 degrees of freedom (chi-square band, 99.9 %) and their
  // lag-one correlation is within 3.29 / sqrt(n) of 0. Whitened as white noise, the lag-one
  // correlation is far outside (the check can fail).
  std::mt19937_64 rng(2);
  std::uniform_real_distribution<double> U(0, 1);
  std::vector<double> t, h;
  for (double x = 0; t.size() < 4000; x += 0.5 + U(rng)) t.push_back(x), h.push_back(0.5 + U(rng));
  NoiseParams p;
  p.s2 = 2, p.lambda = 0.6, p.tau_s = 5, p.nom_share = 0.2, p.nom_tau_s = 30;
  const Eigen::VectorXd e = sample_noise(t, h, p, rng);
  auto innovations = [&](const NoiseParams& q) {
    Eigen::MatrixXd W = e;
    whiten(t, h, q, {}, W);
    return Eigen::VectorXd(W.col(0));
  };
  auto lag1 = [](const Eigen::VectorXd& w) {
    const auto n = w.size();
    return w.head(n - 1).dot(w.tail(n - 1)) / w.squaredNorm();
  };
  const Eigen::VectorXd w = innovations(p);
  const double n = static_cast<double>(w.size());
  const auto band = rnav_test::variance_ratio_band(n);
  INFO("mean square " << w.squaredNorm() / n << ", lag-1 correlation " << lag1(w));
  CHECK(band.contains(w.squaredNorm() / n));
  CHECK(std::abs(lag1(w)) < rnav_test::kZ999 / std::sqrt(n));
  NoiseParams white;
  white.s2 = p.s2;
  CHECK(std::abs(lag1(innovations(white))) > 10 / std::sqrt(n));
  // the same seed draws the same noise; the outlier mixture adds heavy tails at its rate
  std::mt19937_64 a(7), b(7);
  CHECK(sample_noise(t, h, p, a) == sample_noise(t, h, p, b));
  NoiseParams q = white;
  q.p_out = 0.05, q.s_out2 = 400;
  std::mt19937_64 c(8);
  const Eigen::VectorXd o = sample_noise(t, h, q, c);
  int big = 0;
  for (Eigen::Index i = 0; i < o.size(); ++i) big += std::abs(o(i)) > 6 * std::sqrt(q.s2);  // N(0, 2) alone: ~1e-9
  // outliers beyond 6 sigma: 0.05 P(|N(0, 402)| > 8.5) = 0.05 * 0.672 per frame, 134 expected;
  // binomial SD 11.3: a 3.29-SD band
  CHECK(std::abs(big - 134.4) < rnav_test::kZ999 * 11.3);
}

namespace {
// The naming rate of `entry` injected at `size` into n fresh draws of r's identified noise around
// r's fitted nominal model (the test's own bootstrap, independent of measure_injected_limits).
double fresh_rate(const Problem& pb, const SearchResult& r, std::size_t entry, double size, int n, std::uint64_t seed) {
  const Eigen::MatrixXd C = pb.catalogue[entry].columns(0);
  SearchOptions o;
  o.score_holdout = false;
  int named = 0;
  std::mt19937_64 rng(seed);
  for (int k = 0; k < n; ++k) {
    Problem q = pb;
    NoiseParams np = r.noise[0].fit.params;
    np.p_out = 0, np.s_out2 = 0;
    const Eigen::VectorXd w = sample_noise(pb.t_s, {}, np, rng);
    for (std::size_t i = 0; i < q.y.size(); ++i) {
      const auto ii = static_cast<Eigen::Index>(i);
      q.y[i] = r.nuisance_fit(ii) + size * C(ii, 0) + w(ii);
    }
    const SearchResult s = search_effects(q, o);
    for (const auto& f : s.effects) named += f.entry == entry;
  }
  return static_cast<double>(named) / n;
}
}  // namespace

TEST_CASE("injected limits: the stated naming size is named at about the stated rate", "[model_id][injection]") {
  // The nominal problem's range_gain limit measured by injection (check batches of 20). Fresh
  // injections drawn by this test (60 at the stated size, 60 at half of it): at the stated size
  // the rate is 0.9 up to the size's own error (a check batch of 20, CP interval about +-0.15)
  // and the binomial SD of 60 draws (0.039): at least 0.7; at half the size a detection test
  // with P = Phi(a / SE - z_crit) (z_crit about 3.7 here) names it with probability about 0.15,
  // so at most 0.6. A limit stated 2x too large or too small fails one of the two.
  const Synthetic s = make(21, 0, 0, 0, 0, 0.5);
  SearchOptions o;
  o.injection.injections = 20;
  o.injection.entries = {"range_gain"};
  o.injection.threads = 2;
  const SearchResult r = search_effects(s.pb, o);
  REQUIRE(r.injected.count("range_gain@sensor radar"));
  const InjectedLimit& L = r.injected.at("range_gain@sensor radar").at("1");
  INFO("Fisher " << L.fisher << ", named at " << L.named.size << " (" << L.named.hits << "/" << L.named.n << "), detected at "
                 << L.detected.size << ", ladder " << L.ladder.size() << " rungs");
  REQUIRE(std::isfinite(L.named.size));
  // the check batch stops once its verdict on 20 is settled: 15 hits (every count of 15-20 of
  // 20 has an interval containing 0.9), or 6 misses. This limit's check was accepted (a limit
  // whose three checks all fail is stated with the last one's count, not so here)
  CHECK(L.named.n <= 20);
  CHECK(L.named.hits == 15);
  CHECK(L.named.n - L.named.hits <= 5);
  CHECK(L.named.lo <= static_cast<double>(L.named.hits) / L.named.n);
  CHECK(static_cast<double>(L.named.hits) / L.named.n <= L.named.hi);
  CHECK(L.named.lo <= 0.9);
  CHECK(0.9 <= L.named.hi);
  // each ladder rung stopped once both its verdicts (rate >= 0.9 of 10) were settled
  for (const auto& rg : L.ladder) {
    if (rg.n > 10) continue;  // a failed check batch that joined the ladder
    CHECK((rg.named >= 9 || rg.n - rg.named >= 2));
    CHECK((rg.detected >= 9 || rg.n - rg.detected >= 2));
  }
  CHECK(L.detected.size <= L.named.size * 1.0001);  // detected (named or stood in for) never needs more
  CHECK(r.injected.size() == 1);                    // only the entry asked for
  const double at = fresh_rate(s.pb, r, 0, L.named.size, 60, 4242);
  const double half = fresh_rate(s.pb, r, 0, 0.5 * L.named.size, 60, 4343);
  INFO("fresh naming rate " << at << " at the stated size, " << half << " at half of it");
  CHECK(at >= 0.7);
  CHECK(half <= 0.6);
  // deterministic whatever the number of threads
  o.injection.threads = 1;
  const SearchResult r1 = search_effects(s.pb, o);
  const InjectedLimit& L1 = r1.injected.at("range_gain@sensor radar").at("1");
  CHECK(L1.named.size == L.named.size);
  CHECK(L1.named.hits == L.named.hits);
  CHECK(L1.ladder.size() == L.ladder.size());
}

TEST_CASE("injected limits: parameters measured one per thread give what one thread gives", "[model_id][injection]") {
  // Two parameters on two threads run at once, each batch one injection at a time; on one
  // thread one after the other. Each parameter must get the same ladder, sizes and counts (its
  // injections draw from their own streams); a thread's kept state leaking into another's
  // search, or a count cut out of index order, would change them. The progress gives one line
  // per parameter as it is done, counted 1 and 2 whichever finishes first.
  const Synthetic s = make(23, 0, 0, 0, 0, 0.5);
  SearchOptions o;
  o.injection.injections = 10;
  o.injection.ladder_injections = 5;
  o.injection.entries = {"range_gain", "bias_drift"};
  std::vector<std::string> lines;
  std::mutex m;
  o.injection.progress = [&](const std::string& l) {
    const std::lock_guard<std::mutex> lock(m);
    lines.push_back(l);
  };
  o.injection.threads = 2;
  const SearchResult r2 = search_effects(s.pb, o);
  o.injection.threads = 1;
  o.injection.progress = nullptr;
  const SearchResult r1 = search_effects(s.pb, o);
  REQUIRE(r2.injected.size() == 2);
  REQUIRE(r1.injected.size() == 2);
  for (const auto& [entry, params] : r1.injected)
    for (const auto& [param, L1] : params) {
      INFO(entry << " " << param);
      const InjectedLimit& L2 = r2.injected.at(entry).at(param);
      CHECK(L2.named.size == L1.named.size);
      CHECK(L2.named.n == L1.named.n);
      CHECK(L2.named.hits == L1.named.hits);
      CHECK(L2.detected.size == L1.detected.size);
      REQUIRE(L2.ladder.size() == L1.ladder.size());
      for (std::size_t k = 0; k < L1.ladder.size(); ++k) {
        CHECK(L2.ladder[k].size == L1.ladder[k].size);
        CHECK(L2.ladder[k].n == L1.ladder[k].n);
        CHECK(L2.ladder[k].named == L1.ladder[k].named);
        CHECK(L2.ladder[k].detected == L1.ladder[k].detected);
      }
    }
  REQUIRE(lines.size() == 3);
  CHECK_THAT(lines[1], Catch::StartsWith("1 of 2, "));
  CHECK_THAT(lines[2], Catch::StartsWith("2 of 2, "));
}

TEST_CASE("injected limits: on a known hit curve the stated sizes are hit at 90 % on average", "[model_id][injection]") {
  // The ladder alone (measure_ladder through ladder_curve.hpp), its injections drawn from a probit curve of slope 4.8 in
  // log a (what a detection test with P = Phi(a / SE - z_crit) gives at its 90 % point, the
  // prior the ladder's fit carries), with the true 90 % point at 0.2, 1.2 and 8 times the Fisher
  // limit it starts from (the landing flight's site offsets, most entries, the range gain), and
  // one curve whose detection needs half the named size. Over 400 ladders each, the true rate at
  // the stated size must average 0.90: the bound is 4 standard errors of that mean (from the
  // sample's own SD, about 0.07, so about 0.014) plus the bias allowed: 0.01 where named and
  // detected share a curve (over 3000 ladders, rnav_ladder_study: 0.891, 0.903 and 0.900 at the
  // three points). Where detection needs half the named size the named sizes are hit at 0.886
  // and the detected at 0.915 (3000 ladders: biases of 0.014 and 0.015, a dozen SE; a check
  // accepts a size hit at 0.8 four times in five, so a fit that fell low is seldom corrected;
  // docs/diagnosis.md states it), and 0.03 is allowed there: a known shortfall, not a target. A
  // size stated 10 % too large moves the rate by about +0.05 (the curve's slope at 90 %:
  // 4.8 phi(z_0.9) = 0.84 per unit log a, less as the rate nears 1) and fails either bound (it
  // gave 0.94-0.96). The ladder must also stop: at most the rungs and checks its options allow.
  InjectionOptions io;
  io.injections = 20;
  io.threads = 1;
  const int max_draws = io.max_ladder * io.ladder_injections + 1 * io.ladder_injections + 2 * 3 * io.injections;
  constexpr int kLadders = 400;
  for (const HitCurve k : {HitCurve{4.8, 0.2, 0.2}, HitCurve{4.8, 1.2, 1.2}, HitCurve{4.8, 8, 8}, HitCurve{4.8, 2.4, 1.2}}) {
    std::vector<double> named, detected;
    double draws = 0;
    for (int s = 0; s < kLadders; ++s) {
      const LadderOutcome o = ladder_on_curve(k, 0.9, io, 1000 + static_cast<std::uint64_t>(s));
      named.push_back(o.named_rate);
      detected.push_back(o.detected_rate);
      draws += o.injections;
      REQUIRE(o.injections <= max_draws);
    }
    for (const auto* x : {&named, &detected}) {
      const double m = rnav_test::mean(*x), se = std::sqrt(rnav_test::sample_variance(*x) / kLadders);
      INFO("curve a90 named " << k.a_named << ", detected " << k.a_detected << ": "
                              << (x == &named ? "named" : "detected") << " rate mean " << m << ", SE " << se
                              << ", injections per ladder " << draws / kLadders);
      const double bias_allowed = k.a_named == k.a_detected ? 0.01 : 0.03;
      CHECK(std::abs(m - 0.9) <= 4 * se + bias_allowed);
    }
  }
  // bad curves are refused
  CHECK_THROWS_WITH(ladder_on_curve(HitCurve{4.8, 1, 2}, 0.9, io, 1), Catch::Contains("a_detected <= a_named"));
  CHECK_THROWS_WITH(ladder_on_curve(HitCurve{0, 1, 1}, 0.9, io, 1), Catch::Contains("slope"));
}

TEST_CASE("injected limits: a detection limit near or above the naming limit is stated there, from its batch", "[model_id][injection]") {
  // Every injection named is detected, so at the naming limit the detected rate is at least the
  // named one: a detection limit fitted above it, or less than 12 % below it (where the curves'
  // slope is the prior's, 4.8, the detected rate there stays under 97 %), is stated at the
  // naming limit with the named batch's detections. Hit curves as in ladder_curve.hpp (one
  // uniform per injection, named below Phi at a_named, detected below Phi at a_detected). Every
  // ladder states a detection limit at most the naming limit, and one within 12 % below it is
  // the naming limit itself (a refit after a failed detection check is capped there too). With the two 90 % points 5 % apart most share (the 3 % window before shared
  // only fits that fell within 3 % of each other); a factor 2 apart none does.
  InjectionOptions io;
  io.injections = 20;
  io.threads = 1;
  auto draw_on = [](double a_named, double a_detected, std::uint64_t seed) {
    return [=](double a, std::size_t batch, int i) {
      std::mt19937_64 rng(seed * 1000003 + batch * 1009 + static_cast<std::uint64_t>(i));
      const double u = std::uniform_real_distribution<double>(0, 1)(rng);
      const double z = normal_upper_quantile(0.1);
      return InjectionHit{u < normal_cdf(4.8 * std::log(a / a_named) + z), u < normal_cdf(4.8 * std::log(a / a_detected) + z)};
    };
  };
  constexpr double kSameRatio = 0.8826;  // exp(-(z_0.97 - z_0.9) / 4.8)
  constexpr int kSeeds = 20;
  int near_shared = 0, apart_shared = 0;
  for (std::uint64_t seed = 1; seed <= kSeeds; ++seed)
    for (const double a_detected : {1.14, 0.6}) {
      const InjectedLimit L = measure_ladder(draw_on(1.2, a_detected, seed), 1.0, 0.9, io);
      INFO("seed " << seed << ", a_detected " << a_detected << ": named " << L.named.size << " (" << L.named.hits << "/"
                   << L.named.n << "), detected " << L.detected.size << " (" << L.detected.hits << "/" << L.detected.n << ")");
      CHECK(L.detected.size <= L.named.size);
      if (L.detected.size >= kSameRatio * L.named.size) CHECK(L.detected.size == L.named.size);
      const bool shared = L.detected.size == L.named.size && L.detected.n == L.named.n;
      if (shared) CHECK(L.detected.hits >= L.named.hits);
      (a_detected > 1 ? near_shared : apart_shared) += shared;
    }
  CHECK(near_shared >= kSeeds / 2);
  CHECK(apart_shared == 0);
}

TEST_CASE("injected limits: an unknown entry is named, 0 injections keep the Fisher limits", "[model_id][injection]") {
  const Synthetic s = make(22, 0, 0, 0, 0, 0.5);
  SearchOptions o;
  o.injection.injections = 5;
  o.injection.entries = {"range_gian"};
  CHECK_THROWS_WITH(search_effects(s.pb, o), Catch::Contains("range_gian"));
  o.injection.entries = {"bias_step:m"};
  o.injection.max_ladder = 1;
  CHECK_THROWS_WITH(search_effects(s.pb, o), Catch::Contains("max_ladder"));
  o.injection.injections = 0;
  const SearchResult r = search_effects(s.pb, o);
  CHECK(r.injected.empty());
  CHECK(r.detection_limits.count("range_gain@sensor radar"));
}

TEST_CASE("effect search: a run of large residuals is not named outliers", "[model_id][outliers]") {
  // Gross errors strike single frames; 12 consecutive frames 12 sigma off are a burst the noise
  // model underrates, flagged as a run. Without the isolation rule they would be named outliers.
  Synthetic s = make(11, 0, 0, 0, 0, 0.5);
  for (std::size_t i = 200; i < 212; ++i) s.pb.y[i] += 6.0;
  const SearchResult r = search_effects(s.pb, SearchOptions{});
  INFO("flagged " << s.pb.size() - static_cast<std::size_t>(r.noise[0].fit.n) << ", in runs " << r.noise[0].outliers_in_runs);
  CHECK(r.noise[0].outliers_in_runs >= 6);
  CHECK_FALSE(r.noise[0].outliers_named);
}

TEST_CASE("effect search: a step's null may not use slow noise that exists only to absorb it", "[model_id][scan]") {
  // A step of 0.3 in white noise of sigma 0.5 (about 6 SE; 30 seeds). Profiled over the whole
  // noise family (null_set_q = 0) the null explains much of it as a slow Gauss-Markov wander;
  // with the null's noise among the models the data allow once the step is in (null_set_q = 9)
  // the null's maximum is over fewer models, so the statistic can only grow: paired over the
  // same flights, the step is named by the restricted test in flights the profile misses (5 of
  // 30 against 11 of 30 when written) and not the other way round.
  int only9 = 0, only0 = 0, named0 = 0, named9 = 0;
  for (std::uint64_t seed = 1; seed <= 30; ++seed) {
    const Synthetic s = make(500 + seed, 0, 0.3, 0, 0, 0.5);
    SearchOptions o;
    o.null_set_q = 0;
    bool n0 = false, n9 = false;
    for (const auto& e : search_effects(s.pb, o).effects) n0 = n0 || e.name == "bias_step";
    o.null_set_q = 9;
    for (const auto& e : search_effects(s.pb, o).effects) n9 = n9 || e.name == "bias_step";
    only9 += n9 && !n0, only0 += n0 && !n9, named0 += n0, named9 += n9;
  }
  INFO("step named in " << named0 << " of 30 (profile LR) and " << named9 << " of 30 (null among the set); only by the "
                        "profile " << only0 << ", only by the restricted null " << only9);
  CHECK(only0 == 0);
  CHECK(only9 >= 4);
}

TEST_CASE("effect search: a mid-span step is named as a step, not as the drift that explains most of it", "[model_id][scan]") {
  // A step at mid-span is three quarters a straight line: a one-parameter drift, tested under the
  // noise re-identified with it, explains 3/4 of the step's 2 log LR without a scan to pay for.
  // The candidates are ranked on one footing (each with its best noise, each paying its degrees
  // of freedom and its scan), so the step is named where its likelihood beats the drift's by
  // more than its scan costs. Step 0.3 in white noise of sigma 0.5 at t = 100 s of 200 s (about
  // 6 SE), 40 seeds. With this ranking the step is named in 22 and a drift alone in 11; when the
  // entry whose own test had the smallest p entered (the drift, by GLS under noise re-identified
  // with it), the step in 15 and a drift alone in 16. The bound: more than half. A rule that
  // names the step with the old rate (15/40) reaches 21 of 40 with probability about 4 %.
  int step = 0, drift_only = 0;
  for (std::uint64_t seed = 1; seed <= 40; ++seed) {
    const Synthetic s = make(900 + seed, 0, 0.3, 0, 0, 0.5, 100);
    bool st = false, dr = false;
    for (const auto& e : search_effects(s.pb, SearchOptions{}).effects) st = st || e.name == "bias_step", dr = dr || e.name == "bias_drift";
    step += st, drift_only += dr && !st;
  }
  INFO("step named in " << step << " of 40, a drift alone in " << drift_only);
  CHECK(step >= 21);
  CHECK(drift_only < step);
}

TEST_CASE("effect search: a drift chosen first gives way to the step that explains the residual better", "[model_id][scan]") {
  // The mid-span step above, paired over the same 40 flights with and without the swap
  // (SearchOptions::swap_rivals). Forward selection ranks by the plug-in test, where the step
  // pays its scan; when the drift enters first the step given the drift no longer passes. The
  // swap compares the two on the joint likelihood (profile, AIC's cost for the step's scanned
  // time) and names the step. Measured when written: 11 flights name a drift alone without the
  // swap, all 11 the step with it, and no flight goes the other way. The bounds: at least 2
  // rescued (a swap that never fires fails), none lost.
  int rescued = 0, lost = 0, drift_without = 0;
  for (std::uint64_t seed = 1; seed <= 40; ++seed) {
    const Synthetic s = make(900 + seed, 0, 0.3, 0, 0, 0.5, 100);
    auto named = [&](bool swap) {
      SearchOptions o;
      o.swap_rivals = swap;
      bool st = false, dr = false;
      for (const auto& e : search_effects(s.pb, o).effects) st = st || e.name == "bias_step", dr = dr || e.name == "bias_drift";
      return std::make_pair(st, dr && !st);
    };
    const auto [st0, dr0] = named(false);
    const auto [st1, dr1] = named(true);
    drift_without += dr0;
    rescued += dr0 && st1;
    lost += st0 && dr1;
  }
  INFO("a drift alone without the swap in " << drift_without << " of 40; the step with it in " << rescued << " of them; lost " << lost);
  CHECK(rescued >= 2);
  CHECK(lost == 0);
}

TEST_CASE("effect search: a family size below the problem's own is refused, a larger one splits alpha further", "[model_id]") {
  const Synthetic s = make(23, 0, 1.0, 0, 0, 0.5);  // a step of 2 sigma: named at any family size here
  SearchOptions o;
  const SearchResult own = search_effects(s.pb, o);
  o.family_size = own.family_size - 1;
  CHECK_THROWS_WITH(search_effects(s.pb, o), Catch::Contains("family_size"));
  o.family_size = 10 * own.family_size;
  const SearchResult big = search_effects(s.pb, o);
  CHECK(big.family_size == 10 * own.family_size);
  REQUIRE(!own.effects.empty());
  REQUIRE(!big.effects.empty());
  // the same evidence, ten times the tests: log10 p adjusted up by exactly one
  CHECK(big.effects[0].log10_p == Approx(own.effects[0].log10_p + 1).margin(1e-9));
}

TEST_CASE("effect search: progress names each round, candidate and the report, and the searches inside injections are quiet",
          "[model_id][progress]") {
  // A real step (the search tests candidates until it enters) with 5 injections of range_gain:
  // the injections run whole searches of their own, which must not report (their lines would
  // drown the search's own); the lines may come from several threads, so they are collected
  // under a lock.
  const Synthetic s = make(7, 0, 3.0, 8.0, 0, 0.5);
  SearchOptions o;
  o.injection.injections = 5;
  o.injection.entries = {"range_gain"};
  o.injection.threads = 2;
  std::mutex m;
  std::vector<std::string> lines;
  o.progress = [&](const std::string& line) {
    const std::lock_guard<std::mutex> lock(m);
    lines.push_back(line);
  };
  const SearchResult r = search_effects(s.pb, o);
  REQUIRE(!r.effects.empty());
  REQUIRE(!lines.empty());
  auto count = [&](const std::string& part) {
    return std::count_if(lines.begin(), lines.end(), [&](const std::string& l) { return l.find(part) != std::string::npos; });
  };
  CHECK(lines.front().rfind("round 1 of at most 3, noise identification of", 0) == 0);
  CHECK(count("round 1 of at most 3, selection step 1: testing bias_step") >= 1);
  CHECK(count("report: ") == 1);
  CHECK(lines.back().rfind("report: ", 0) == 0);  // nothing from the injections after it
  // one noise identification line per round run, none from the injections' own searches
  CHECK(count("noise identification") <= 3);
}

namespace {
// A range channel whose range passes through a smooth step at t = 100 s (r = 3000 + 400
// tanh((t - 100) / width)), white noise 0.5 m, a 0.3 m bias step at 100 s hidden; catalogue: the
// physical range_gain (column r) and the scanned bias_step (41 times, 20 ... 180 s).
Problem smooth_step_problem(std::uint64_t seed, double width_s) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> N(0, 1);
  Problem pb;
  pb.channels.push_back({"radar:1:range", "radar", "1", "m", 0.5});
  std::vector<double> range;
  for (double t = 0.5; t < 200; t += 0.5) {
    const double r = 3000 + 400 * std::tanh((t - 100) / width_s);
    range.push_back(r);
    pb.channel.push_back(0);
    pb.t_s.push_back(t);
    pb.y.push_back((t >= 100 ? 0.3 : 0.0) + 0.5 * N(rng));
    pb.estimation.push_back(t < 130);
  }
  add_gain_and_step(pb, range);
  return pb;
}
}  // namespace

TEST_CASE("effect search: a scanned step does not replace a physical cause that explains the data nearly as well", "[model_id][scan]") {
  // A 0.3 m step (about 6 SE) hidden where the range passes through a 20 s smooth step: the
  // physical range_gain (no scan) ranks first and explains most of it; the step explains it
  // better, but on 400 samples by less than explaining as well besides (as_well_margin: 2 ln 41
  // = 7.4, beside AIC's 2 per parameter and scanned value), so the physical cause stays, named
  // with the step as confounded (swap_for_better). Measured when written, 30 seeds: the step
  // named in 1 with the margin and in 17 without it (the gain in 29 and 13). The bounds: the
  // step in at most 5 and the gain in at least 25; without the margin P(step <= 5) is about
  // 1e-5 (binomial, p = 17/30), with it P(step >= 6) about 1e-3 (p = 1/30).
  int gain = 0, step = 0, step_closer = 0;
  for (std::uint64_t seed = 1; seed <= 30; ++seed) {
    const SearchResult r = search_effects(smooth_step_problem(7000 + seed, 20.0), SearchOptions{});
    for (const auto& e : r.effects) {
      gain += e.name == "range_gain", step += e.name == "bias_step";
      for (const auto& c : e.confounded_with) step_closer += e.name == "range_gain" && c.name == "bias_step" && c.dlr < 0;
    }
  }
  INFO("range_gain named in " << gain << " of 30, bias_step in " << step << "; the step explained the data better in "
                              << step_closer << " of the gain's");
  CHECK(step <= 5);
  CHECK(gain >= 25);
  CHECK(step_closer >= 10);  // the margin was needed: the step did explain better there
}

namespace {
// Two search reports equal bit for bit: the effects chosen, their estimates and statistics,
// each channel's noise and the held-out effects.
void check_same_report(const SearchResult& x, const SearchResult& y) {
  REQUIRE(x.effects.size() == y.effects.size());
  for (std::size_t i = 0; i < x.effects.size(); ++i) {
    CHECK(x.effects[i].name == y.effects[i].name);
    CHECK(x.effects[i].estimate == y.effects[i].estimate);
    CHECK(x.effects[i].lr == y.effects[i].lr);
    CHECK(x.effects[i].kept_lr == y.effects[i].kept_lr);
  }
  REQUIRE(x.noise.size() == y.noise.size());
  for (std::size_t c = 0; c < x.noise.size(); ++c) {
    CHECK(x.noise[c].fit.params.tau_s == y.noise[c].fit.params.tau_s);
    CHECK(x.noise[c].fit.params.s2 == y.noise[c].fit.params.s2);
  }
  CHECK(x.holdout_effects == y.holdout_effects);
}
}  // namespace

TEST_CASE("effect search: candidates tested several at once give the same report as one at a time", "[model_id]") {
  // Forward selection tests its ranked candidates `threads` at a time and takes the first that
  // passes in rank order: the chosen entries, estimates and statistics must be bit-identical.
  for (std::uint64_t seed : {3u, 901u, 7003u}) {
    const Problem pb = seed == 7003u ? smooth_step_problem(seed, 20.0) : make(seed, seed == 3u ? 3e-3 : 0.0, 0.3, 8.0, 0, 0.5).pb;
    SearchOptions o;
    const SearchResult one = search_effects(pb, o);
    for (int threads : {2, 3}) {
      o.threads = threads;
      const SearchResult many = search_effects(pb, o);
      INFO("seed " << seed << ", threads " << threads);
      check_same_report(many, one);
    }
  }
  SearchOptions bad;
  bad.threads = 0;
  CHECK_THROWS_WITH(search_effects(make(1, 0, 0, 0, 0, 0.5).pb, bad), Catch::Contains("threads >= 1"));
}

TEST_CASE("noise memo: a remembered fit is the fit identify_noise gives, and only for the same inputs", "[model_id][memo]") {
  // a 300-frame Gauss-Markov series (tau 20 s, sampled at 1 s) and one fixed-effect column
  std::mt19937_64 rng(71);
  std::normal_distribution<double> g;
  std::vector<double> t;
  Eigen::VectorXd e(300);
  Eigen::MatrixXd X(300, 1), X2(300, 1);
  double x = 0;
  for (int i = 0; i < 300; ++i) {
    t.push_back(i);
    x = std::exp(-1.0 / 20) * x + std::sqrt(1 - std::exp(-2.0 / 20)) * g(rng);
    e(i) = x + 0.3 * g(rng);
    X(i, 0) = i < 150 ? 0.0 : 1.0;
    X2(i, 0) = i < 100 ? 0.0 : 1.0;
  }
  NoiseIdOptions o;
  search_detail::NoiseMemo memo;
  const NoiseFit direct = identify_noise(t, {}, e, X, o);
  const NoiseFit first = memo.fit(t, {}, e, X, o, nullptr);
  const NoiseFit again = memo.fit(t, {}, e, X, o, nullptr);
  CHECK(memo.misses() == 1);
  CHECK(memo.hits() == 1);
  for (const NoiseFit* f : {&first, &again}) {
    CHECK(f->params.lambda == direct.params.lambda);
    CHECK(f->params.tau_s == direct.params.tau_s);
    CHECK(f->params.s2 == direct.params.s2);
    CHECK(f->loglik_ml == direct.loglik_ml);
    CHECK(f->outlier == direct.outlier);
  }
  // another column, other options, given flags: each computed afresh; the same series asked
  // again (another channel or another search with the same frames): the stored fit
  const NoiseFit other = memo.fit(t, {}, e, X2, o, nullptr);
  CHECK(other.loglik_ml == identify_noise(t, {}, e, X2, o).loglik_ml);
  CHECK(memo.fit(t, {}, e, X, o, nullptr).loglik_ml == direct.loglik_ml);
  NoiseIdOptions pm = o;
  pm.profile_ml = true;
  CHECK(memo.fit(t, {}, e, X, pm, nullptr).loglik_ml == identify_noise(t, {}, e, X, pm).loglik_ml);
  const std::vector<char> skip(300, 0);
  memo.fit(t, {}, e, X, o, &skip);
  CHECK(memo.misses() == 4);
  CHECK(memo.hits() == 2);
  // a series its columns span throws DegenerateSeries, from the memo as from identify_noise
  Eigen::MatrixXd span = Eigen::MatrixXd::Identity(300, 300).leftCols(298);
  CHECK_THROWS_AS(memo.fit(t, {}, e, span, o, nullptr), DegenerateSeries);
  CHECK_THROWS_AS(memo.fit(t, {}, e, span, o, nullptr), DegenerateSeries);
  CHECK(memo.hits() == 3);
  // a confidence set is ranked from the series' profile grid, keyed apart from a fit: the grid
  // is computed once, and sets at any level read it
  const auto set4 = memo.confidence_set(t, {}, e, X, o, skip, 4.0);
  const auto direct4 = noise_confidence_set(t, {}, e, X, o, skip, 4.0);
  REQUIRE(set4.size() == direct4.size());
  for (std::size_t i = 0; i < set4.size(); ++i) {
    CHECK(set4[i].lambda == direct4[i].lambda);
    CHECK(set4[i].tau_s == direct4[i].tau_s);
    CHECK(set4[i].s2 == direct4[i].s2);
  }
  CHECK(memo.confidence_set(t, {}, e, X, o, skip, 4.0).size() == set4.size());
  CHECK(memo.confidence_set(t, {}, e, X, o, skip, 9.0).size() == noise_confidence_set(t, {}, e, X, o, skip, 9.0).size());
  CHECK(memo.misses() == 6);
  CHECK(memo.hits() == 5);
  // a profile fit with those flags reads the same grid (and is what identify_noise gives)
  const NoiseFit pf = memo.fit(t, {}, e, X, pm, &skip);
  CHECK(memo.misses() == 7);
  CHECK(memo.hits() == 6);
  CHECK(pf.loglik_ml == identify_noise(t, {}, e, X, pm, &skip).loglik_ml);
}

TEST_CASE("noise identification: the profile grid gives the profile fit, the confidence sets and loglik_ml_at, bit for bit",
          "[model_id][noise]") {
  // A Gauss-Markov series (tau 20 s) plus white noise, with a step column, a few frames kept
  // out, and a nominal component with a per-frame gain: every path of the grid's arithmetic.
  std::mt19937_64 rng(31);
  std::normal_distribution<double> g;
  std::vector<double> t, h;
  Eigen::VectorXd e(400);
  Eigen::MatrixXd X(400, 2);
  double x = 0;
  for (int i = 0; i < 400; ++i) {
    t.push_back(0.5 * i + (i > 200 ? 7.0 : 0.0));  // a gap of 7 s
    h.push_back(0.5 + i / 400.0);
    x = std::exp(-0.5 / 20) * x + std::sqrt(1 - std::exp(-1.0 / 20)) * g(rng);
    e(i) = x + 0.4 * g(rng) + (i >= 250 ? 0.8 : 0.0);
    X(i, 0) = 1;
    X(i, 1) = i >= 250 ? 1.0 : 0.0;
  }
  std::vector<char> skip(400, 0);
  skip[17] = skip[333] = 1;
  NoiseIdOptions o;
  o.nominal_share = 0.2, o.nominal_tau_s = 40;
  NoiseIdOptions pm = o;
  pm.profile_ml = true;
  const NoiseGrid grid = profile_noise_grid(t, h, e, X, o, skip);
  REQUIRE(grid.points.size() == 1 + 28 * 7);
  // the profile fit: the same with the grid read as computed
  const NoiseFit direct = identify_noise(t, h, e, X, pm, &skip), read = identify_noise_profile(t, h, e, X, pm, skip, grid);
  CHECK(read.loglik_ml == direct.loglik_ml);
  CHECK(read.params.lambda == direct.params.lambda);
  CHECK(read.params.tau_s == direct.params.tau_s);
  CHECK(read.params.s2 == direct.params.s2);
  CHECK(direct.params.lambda > 0);  // a correlated model: the refinement ran from the grid's best
  CHECK_THROWS_AS(identify_noise_profile(t, h, e, X, o, skip, grid), std::invalid_argument);  // not profile mode
  // the confidence set: the same models in the same order
  for (double q : {2.0, 5.0, 20.0}) {
    const std::vector<NoiseParams> set = noise_confidence_set(t, h, e, X, o, skip, q);
    const std::vector<std::size_t> ix = confidence_indices(grid, q);
    REQUIRE(ix.size() == set.size());
    CHECK(set.size() > 1);
    for (std::size_t k = 0; k < ix.size(); ++k) {
      CHECK(grid.points[ix[k]].p.lambda == set[k].lambda);
      CHECK(grid.points[ix[k]].p.tau_s == set[k].tau_s);
      CHECK(grid.points[ix[k]].p.s2 == set[k].s2);
    }
  }
  // loglik_ml_at at each grid model, with other columns (the null's, as the scanned test reads
  // it): the other columns' grid at the same index
  const Eigen::MatrixXd X0 = X.leftCols(1);
  const NoiseGrid grid0 = profile_noise_grid(t, h, e, X0, o, skip);
  for (std::size_t i = 0; i < grid.points.size(); i += 13)
    CHECK(grid0.points[i].ml == loglik_ml_at(t, h, e, X0, grid.points[i].p, skip));
  CHECK(grid0.points[0].ml == loglik_ml_at(t, h, e, X0, grid.points[0].p, skip));  // the null
}

TEST_CASE("noise identification: the refinement reaches the likelihood's maximum where the correlated share is small",
          "[model_id][noise]") {
  // 2 000 frames at 2 Hz: white noise plus a Gauss-Markov part of 3 % of the variance, tau 20 s
  // (the azimuth-only bench flight's bearing noise has this shape: its fit stopped at tau 202 s,
  // lambda 0.11, 3.0 below the maximum at tau 17.7 s, lambda 0.033, when the refinement was two
  // passes of line searches moving tau one grid step each). The profile fit's ML log-likelihood
  // must be at least the best of a dense grid of 48 x 40 models around the truth (loglik_ml_at,
  // every model on it evaluated exactly); the dense grid's best lies below the true maximum, so
  // the 1e-4 allowed is the refinement's stop alone (a step under 1e-3, a rise under 1e-5).
  std::mt19937_64 rng(77);
  std::normal_distribution<double> g;
  const int n = 2000;
  const double lambda = 0.03, tau = 20, dt = 0.5;
  std::vector<double> t;
  Eigen::VectorXd e(n);
  double x = 0;
  const double phi = std::exp(-dt / tau);
  for (int i = 0; i < n; ++i) {
    t.push_back(dt * i);
    x = phi * x + std::sqrt(1 - phi * phi) * g(rng);
    e(i) = std::sqrt(lambda) * x + std::sqrt(1 - lambda) * g(rng);
  }
  const Eigen::MatrixXd X = Eigen::MatrixXd::Ones(n, 1);
  NoiseIdOptions pm;
  pm.profile_ml = true;
  const std::vector<char> none(static_cast<std::size_t>(n), 0);
  const NoiseFit fit = identify_noise(t, {}, e, X, pm, &none);
  REQUIRE(fit.correlated);
  double dense = -INFINITY;
  NoiseParams at;
  for (int i = 0; i < 48; ++i)
    for (int j = 0; j < 40; ++j) {
      NoiseParams p;
      p.tau_s = std::exp(std::log(2.0) + (std::log(400.0) - std::log(2.0)) * i / 47);
      p.lambda = std::exp(std::log(0.003) + (std::log(0.5) - std::log(0.003)) * j / 39);
      const double ll = loglik_ml_at(t, {}, e, X, p, none);
      if (ll > dense) dense = ll, at = p;
    }
  INFO("fit: tau " << fit.params.tau_s << " s, lambda " << fit.params.lambda << ", ML " << fit.loglik_ml
                   << "; dense grid's best: tau " << at.tau_s << " s, lambda " << at.lambda << ", ML " << dense);
  CHECK(fit.loglik_ml >= dense - 1e-4);
  // and the fit is the truth's neighbourhood, not a corner of the box
  CHECK(fit.params.lambda < 0.3);
  CHECK(fit.params.tau_s > 2);
  CHECK(fit.params.tau_s < 400);
}

TEST_CASE("noise identification: the grid's REML and ML log-likelihoods are the dense GLS ones, nearly collinear columns too",
          "[model_id][noise]") {
  // Each grid point's likelihoods against the dense covariance C (s^2 = 1, the point's structure):
  //   ML   -1/2 [n log(RSS / n) + log|C| + n (1 + log 2 pi)],
  //   REML -1/2 [n' log(RSS / n') + log|C| + log|X' C^-1 X| + n' (1 + log 2 pi)],  n' = n - k,
  // RSS the GLS residual's C^-1 norm. Two designs: well conditioned (the likelihood from the
  // whitened Gram matrix), and a column within 1e-6 of another's span (the Gram matrix's pivot
  // under 1e-8: the QR of the whitened columns instead). Tolerance 1e-9 relative: about 1e6
  // times the rounding, room for the 1e-6 column's condition number.
  const std::vector<double> h = [] {
    std::vector<double> v;
    for (int i = 0; i < 60; ++i) v.push_back(0.6 + i / 60.0);
    return v;
  }();
  std::vector<double> t;
  for (int i = 0; i < 60; ++i) t.push_back(0.5 * i + (i > 30 ? 3.0 : 0.0));
  std::mt19937_64 rng(5);
  std::normal_distribution<double> g;
  Eigen::VectorXd e(60);
  for (auto& v : e) v = g(rng);
  NoiseIdOptions o;
  o.nominal_share = 0.25, o.nominal_tau_s = 12;
  for (double tilt : {1.0, 1e-6}) {
    Eigen::MatrixXd X(60, 3);
    for (int i = 0; i < 60; ++i) {
      const double u = t[static_cast<std::size_t>(i)] / 33;
      X(i, 0) = 1, X(i, 1) = u, X(i, 2) = 1 + tilt * u * u;  // near 1 + 0 u^2 when tilt is small
    }
    const NoiseGrid grid = profile_noise_grid(t, h, e, X, o, {});
    for (std::size_t i = 0; i < grid.points.size(); i += 17) {
      NoiseParams p = grid.points[i].p;
      p.s2 = 1;
      // dense: C = L L', X and e whitened by L^-1, least squares by Householder QR (stable where
      // X' C^-1 X is too ill-conditioned to invert)
      const Eigen::LLT<Eigen::MatrixXd> llt(dense_cov(t, h, p));
      const Eigen::MatrixXd Xw = llt.matrixL().solve(X);
      const Eigen::VectorXd ew = llt.matrixL().solve(e);
      const Eigen::HouseholderQR<Eigen::MatrixXd> qr(Xw);
      const double rss = (ew - Xw * qr.solve(ew)).squaredNorm(), n = 60, np = 57;
      double logC = 0, logA = 0;
      for (int j = 0; j < 60; ++j) logC += 2 * std::log(llt.matrixL()(j, j));
      for (int j = 0; j < 3; ++j) logA += 2 * std::log(std::abs(qr.matrixQR()(j, j)));
      const double ml = -0.5 * (n * std::log(rss / n) + logC + n * (1 + std::log(2 * M_PI)));
      const double reml = -0.5 * (np * std::log(rss / np) + logC + logA + np * (1 + std::log(2 * M_PI)));
      INFO("tilt " << tilt << ", point " << i << ": lambda " << p.lambda << ", tau " << p.tau_s);
      CHECK(grid.points[i].ml == Approx(ml).epsilon(1e-9));
      CHECK(grid.points[i].ll == Approx(reml).epsilon(1e-9));
    }
  }
}

TEST_CASE("effect search: the noise a simulation draws keeps the slow wander the identified noise leaves to its trend",
          "[model_id][noise]") {
  // 30 series of 200 s (about 500 frames): a Gauss-Markov wander (sd 2 m, tau 200 s: as slow as
  // the series) plus 0.5 m white noise, no mean effect. The identified noise (a quadratic trend,
  // tau <= span / 4) takes the wander for a trend; the drawn noise (ML, no trend, tau up to the
  // span) must hold it. What a simulation of the series shows of a noise model is the series'
  // mean and its spread about it: over a span T, a Gauss-Markov part of variance q and time
  // constant tau gives E mean^2 = q f and E spread^2 = q (1 - f), f = 2 / x - 2 (1 - e^-x) / x^2,
  // x = T / tau (continuous sampling; the frames are dense against tau), white noise r adds r to
  // the spread. One series determines the wander with about one degree of freedom, so the checks
  // are on means over the 30 series of each model's expectation over the true one, within 3
  // standard errors (their empirical sd / sqrt(30)) of 1; the identified noise's E mean^2 falls
  // below a quarter of the truth. White series of the same length: the wander flag
  // (ChannelNoise::slow_wander) may come up by chance in a few, where the wandering series raise it
  // in most.
  const int kSeries = 30;
  const double sd_wander = 2, tau_wander = 200, sd_white = 0.5, span = 200;
  const auto f_of = [span](double tau) {
    const double x = span / tau;
    return 2 / x - 2 * (1 - std::exp(-x)) / (x * x);
  };
  // E mean^2 and E spread^2 of a noise model over the span
  const auto expect = [&](const NoiseParams& p) {
    const double q = p.s2 * p.lambda, r = p.s2 * (1 - p.lambda), f = p.lambda > 0 ? f_of(p.tau_s) : 0.0;
    return std::make_pair(q * f, q * (1 - f) + r);
  };
  NoiseParams truth;
  truth.s2 = sd_wander * sd_wander + sd_white * sd_white, truth.lambda = sd_wander * sd_wander / truth.s2, truth.tau_s = tau_wander;
  const auto [m2_true, v_true] = expect(truth);
  std::vector<double> mean2_drawn, spread_drawn, mean2_fit;
  int flagged_wander = 0, flagged_white = 0;
  for (int k = 0; k < kSeries; ++k) {
    for (const bool wander : {true, false}) {
      std::mt19937_64 rng(7000 + 2 * k + wander);
      std::uniform_real_distribution<double> U(0, 1);
      Problem pb;
      pb.channels.push_back({"radar:1:range", "radar", "1", "m", sd_white});
      std::vector<double> t;
      for (double ti = 0; ti < span; ti += 0.3 + 0.2 * U(rng)) t.push_back(ti);
      NoiseParams gm;
      gm.s2 = sd_wander * sd_wander, gm.lambda = 0.999, gm.tau_s = tau_wander;
      const Eigen::VectorXd w = sample_noise(t, {}, gm, rng);
      std::normal_distribution<double> N(0, sd_white);
      for (std::size_t i = 0; i < t.size(); ++i) {
        pb.channel.push_back(0);
        pb.t_s.push_back(t[i]);
        pb.y.push_back((wander ? w(static_cast<Eigen::Index>(i)) : 0.0) + N(rng));
        pb.estimation.push_back(true);
      }
      SearchOptions o;
      o.score_holdout = false;
      const SearchResult r = search_effects(pb, o);
      REQUIRE(r.noise.size() == 1);
      const ChannelNoise& cn = r.noise[0];
      REQUIRE(cn.drawn_ok);
      if (wander) {
        mean2_drawn.push_back(expect(cn.drawn.params).first / m2_true);
        spread_drawn.push_back(expect(cn.drawn.params).second / v_true);
        mean2_fit.push_back(expect(cn.fit.params).first / m2_true);
        flagged_wander += cn.slow_wander;
      } else {
        flagged_white += cn.slow_wander;
      }
    }
  }
  const auto [m_m2, sd_m2] = mean_and_sd(mean2_drawn);
  const auto [m_v, sd_v] = mean_and_sd(spread_drawn);
  const auto [m_fit, sd_fit] = mean_and_sd(mean2_fit);
  INFO("E mean^2, drawn / true: " << m_m2 << " (sd " << sd_m2 << "); E spread^2, drawn / true: " << m_v << " (sd " << sd_v
                                  << "); E mean^2, identified / true: " << m_fit << "; wander flagged in " << flagged_wander
                                  << " of " << kSeries << " wandering and " << flagged_white << " of " << kSeries << " white series");
  CHECK(std::abs(m_m2 - 1) < 3 * sd_m2 / std::sqrt(kSeries));
  CHECK(std::abs(m_v - 1) < 3 * sd_v / std::sqrt(kSeries));
  CHECK(m_fit < 0.25);
  CHECK(flagged_wander >= kSeries * 2 / 3);
  CHECK(flagged_white <= 3);
}

TEST_CASE("effect search: the offsets no named effect explains are a random effect across a group's targets, and a target's own effect leaves it out",
          "[model_id]") {
  // Each problem: kTargets range channels of one radar (one offset group), 100 frames over 200 s
  // each with white noise 5 m, each channel's constant offset u_k ~ N(mu, tau^2), mu = -20 m,
  // tau = 10 m (a hull's echo point, unknown per ship); channel 0 also carries an offset of its
  // own (+100 m) that its own catalogue entry (echo_range_offset on target 0) explains. Each
  // channel's mean is known to 0.5 m against tau = 10, so mu's estimate over a problem varies
  // as the u_k's mean (tau / sqrt(7), 3.8 m) and tau^2's as a sample variance on 6 dof; over
  // kProblems problems, the means of both lie within 3 standard errors (their empirical sd /
  // sqrt(kProblems)) of the truth. Channel 0 is left out of the group (explained) in every one.
  // The drawn noise of the grouped channels is identified about each channel's own mean: its
  // sigma stays the 5 m white noise, not the offset (a fit without the mean takes part of a
  // 20 m offset for a slow wander).
  const int kProblems = 40, kTargets = 8, kFrames = 100;
  const double mu = -20, tau = 10, sigma = 5, own = 100;
  std::vector<double> mu_hat, tau2_hat;
  double drawn_sd = 0;
  int drawn_n = 0, left_out = 0, grouped = 0;
  for (int k = 0; k < kProblems; ++k) {
    std::mt19937_64 rng(9100 + k);
    std::normal_distribution<double> N(0, 1);
    Problem pb;
    for (int c = 0; c < kTargets; ++c) {
      pb.channels.push_back({"radar:" + std::to_string(c) + ":range", "radar", std::to_string(c), "m", sigma});
      pb.channels.back().offset_group = "radar:range";
    }
    for (int c = 0; c < kTargets; ++c) {
      const double u = mu + tau * N(rng) + (c == 0 ? own : 0.0);
      for (int i = 0; i < kFrames; ++i) {
        pb.channel.push_back(c);
        pb.t_s.push_back(2.0 * i);
        pb.y.push_back(u + sigma * N(rng));
        pb.estimation.push_back(true);
      }
    }
    const auto n = static_cast<Eigen::Index>(pb.y.size());
    pb.catalogue.push_back({"echo_range_offset", {"radar", "0"}, {"m"}, "target 0's range", "", {}, [n](std::size_t) {
                              Eigen::MatrixXd C = Eigen::MatrixXd::Zero(n, 1);
                              C.topRows(kFrames).setOnes();  // channel 0's frames come first
                              return C;
                            }});
    SearchOptions o;
    o.score_holdout = false;
    const SearchResult r = search_effects(pb, o);
    REQUIRE(r.offsets.size() == 1);
    const OffsetGroup& g = r.offsets[0];
    CHECK(g.group == "radar:range");
    left_out += g.explained == std::vector<std::string>{"radar:0:range"};
    grouped += g.targets == kTargets - 1;
    mu_hat.push_back(g.mean);
    tau2_hat.push_back(g.sd * g.sd);
    for (std::size_t c = 1; c < r.noise.size(); ++c) {
      CHECK(r.noise[c].offset_group == "radar:range");
      drawn_sd += std::sqrt(r.noise[c].drawn.params.s2), ++drawn_n;
    }
    CHECK(r.noise[0].offset_group.empty());
  }
  const auto [m_mu, sd_mu] = mean_and_sd(mu_hat);
  const auto [m_t2, sd_t2] = mean_and_sd(tau2_hat);
  INFO("mu: " << m_mu << " (sd " << sd_mu << "); tau^2: " << m_t2 << " (sd " << sd_t2 << "); drawn sigma " << drawn_sd / drawn_n);
  CHECK(left_out == kProblems);
  CHECK(grouped == kProblems);
  CHECK(std::abs(m_mu - mu) < 3 * sd_mu / std::sqrt(kProblems));
  CHECK(std::abs(m_t2 - tau * tau) < 3 * sd_t2 / std::sqrt(kProblems));
  // the mean of 280 sigma estimates, each from 99 frames (SE about 5 / sqrt(2 * 99) = 0.36 m
  // each, 0.02 m over all): within 5 % of the truth
  CHECK(std::abs(drawn_sd / drawn_n - sigma) < 0.05 * sigma);
}

TEST_CASE("progress clock: the time left is the mean time per part done times the parts left", "[model_id][progress]") {
  CHECK_THROWS_AS(ProgressClock(0), std::invalid_argument);
  const ProgressClock clock(4);
  CHECK_THROWS_AS(clock.left_s(0), std::invalid_argument);
  CHECK_THROWS_AS(clock.left_s(5), std::invalid_argument);
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  CHECK(clock.left_s(4) == 0);
  // one part of four done after >= 50 ms: three more at the same pace. The clock is read twice
  // (spent, then left), so left lies between 3 x the spent before and 3 x the spent after.
  const double before = clock.spent_s(), left = clock.left_s(1), after = clock.spent_s();
  CHECK(before >= 0.05);
  CHECK(left >= 3 * before);
  CHECK(left <= 3 * after);
  // two of four: as much again as spent
  const double b2 = clock.spent_s(), l2 = clock.left_s(2), a2 = clock.spent_s();
  CHECK(l2 >= b2);
  CHECK(l2 <= a2);
}

TEST_CASE("effect search: searches sharing a noise memo report what each gives alone, bit for bit", "[model_id][memo]") {
  // A memo filled by one search answers another of the same data (every fit a hit) and of
  // other data with the same frames (hits where the columns and residuals agree): the reports
  // must equal fresh searches' in every effect, estimate and statistic.
  const Problem a = make(3, 3e-3, 0.3, 8.0, 0, 0.5).pb;
  const Problem b = make(901, 0.0, 0.3, 8.0, 0, 0.5).pb;
  const SearchResult fresh_a = search_effects(a, SearchOptions{});
  const SearchResult fresh_b = search_effects(b, SearchOptions{});
  SearchOptions shared;
  shared.noise_memo = make_noise_memo();
  const SearchResult first_a = search_effects(a, shared);
  const std::size_t misses = shared.noise_memo->misses();
  const SearchResult again_a = search_effects(a, shared);
  CHECK(shared.noise_memo->misses() == misses);  // the second search of a: every fit remembered
  CHECK(shared.noise_memo->hits() > 0);
  const SearchResult then_b = search_effects(b, shared);
  CHECK(shared.noise_memo->misses() > misses);  // b's own series: computed
  check_same_report(first_a, fresh_a);
  check_same_report(again_a, fresh_a);
  check_same_report(then_b, fresh_b);
}
