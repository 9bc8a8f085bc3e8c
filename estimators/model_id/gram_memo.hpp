// Internal to noise identification (noise_id.cpp): the Gram matrices of [X | e] whitened under
// each model of a kept gain table, from entries remembered per pair of columns.
//
// Why: a diagnosis identifies the noise of the same few series thousands of times, each time
// under the same grid of models (their gain tables kept) and with columns mostly seen before:
// the nuisance and the chosen effects beside each candidate's columns, the same catalogue
// columns beside each injection's residuals. The whitened Gram matrices were over a third of a
// 500-plot landing diagnosis's time, and about one entry in four was new.
#pragma once

#include "estimators/model_id/generation_store.hpp"
#include "estimators/model_id/noise_model.hpp"

#include <Eigen/Dense>

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <utility>
#include <vector>

namespace rnav {

/// One thread's memo (not locked).
class GramMemo {
 public:
  using Key = std::pair<std::uint64_t, std::uint64_t>;
  /// Wider matrices are left to whitened_grams (whose sums then run in another order).
  static constexpr Eigen::Index kMaxColumns = 8;
  static constexpr std::size_t kMaxModels = 8;  ///< models per table served
  /// Shorter series are left to whitened_grams: their sums cost less than the lookups (the nine
  /// Autoferry recordings pooled, many short series among them: 29.1 s with this bound, 29.9 s
  /// without, 28.1 s with no memo at all).
  static constexpr Eigen::Index kMinFrames = 200;

  /// budget_bytes: what the kept whitened columns may hold, and as much for the kept entries
  /// and again for the kept grid entries.
  explicit GramMemo(std::size_t budget_bytes);

  /// Whether grams() serves this table and matrix: at most kMaxModels models, kMaxColumns
  /// columns, at least kMinFrames frames.
  static bool serves(const GainTable& table, const Eigen::MatrixXd& M);

  /// The key of one column's values (col_keys of grams()).
  static Key column_key(const Eigen::MatrixXd& M, Eigen::Index c);

  /// grams[j] = W_j' W_j, W_j being M whitened under table.models[j]: whitened_grams(table, M,
  /// grams)'s values bit for bit. Each entry is the sum over the frames of w_a w_b in frame order
  /// from 0, w whitened by whiten(table, j, .), as whitened_grams sums it for up to kMaxColumns
  /// columns; an entry is computed once per (table, column a, column b) and then read.
  /// table_key: a key of everything the table's gains depend on (frames, gains h, frames kept
  /// out, models); col_keys[c] = column_key(M, c). Throws std::invalid_argument unless
  /// serves(table, M), and when M's rows are not the table's frames or col_keys is not one per
  /// column.
  void grams(const GainTable& table, const Key& table_key, const Eigen::MatrixXd& M, const std::vector<Key>& col_keys,
             std::vector<Eigen::MatrixXd>& grams);

  /// The gain tables of a grid of models (one table per correlation time, each serving M) and
  /// their keys, asked for one at a time (a table is only valid until the next is asked for).
  using TableOf = std::function<std::pair<Key, const GainTable*>(std::size_t)>;

  /// grams[t][j] = grams() of table t's model j, for tables t = 0 .. T - 1 (table_of(t)): the
  /// same values bit for bit, each entry computed as grams() computes it, but remembered per
  /// (grid, column a, column b) for all T tables at once: one lookup per pair of columns where
  /// grams() takes T (a noise identification's grid is 28 tables of 7 models). grid_key: a key
  /// of everything the T tables depend on. table_of is called only when an entry is missing.
  /// Throws std::invalid_argument as grams() does, and when the tables differ in their count of
  /// models.
  void grid_grams(std::size_t T, const TableOf& table_of, const Key& grid_key, const Eigen::MatrixXd& M,
                  const std::vector<Key>& col_keys, std::vector<std::vector<Eigen::MatrixXd>>& grams);

  std::size_t entries_computed() const { return computed_; }  ///< entries summed (not read)
  std::size_t entries_read() const { return read_; }          ///< entries read from the memo

 private:
  using Sums = std::array<double, kMaxModels>;  ///< one entry under each model
  /// A column whitened under every model, frame-major: w[i * J + j].
  using Whitened = std::shared_ptr<const double[]>;
  GenerationStore<Whitened> columns_;
  GenerationStore<Sums> entries_;
  /// A grid's entry: the sums of one pair of columns under every model of its T tables,
  /// [t * J + j].
  GenerationStore<std::vector<double>> grid_entries_;
  std::size_t computed_ = 0, read_ = 0;
  /// The key of the entry of columns ka, kb under owner (a table's or a grid's key).
  static Key pair_key(const Key& owner, const Key& ka, const Key& kb);
  /// Column c of M whitened under every model of the table: kept, or whitened now and kept.
  Whitened whitened_column(const GainTable& table, const Key& table_key, const Eigen::MatrixXd& M, Eigen::Index c,
                           const Key& col_key);
  // one call's scratch, kept between calls (a memo serves one thread)
  struct Missing {
    Eigen::Index a, b;
    Key key;
  };
  std::vector<Missing> missing_;
  std::vector<Whitened> w_;
  std::vector<char> needed_;
  std::vector<char> done_;  ///< grid_grams: the missing entries summed so far in one table
};

}  // namespace rnav
