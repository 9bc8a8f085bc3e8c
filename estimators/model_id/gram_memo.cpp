#include "estimators/model_id/gram_memo.hpp"

#include "estimators/model_id/byte_hash.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>
#include <utility>

namespace rnav {

namespace {

// What an entry of the memo holds beyond its sums: the key, the list's and the index's nodes.
constexpr std::size_t kEntryOverhead = 96;

// One entry under each of J models from two columns whitened frame-major (w[i * J + j]): the
// sum over the frames of wa wb in frame order from 0, the models' sums interleaved. A frame kept
// out is whitened to 0: its product adds +0, which changes no sum (a sum from +0 is never -0).
// Two doubles in one SSE2 register (GCC's vector extension; element-wise IEEE arithmetic, each
// lane's result what the scalar operation gives).
typedef double v2d __attribute__((vector_size(16)));

template <std::size_t J>
void sums(const double* wa, const double* wb, Eigen::Index n, std::array<double, GramMemo::kMaxModels>& s) {
  constexpr std::size_t P = J / 2;  // models in pairs, one pair per register (an odd last alone)
  v2d acc[P > 0 ? P : 1] = {};
  double last = 0;
  for (Eigen::Index i = 0; i < n; ++i) {
    const double* ra = wa + static_cast<std::size_t>(i) * J;
    const double* rb = wb + static_cast<std::size_t>(i) * J;
    for (std::size_t p = 0; p < P; ++p) acc[p] += v2d{ra[2 * p], ra[2 * p + 1]} * v2d{rb[2 * p], rb[2 * p + 1]};
    if (J % 2 == 1) last += ra[J - 1] * rb[J - 1];
  }
  for (std::size_t p = 0; p < P; ++p) s[2 * p] = acc[p][0], s[2 * p + 1] = acc[p][1];
  if (J % 2 == 1) s[J - 1] = last;
}

// sums<J> of two entries that share column wb, (wa, wb) and (wc, wb), in one pass over the
// frames (wb read once): each entry's sums in sums<J>'s order, the same values bit for bit
// (w_a w_b = w_b w_a exactly).
template <std::size_t J>
void sums2(const double* wa, const double* wc, const double* wb, Eigen::Index n,
           std::array<double, GramMemo::kMaxModels>& sa, std::array<double, GramMemo::kMaxModels>& sc) {
  constexpr std::size_t P = J / 2;
  v2d acc_a[P > 0 ? P : 1] = {}, acc_c[P > 0 ? P : 1] = {};
  double last_a = 0, last_c = 0;
  for (Eigen::Index i = 0; i < n; ++i) {
    const std::size_t row = static_cast<std::size_t>(i) * J;
    const double *ra = wa + row, *rc = wc + row, *rb = wb + row;
    for (std::size_t p = 0; p < P; ++p) {
      const v2d b = {rb[2 * p], rb[2 * p + 1]};
      acc_a[p] += v2d{ra[2 * p], ra[2 * p + 1]} * b;
      acc_c[p] += v2d{rc[2 * p], rc[2 * p + 1]} * b;
    }
    if (J % 2 == 1) last_a += ra[J - 1] * rb[J - 1], last_c += rc[J - 1] * rb[J - 1];
  }
  for (std::size_t p = 0; p < P; ++p) {
    sa[2 * p] = acc_a[p][0], sa[2 * p + 1] = acc_a[p][1];
    sc[2 * p] = acc_c[p][0], sc[2 * p + 1] = acc_c[p][1];
  }
  if (J % 2 == 1) sa[J - 1] = last_a, sc[J - 1] = last_c;
}

// sums<J> for J = 1 .. kMaxModels, the models' count fixed at compile time (their sums stay in
// registers).
using SumsFn = void (*)(const double*, const double*, Eigen::Index, std::array<double, GramMemo::kMaxModels>&);
template <std::size_t... Js>
constexpr std::array<SumsFn, sizeof...(Js)> sums_table(std::index_sequence<Js...>) {
  return {&sums<Js + 1>...};
}
constexpr auto kSums = sums_table(std::make_index_sequence<GramMemo::kMaxModels>{});
using Sums2Fn = void (*)(const double*, const double*, const double*, Eigen::Index,
                         std::array<double, GramMemo::kMaxModels>&, std::array<double, GramMemo::kMaxModels>&);
template <std::size_t... Js>
constexpr std::array<Sums2Fn, sizeof...(Js)> sums2_table(std::index_sequence<Js...>) {
  return {&sums2<Js + 1>...};
}
constexpr auto kSums2 = sums2_table(std::make_index_sequence<GramMemo::kMaxModels>{});

}  // namespace

GramMemo::Key GramMemo::pair_key(const Key& owner, const Key& ka, const Key& kb) {
  // w_a w_b = w_b w_a exactly, summed in the same order: one entry for both orders
  ByteHash k;
  k.value(owner), k.value(std::min(ka, kb)), k.value(std::max(ka, kb));
  return k.key();
}

GramMemo::Whitened GramMemo::whitened_column(const GainTable& table, const Key& table_key, const Eigen::MatrixXd& M,
                                             Eigen::Index c, const Key& col_key) {
  ByteHash k;
  k.value(table_key), k.value(col_key);
  if (const Whitened* kept = columns_.find(k.key())) return *kept;
  // (not value-initialised: every value is written)
  const std::size_t size = static_cast<std::size_t>(M.rows()) * table.gains.size();
  std::shared_ptr<double[]> out(new double[size]);
  whiten_each_model(table, M.col(c), out.get());
  columns_.insert(k.key(), out, size * sizeof(double) + kEntryOverhead);
  return out;
}

GramMemo::GramMemo(std::size_t budget_bytes)
    : columns_(budget_bytes), entries_(budget_bytes), grid_entries_(budget_bytes) {
  if (budget_bytes == 0) throw std::invalid_argument("GramMemo: the budget must be > 0 bytes");
}

bool GramMemo::serves(const GainTable& table, const Eigen::MatrixXd& M) {
  return !table.models.empty() && table.models.size() <= kMaxModels && M.cols() >= 1 && M.cols() <= kMaxColumns &&
         M.rows() >= kMinFrames;
}

GramMemo::Key GramMemo::column_key(const Eigen::MatrixXd& M, Eigen::Index c) {
  ByteHash k;
  k.value(M.rows());
  k.bytes(M.col(c).data(), static_cast<std::size_t>(M.rows()) * sizeof(double));
  return k.key();
}

void GramMemo::grams(const GainTable& table, const Key& table_key, const Eigen::MatrixXd& M,
                     const std::vector<Key>& col_keys, std::vector<Eigen::MatrixXd>& grams) {
  if (!serves(table, M))
    throw std::invalid_argument("GramMemo: " + std::to_string(table.models.size()) + " models and " +
                                std::to_string(M.cols()) + " columns: at most " + std::to_string(kMaxModels) + " and " +
                                std::to_string(kMaxColumns) + " are served");
  const Eigen::Index K = M.cols(), n = M.rows();
  const std::size_t J = table.models.size();
  for (const auto& g : table.gains)
    if (static_cast<Eigen::Index>(g.size()) != n) throw std::invalid_argument("GramMemo: rows != number of times");
  if (col_keys.size() != static_cast<std::size_t>(K)) throw std::invalid_argument("GramMemo: one key per column needed");
  grams.resize(J);
  for (Eigen::MatrixXd& G : grams) G.resize(K, K);
  auto set = [&](Eigen::Index a, Eigen::Index b, const Sums& s) {
    for (std::size_t j = 0; j < J; ++j) grams[j](a, b) = grams[j](b, a) = s[j];
  };
  // the entries kept; the missing ones listed
  std::vector<Missing>& missing = missing_;
  missing.clear();
  for (Eigen::Index a = 0; a < K; ++a)
    for (Eigen::Index b = a; b < K; ++b) {
      const Key key = pair_key(table_key, col_keys[static_cast<std::size_t>(a)], col_keys[static_cast<std::size_t>(b)]);
      if (const Sums* s = entries_.find(key)) {
        set(a, b, *s);
        ++read_;
      } else {
        missing.push_back({a, b, key});
      }
    }
  if (missing.empty()) return;
  // the columns the missing entries need, whitened under every model (kept, or whitened now)
  std::vector<Whitened>& w = w_;
  std::vector<char>& needed = needed_;
  w.assign(static_cast<std::size_t>(K), nullptr);
  needed.assign(static_cast<std::size_t>(K), 0);
  for (const Missing& m : missing) needed[static_cast<std::size_t>(m.a)] = needed[static_cast<std::size_t>(m.b)] = 1;
  for (Eigen::Index c = 0; c < K; ++c)
    if (needed[static_cast<std::size_t>(c)])
      w[static_cast<std::size_t>(c)] = whitened_column(table, table_key, M, c, col_keys[static_cast<std::size_t>(c)]);
  for (const Missing& mi : missing) {
    const double* wa = w[static_cast<std::size_t>(mi.a)].get();
    const double* wb = w[static_cast<std::size_t>(mi.b)].get();
    Sums s{};
    kSums[J - 1](wa, wb, n, s);
    set(mi.a, mi.b, s);
    entries_.insert(mi.key, s, sizeof(Sums) + kEntryOverhead);
    ++computed_;
  }
}

void GramMemo::grid_grams(std::size_t T, const TableOf& table_of, const Key& grid_key, const Eigen::MatrixXd& M,
                          const std::vector<Key>& col_keys, std::vector<std::vector<Eigen::MatrixXd>>& grams) {
  const Eigen::Index K = M.cols(), n = M.rows();
  if (col_keys.size() != static_cast<std::size_t>(K)) throw std::invalid_argument("GramMemo: one key per column needed");
  if (K < 1 || K > kMaxColumns || n < kMinFrames)
    throw std::invalid_argument("GramMemo: " + std::to_string(K) + " columns of " + std::to_string(n) + " frames: at most " +
                                std::to_string(kMaxColumns) + " columns and at least " + std::to_string(kMinFrames) +
                                " frames are served");
  // the grid's entries kept; the missing ones listed (their sums are filled table by table)
  std::vector<Missing>& pending = missing_;  // (kept between calls: allocated on every call, a fiftieth of a diagnosis)
  pending.clear();
  std::size_t J = 0;  // models per table: from the first entry read or table asked for
  auto shape = [&](std::size_t j) {
    if (J == 0) {
      J = j;
      // (the caller's matrices kept where their shape is already this: every entry is written
      // below, and 196 allocations per grid were a twentieth of a landing diagnosis)
      grams.resize(T);
      for (std::vector<Eigen::MatrixXd>& g : grams) {
        g.resize(J);
        for (Eigen::MatrixXd& m : g) m.resize(K, K);
      }
    } else if (j != J) {
      throw std::invalid_argument("GramMemo: the grid's tables differ in their count of models");
    }
  };
  for (Eigen::Index a = 0; a < K; ++a)
    for (Eigen::Index b = a; b < K; ++b) {
      const Key key = pair_key(grid_key, col_keys[static_cast<std::size_t>(a)], col_keys[static_cast<std::size_t>(b)]);
      if (const std::vector<double>* s = grid_entries_.find(key)) {
        shape(s->size() / T);
        for (std::size_t t = 0; t < T; ++t)
          for (std::size_t j = 0; j < J; ++j) grams[t][j](a, b) = grams[t][j](b, a) = (*s)[t * J + j];
        ++read_;
      } else {
        pending.push_back({a, b, key});
      }
    }
  if (pending.empty()) return;
  // table by table: the missing entries' sums as grams() computes them (the same whitened
  // columns, kept per table and column, and the same sums)
  std::vector<std::vector<double>> sums(pending.size());  // (moved into the memo below)
  std::vector<Whitened>& w = w_;
  std::vector<char>& needed = needed_;
  needed.assign(static_cast<std::size_t>(K), 0);
  for (const Missing& p : pending) needed[static_cast<std::size_t>(p.a)] = needed[static_cast<std::size_t>(p.b)] = 1;
  for (std::size_t t = 0; t < T; ++t) {
    const auto [table_key, table] = table_of(t);
    if (!serves(*table, M))
      throw std::invalid_argument("GramMemo: table " + std::to_string(t) + " of the grid: " +
                                  std::to_string(table->models.size()) + " models, at most " + std::to_string(kMaxModels));
    for (const auto& g : table->gains)
      if (static_cast<Eigen::Index>(g.size()) != n) throw std::invalid_argument("GramMemo: rows != number of times");
    shape(table->models.size());
    w.assign(static_cast<std::size_t>(K), nullptr);
    for (Eigen::Index c = 0; c < K; ++c)
      if (needed[static_cast<std::size_t>(c)])
        w[static_cast<std::size_t>(c)] = whitened_column(*table, table_key, M, c, col_keys[static_cast<std::size_t>(c)]);
    auto keep = [&](std::size_t m, const Sums& s) {
      const Missing& p = pending[m];
      sums[m].resize(T * J);
      for (std::size_t j = 0; j < J; ++j) {
        grams[t][j](p.a, p.b) = grams[t][j](p.b, p.a) = s[j];
        sums[m][t * J + j] = s[j];
      }
      ++computed_;
    };
    // two entries that share their second column in one pass (most of a grid's missing entries
    // pair e with another column)
    std::vector<char>& done = done_;
    done.assign(pending.size(), 0);
    for (std::size_t m = 0; m < pending.size(); ++m) {
      if (done[m]) continue;
      const Missing& p = pending[m];
      std::size_t m2 = m + 1;
      while (m2 < pending.size() && (done[m2] || pending[m2].b != p.b)) ++m2;
      Sums s{}, s2{};
      if (m2 < pending.size()) {
        kSums2[J - 1](w[static_cast<std::size_t>(p.a)].get(), w[static_cast<std::size_t>(pending[m2].a)].get(),
                      w[static_cast<std::size_t>(p.b)].get(), n, s, s2);
        keep(m2, s2);
        done[m2] = 1;
      } else {
        kSums[J - 1](w[static_cast<std::size_t>(p.a)].get(), w[static_cast<std::size_t>(p.b)].get(), n, s);
      }
      keep(m, s);
    }
  }
  for (std::size_t m = 0; m < pending.size(); ++m) {
    const std::size_t bytes = sums[m].size() * sizeof(double) + kEntryOverhead;
    grid_entries_.insert(pending[m].key, std::move(sums[m]), bytes);
  }
}

}  // namespace rnav
