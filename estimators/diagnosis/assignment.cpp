#include "estimators/diagnosis/assignment.hpp"

#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>

namespace rnav {

namespace {

// Hungarian method (shortest augmenting paths with row and column potentials u, v) on a square
// n x n matrix a (finite), rows assigned to columns; returns per row its column.
std::vector<int> hungarian_square(const Eigen::MatrixXd& a) {
  const int n = static_cast<int>(a.rows());
  const double inf = std::numeric_limits<double>::infinity();
  // 1-based arrays with a virtual column 0 (the classical formulation)
  std::vector<double> u(n + 1, 0.0), v(n + 1, 0.0);
  std::vector<int> p(n + 1, 0), way(n + 1, 0);  // p[j]: the row matched to column j
  for (int i = 1; i <= n; ++i) {
    p[0] = i;
    int j0 = 0;
    std::vector<double> minv(n + 1, inf);
    std::vector<char> used(n + 1, 0);
    do {
      used[j0] = 1;
      const int i0 = p[j0];
      double delta = inf;
      int j1 = 0;
      for (int j = 1; j <= n; ++j) {
        if (used[j]) continue;
        const double cur = a(i0 - 1, j - 1) - u[i0] - v[j];
        if (cur < minv[j]) minv[j] = cur, way[j] = j0;
        if (minv[j] < delta) delta = minv[j], j1 = j;
      }
      for (int j = 0; j <= n; ++j) {
        if (used[j]) u[p[j]] += delta, v[j] -= delta;
        else minv[j] -= delta;
      }
      j0 = j1;
    } while (p[j0] != 0);
    do {  // augment along the path
      const int j1 = way[j0];
      p[j0] = p[j1];
      j0 = j1;
    } while (j0 != 0);
  }
  std::vector<int> col(n, -1);
  for (int j = 1; j <= n; ++j)
    if (p[j] > 0) col[p[j] - 1] = j - 1;
  return col;
}

int find(std::vector<int>& parent, int x) {
  while (parent[x] != x) x = parent[x] = parent[parent[x]];
  return x;
}

}  // namespace

std::vector<long> assign_min_cost(const Eigen::MatrixXd& cost, const std::vector<double>& miss) {
  const int T = static_cast<int>(cost.rows()), D = static_cast<int>(cost.cols());
  if (static_cast<int>(miss.size()) != T) throw std::invalid_argument("assign_min_cost: one miss cost per target needed");
  for (double m : miss)
    if (!(m >= 0) || !std::isfinite(m)) throw std::invalid_argument("assign_min_cost: miss costs must be finite and >= 0");
  for (int t = 0; t < T; ++t)
    for (int d = 0; d < D; ++d)
      if (!(cost(t, d) >= 0)) throw std::invalid_argument("assign_min_cost: costs must be >= 0 (+inf: not allowed), not NaN");
  // connected components of the allowed pairs: targets 0..T-1, detections T..T+D-1
  std::vector<int> parent(static_cast<std::size_t>(T + D));
  std::iota(parent.begin(), parent.end(), 0);
  for (int t = 0; t < T; ++t)
    for (int d = 0; d < D; ++d)
      if (std::isfinite(cost(t, d))) parent[static_cast<std::size_t>(find(parent, t))] = find(parent, T + d);
  std::vector<long> out(static_cast<std::size_t>(T), -1);
  std::vector<char> done(static_cast<std::size_t>(T), 0);
  for (int t0 = 0; t0 < T; ++t0) {
    if (done[static_cast<std::size_t>(t0)]) continue;
    const int root = find(parent, t0);
    std::vector<int> ts, ds;
    for (int t = 0; t < T; ++t)
      if (find(parent, t) == root) ts.push_back(t), done[static_cast<std::size_t>(t)] = 1;
    for (int d = 0; d < D; ++d)
      if (find(parent, T + d) == root) ds.push_back(d);
    if (ds.empty()) continue;  // no allowed pair: unassigned
    const int nt = static_cast<int>(ts.size()), nd = static_cast<int>(ds.size());
    if (nt == 1 && nd == 1) {  // the common case: one target, one detection
      if (cost(ts[0], ds[0]) <= miss[static_cast<std::size_t>(ts[0])]) out[static_cast<std::size_t>(ts[0])] = ds[0];
      continue;
    }
    // square matrix: rows = the component's targets, then one dummy row per detection (it
    // stays unassigned at 0); columns = its detections, then one miss column per target
    // (allowed to its own target only). A forbidden pair costs more than every feasible
    // assignment (all misses taken).
    const int n = nt + nd;
    double big = 1;
    for (int t : ts) big += miss[static_cast<std::size_t>(t)];
    big *= 1e6;
    Eigen::MatrixXd a = Eigen::MatrixXd::Zero(n, n);
    for (int i = 0; i < nt; ++i) {
      for (int j = 0; j < nd; ++j) a(i, j) = std::isfinite(cost(ts[i], ds[j])) ? cost(ts[i], ds[j]) : big;
      for (int j = 0; j < nt; ++j) a(i, nd + j) = j == i ? miss[static_cast<std::size_t>(ts[i])] : big;
    }
    const std::vector<int> col = hungarian_square(a);
    for (int i = 0; i < nt; ++i)
      if (col[i] < nd && std::isfinite(cost(ts[i], ds[col[i]]))) out[static_cast<std::size_t>(ts[i])] = ds[col[i]];
  }
  return out;
}

}  // namespace rnav
