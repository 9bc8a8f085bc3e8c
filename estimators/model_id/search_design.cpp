#include "estimators/model_id/search_design.hpp"

#include "estimators/model_id/stats.hpp"

#include <algorithm>
#include <limits>
#include <cmath>
#include <stdexcept>
#include <tuple>

namespace rnav::search_detail {

Ols ols(const Eigen::MatrixXd& X0, const Eigen::VectorXd& y0, const std::vector<char>& mask, bool basic) {
  Ols f;
  Eigen::MatrixXd X = X0;
  Eigen::VectorXd y = y0;
  if (!mask.empty())
    for (Eigen::Index i = 0; i < X.rows(); ++i)
      if (!mask[static_cast<std::size_t>(i)]) X.row(i).setZero(), y(i) = 0;
  f.n = 0;
  for (Eigen::Index i = 0; i < X.rows(); ++i) f.n += mask.empty() || mask[static_cast<std::size_t>(i)];
  const Eigen::Index k = X.cols();
  if (k == 0) {
    f.rss = y.squaredNorm();
    f.ok = true;
    return f;
  }
  Eigen::VectorXd d(k);
  for (Eigen::Index j = 0; j < k; ++j) d(j) = X.col(j).norm() > 0 ? 1.0 / X.col(j).norm() : 1.0;
  const Eigen::MatrixXd Xs = X * d.asDiagonal();
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(Xs);
  qr.setThreshold(1e-9);
  f.rank = static_cast<int>(qr.rank());
  if (f.rank < k && !basic) return f;  // collinear: the caller decides
  f.beta = d.asDiagonal() * qr.solve(y);
  f.rss = (y - X * f.beta).squaredNorm();
  if (f.rank < k) {
    f.ok = f.beta.allFinite();
    return f;
  }
  const Eigen::MatrixXd Rinv = qr.matrixR().topLeftCorner(k, k).triangularView<Eigen::Upper>().solve(
      Eigen::MatrixXd::Identity(k, k));
  const Eigen::MatrixXd cs = Rinv * Rinv.transpose();  // in the permuted, scaled basis
  const Eigen::MatrixXd P = qr.colsPermutation();
  f.cov_unscaled = d.asDiagonal() * (P * cs * P.transpose()) * d.asDiagonal();
  f.ok = true;
  return f;
}

Design::Design(const Problem& p) : pb(&p) {
  const std::size_t n = p.size();
  if (p.channel.size() != n || p.t_s.size() != n || p.estimation.size() != n)
    throw std::invalid_argument("effect search: channel, t_s, y and estimation must have one entry per observation");
  if (!p.nominal_corr_gain.empty() && p.nominal_corr_gain.size() != n)
    throw std::invalid_argument("effect search: nominal_corr_gain must be empty or have one entry per observation");
  if (p.nuisance.rows() != static_cast<Eigen::Index>(n) && p.nuisance.cols() > 0)
    throw std::invalid_argument("effect search: nuisance must have one row per observation");
  rows.assign(p.channels.size(), {});
  times.assign(p.channels.size(), {});
  gains.assign(p.channels.size(), {});
  for (std::size_t i = 0; i < n; ++i) {
    const int c = p.channel[i];
    if (c < 0 || static_cast<std::size_t>(c) >= p.channels.size())
      throw std::invalid_argument("effect search: observation " + std::to_string(i) + " names no channel");
    if (!std::isfinite(p.t_s[i]) || !std::isfinite(p.y[i]))
      throw std::invalid_argument("effect search: observation " + std::to_string(i) + " of channel " +
                                  p.channels[static_cast<std::size_t>(c)].name + " is not finite");
    auto& tc = times[static_cast<std::size_t>(c)];
    if (!tc.empty() && p.t_s[i] < tc.back())
      throw std::invalid_argument("effect search: channel " + p.channels[static_cast<std::size_t>(c)].name +
                                  " is not in time order at observation " + std::to_string(i));
    rows[static_cast<std::size_t>(c)].push_back(i);
    tc.push_back(p.t_s[i]);
    if (!p.nominal_corr_gain.empty()) {
      if (!(p.nominal_corr_gain[i] >= 0) || !std::isfinite(p.nominal_corr_gain[i]))
        throw std::invalid_argument("effect search: nominal_corr_gain of observation " + std::to_string(i) +
                                    " must be finite and >= 0");
      gains[static_cast<std::size_t>(c)].push_back(p.nominal_corr_gain[i]);
    }
  }
  for (std::size_t c = 0; c < rows.size(); ++c) {
    if (!(p.channels[c].nominal_sigma > 0))
      throw std::invalid_argument("effect search: channel " + p.channels[c].name + " needs a nominal sigma > 0");
    const Channel& ch = p.channels[c];
    if (!(ch.nominal_corr_sigma >= 0) || (ch.nominal_corr_sigma > 0 && !(ch.nominal_corr_tau_s > 0)))
      throw std::invalid_argument("effect search: channel " + ch.name +
                                  ": nominal correlated sigma must be >= 0, with a correlation time > 0");
    if (rows[c].size() < 10)
      throw std::invalid_argument("effect search: channel " + p.channels[c].name + " has fewer than 10 observations");
  }
}

Eigen::MatrixXd Design::raw_columns(std::size_t e, std::size_t v) const {
  const Candidate& c = pb->catalogue[e];
  Eigen::MatrixXd C = c.columns(v);
  if (C.rows() != static_cast<Eigen::Index>(pb->size()) || C.cols() != static_cast<Eigen::Index>(c.params.size()))
    throw std::invalid_argument("effect search: entry " + c.name + " (" + c.scope.label() + ") returned " +
                                std::to_string(C.rows()) + " x " + std::to_string(C.cols()) + " columns, expected " +
                                std::to_string(pb->size()) + " x " + std::to_string(c.params.size()));
  if (!C.allFinite())
    throw std::invalid_argument("effect search: entry " + c.name + " (" + c.scope.label() + ") has non-finite columns");
  return C;
}

const Eigen::MatrixXd& Design::raw_view(std::size_t e, std::size_t v, Eigen::MatrixXd& scratch) const {
  const Candidate& c = pb->catalogue[e];
  if (c.kept_columns && v < c.kept_columns->columns.size()) return c.kept_columns->columns[v];
  scratch = raw_columns(e, v);
  return scratch;
}

const std::vector<char>* Design::kept_touches(std::size_t e, std::size_t v) const {
  const Candidate& c = pb->catalogue[e];
  if (c.kept_columns && v < c.kept_columns->touches.size() && c.kept_columns->touches[v].size() == rows.size())
    return &c.kept_columns->touches[v];
  return nullptr;
}

std::vector<char> Design::touches(const Eigen::MatrixXd& raw) const {
  std::vector<char> out(rows.size(), 0);
  for (std::size_t c = 0; c < rows.size(); ++c)
    for (Eigen::Index j = 0; j < raw.cols() && !out[c]; ++j) {
      const double* col = raw.col(j).data();
      for (std::size_t r : rows[c])
        if (col[r] != 0) {
          out[c] = 1;
          break;
        }
    }
  return out;
}

Eigen::MatrixXd Design::whiten(const Eigen::MatrixXd& raw) const { return whiten_with(raw, noise); }

Eigen::MatrixXd Design::whiten_with(const Eigen::MatrixXd& raw, const std::vector<NoiseParams>& np) const {
  return whiten_through(raw, gain_tables(np));
}

std::vector<GainTable> Design::gain_tables(const std::vector<NoiseParams>& np) const {
  if (np.size() != rows.size()) throw std::logic_error("effect search: one noise model per channel expected");
  std::vector<GainTable> out(rows.size());
  for (std::size_t c = 0; c < rows.size(); ++c) innovation_gains(times[c], gains[c], {np[c]}, skip[c], out[c]);
  return out;
}

void Design::whiten_channel(std::size_t c, const GainTable& table, const std::vector<const double*>& src,
                            const std::vector<double*>& dst) const {
  const std::vector<std::size_t>& rc = rows[c];
  const auto m = static_cast<Eigen::Index>(rc.size());
  const std::size_t k = src.size();
  if (m == 0 || k == 0) return;
  if (one_block(c)) {  // whitened where they are, all at once
    thread_local std::vector<const double*> from;
    thread_local std::vector<double*> to;
    from.resize(k), to.resize(k);
    for (std::size_t j = 0; j < k; ++j) from[j] = src[j] + rc.front(), to[j] = dst[j] + rc.front();
    rnav::whiten(table, 0, from, to);
    return;
  }
  thread_local Eigen::MatrixXd B;  // the channel's rows, gathered (kept per thread: set_noise whitens every grid point)
  B.resize(m, static_cast<Eigen::Index>(k));
  for (std::size_t j = 0; j < k; ++j) {
    double* b = B.col(static_cast<Eigen::Index>(j)).data();
    for (Eigen::Index r = 0; r < m; ++r) b[r] = src[j][rc[static_cast<std::size_t>(r)]];
  }
  rnav::whiten(table, 0, B);
  for (std::size_t j = 0; j < k; ++j) {
    const double* b = B.col(static_cast<Eigen::Index>(j)).data();
    for (Eigen::Index r = 0; r < m; ++r) dst[j][rc[static_cast<std::size_t>(r)]] = b[r];
  }
}

Eigen::MatrixXd Design::whiten_through(const Eigen::MatrixXd& raw, const std::vector<GainTable>& tables) const {
  Eigen::MatrixXd out = Eigen::MatrixXd::Zero(raw.rows(), raw.cols());
  std::vector<const double*> src;
  std::vector<double*> dst;
  for (Eigen::Index j = 0; j < raw.cols(); ++j) src.push_back(raw.col(j).data()), dst.push_back(out.col(j).data());
  // a channel the columns do not touch stays zero (most entries touch one channel of several)
  const std::vector<char> touched = touches(raw);
  for (std::size_t c = 0; c < rows.size(); ++c)
    if (touched[c]) whiten_channel(c, tables[c], src, dst);
  return out;
}

bool Design::one_block(std::size_t c) const {
  // rows ascend: one block when the last minus the first is their count less one
  return !rows[c].empty() && rows[c].back() - rows[c].front() + 1 == rows[c].size();
}

void Design::lay_out_catalogue() {
  // (Cw's storage is kept from one noise to the next: the rows of the channels a grid point does
  // not touch are 0 under every noise, written once; zeroing them again was a thirtieth of a
  // landing diagnosis)
  const Problem& p = *pb;
  const std::size_t nc = rows.size();
  Eigen::MatrixXd scratch;
  Cw.assign(p.catalogue.size(), {});
  cat_touched_.assign(p.catalogue.size(), {});
  for (std::size_t e = 0; e < p.catalogue.size(); ++e) {
    const std::size_t nv = p.catalogue[e].variants();
    std::vector<char>& touched = cat_touched_[e];
    touched.resize(nv * nc);
    for (std::size_t v = 0; v < nv; ++v) {
      const Eigen::MatrixXd& raw = raw_view(e, v, scratch);
      const std::vector<char>* kt = kept_touches(e, v);
      const std::vector<char> own = kt ? std::vector<char>{} : touches(raw);
      std::copy_n((kt ? *kt : own).begin(), nc, touched.begin() + static_cast<std::ptrdiff_t>(v * nc));
      Eigen::MatrixXd& out = Cw[e].emplace_back(raw.rows(), raw.cols());  // the touched channels' rows: whiten_catalogue's
      // the rows of the channels it does not touch: 0 (the channels' rows partition the observations)
      for (std::size_t c = 0; c < nc; ++c) {
        if (rows[c].empty() || touched[v * nc + c]) continue;
        for (Eigen::Index j = 0; j < out.cols(); ++j) {
          double* to = out.col(j).data();
          if (one_block(c))
            std::fill_n(to + rows[c].front(), rows[c].size(), 0.0);
          else
            for (std::size_t r : rows[c]) to[r] = 0;
        }
      }
    }
  }
  catalogue_laid_out_ = true;
}

void Design::whiten_catalogue(const std::vector<GainTable>& tables) {
  // Channel by channel, every column of every entry's grid points that touches it whitened at
  // once: whiten_through's values bit for bit (each column's recursion is its own), but eight
  // columns at a time where one grid point has one to three (a lone column's recursion is a chain
  // of dependent operations that leaves the processor mostly waiting; whiten_channel).
  const Problem& p = *pb;
  const std::size_t nc = rows.size();
  if (!catalogue_laid_out_) lay_out_catalogue();
  const std::vector<std::vector<char>>& touched = cat_touched_;  // [entry][variant * channels + channel]
  Eigen::MatrixXd scratch;
  // each grid point's raw columns once (computed, where they are not kept, into scratch, which
  // the next one overwrites: their touched channels' rows are put in Cw first and whitened there)
  std::vector<std::vector<std::vector<const double*>>> from(Cw.size());  // [entry][variant][column]
  for (std::size_t e = 0; e < Cw.size(); ++e) {
    from[e].resize(Cw[e].size());
    for (std::size_t v = 0; v < Cw[e].size(); ++v) {
      const Eigen::MatrixXd& raw = raw_view(e, v, scratch);
      const bool own = &raw == &scratch;
      for (Eigen::Index j = 0; j < raw.cols(); ++j) {
        double* to = Cw[e][v].col(j).data();
        if (own)
          for (std::size_t c = 0; c < nc; ++c)
            if (touched[e][v * nc + c])
              for (std::size_t r : rows[c]) to[r] = raw(static_cast<Eigen::Index>(r), j);
        from[e][v].push_back(own ? to : raw.col(j).data());
      }
    }
  }
  std::vector<const double*> src;
  std::vector<double*> dst;
  for (std::size_t c = 0; c < nc; ++c) {
    src.clear(), dst.clear();
    for (std::size_t e = 0; e < Cw.size(); ++e)
      for (std::size_t v = 0; v < Cw[e].size(); ++v) {
        if (!touched[e][v * nc + c]) continue;
        for (Eigen::Index j = 0; j < Cw[e][v].cols(); ++j) {
          src.push_back(from[e][v][static_cast<std::size_t>(j)]);
          dst.push_back(Cw[e][v].col(j).data());
        }
      }
    whiten_channel(c, tables[c], src, dst);
  }
  // each grid point's unit_gram, scanning for zeros only from the first touched channel's first
  // row to the last one's last
  Cg.assign(p.catalogue.size(), {});
  for (std::size_t e = 0; e < Cw.size(); ++e)
    for (std::size_t v = 0; v < Cw[e].size(); ++v) {
      Eigen::Index lo = Cw[e][v].rows(), hi = 0;
      for (std::size_t c = 0; c < nc; ++c)
        if (!rows[c].empty() && touched[e][v * nc + c]) {
          lo = std::min(lo, static_cast<Eigen::Index>(rows[c].front()));
          hi = std::max(hi, static_cast<Eigen::Index>(rows[c].back()) + 1);
        }
      Cg[e].push_back(unit_gram(Cw[e][v], lo, std::max(lo, hi)));
    }
}

void Design::set_noise(const std::vector<NoiseParams>& np, const std::vector<std::vector<char>>& sk) {
  noise = np;
  skip = sk;
  lr_memo = std::make_shared<LrMemo>();  // the projections under the noise before are kept by their projectors only
  const Problem& p = *pb;
  used.assign(p.size(), 1);
  for (std::size_t c = 0; c < rows.size(); ++c)
    for (std::size_t r = 0; r < rows[c].size(); ++r)
      if (!skip[c].empty() && skip[c][r]) used[rows[c][r]] = 0;
  n_used = 0;
  for (char u : used) n_used += u;
  // each channel's gains once for the residuals, the nuisance and every entry's columns
  const std::vector<GainTable> tables = gain_tables(noise);
  yw = whiten_through(Eigen::Map<const Eigen::VectorXd>(p.y.data(), static_cast<Eigen::Index>(p.size())), tables);
  Nw = p.nuisance.cols() > 0 ? whiten_through(p.nuisance, tables) : Eigen::MatrixXd(static_cast<Eigen::Index>(p.size()), 0);
  whiten_catalogue(tables);
}

Eigen::MatrixXd model_matrix(const Design& d, const std::vector<std::pair<std::size_t, std::size_t>>& chosen) {
  Eigen::Index k = d.Nw.cols();
  for (const auto& [e, v] : chosen) k += d.Cw[e][v].cols();
  Eigen::MatrixXd M(d.yw.size(), k);
  M.leftCols(d.Nw.cols()) = d.Nw;
  Eigen::Index col = d.Nw.cols();
  for (const auto& [e, v] : chosen) {
    M.middleCols(col, d.Cw[e][v].cols()) = d.Cw[e][v];
    col += d.Cw[e][v].cols();
  }
  return M;
}

Eigen::MatrixXd raw_model_matrix(const Design& d, const std::vector<std::pair<std::size_t, std::size_t>>& chosen) {
  const Problem& p = *d.pb;
  Eigen::Index k = p.nuisance.cols();
  std::vector<Eigen::MatrixXd> blocks;
  for (const auto& [e, v] : chosen) {
    blocks.push_back(d.raw_columns(e, v));
    k += blocks.back().cols();
  }
  Eigen::MatrixXd M(static_cast<Eigen::Index>(p.size()), k);
  if (p.nuisance.cols() > 0) M.leftCols(p.nuisance.cols()) = p.nuisance;
  Eigen::Index col = p.nuisance.cols();
  for (const auto& b : blocks) {
    M.middleCols(col, b.cols()) = b;
    col += b.cols();
  }
  return M;
}

namespace {
// The columns of A scaled to unit norm, span(Q) projected out.
Eigen::MatrixXd projected_unit(const Eigen::MatrixXd& Q, const Eigen::MatrixXd& A) {
  Eigen::MatrixXd U = A;
  for (Eigen::Index j = 0; j < U.cols(); ++j) {
    const double nj = U.col(j).norm();
    if (nj > 0) U.col(j) /= nj;
  }
  return Q.cols() > 0 ? Eigen::MatrixXd(U - Q * (Q.transpose() * U)) : U;
}
// The rank threshold on the singular values of projected_unit's columns.
constexpr double kRankSv = 1e-6;
// Two 2 log LR closer than this (relative; absolute below 1) are one value: far above the
// rounding of a likelihood over 1e5 frames (1e-16 per term), far below any evidence.
constexpr double kTieLr = 1e-9;
// Orthonormal basis of the columns of A after projecting out span(Q) (Q orthonormal); empty if
// nothing is left. The columns are scaled to unit norm first (the span is the same), so the
// rank decision (singular value below 1e-6) does not depend on their units: a whitened drift
// column (time / sigma, ~1e5 per row) must not push a constant's column (~0.1) below the
// threshold and out of the basis.
Eigen::MatrixXd residual_basis(const Eigen::MatrixXd& Q, const Eigen::MatrixXd& A) {
  const Eigen::MatrixXd R = projected_unit(Q, A);
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(R, Eigen::ComputeThinU);
  const auto& s = svd.singularValues();
  Eigen::Index rank = 0;
  for (Eigen::Index i = 0; i < s.size(); ++i)
    if (s(i) > kRankSv) ++rank;
  return svd.matrixU().leftCols(rank);
}
Eigen::MatrixXd orthonormal(const Eigen::MatrixXd& M) {
  if (M.cols() == 0) return Eigen::MatrixXd(M.rows(), 0);
  return residual_basis(Eigen::MatrixXd(M.rows(), 0), M);
}
}  // namespace

UnitGram unit_gram(const Eigen::MatrixXd& C) { return unit_gram(C, 0, C.rows()); }

UnitGram unit_gram(const Eigen::MatrixXd& C, Eigen::Index zero_below, Eigen::Index zero_from) {
  if (!(0 <= zero_below && zero_below <= zero_from && zero_from <= C.rows()))
    throw std::logic_error("unit_gram: the rows known to be 0 must be a prefix and a suffix");
  UnitGram g;
  const Eigen::Index k = C.cols();
  // the rows outside which every column is 0 (a column touches one channel's block of rows; a
  // step, the rows after its time): the products below run over them alone
  g.lo = C.rows(), g.hi = 0;
  for (Eigen::Index j = 0; j < k; ++j) {
    const double* c = C.col(j).data();
    Eigen::Index lo = zero_below, hi = zero_from;
    while (lo < hi && c[lo] == 0) ++lo;
    while (hi > lo && c[hi - 1] == 0) --hi;
    if (lo < hi) g.lo = std::min(g.lo, lo), g.hi = std::max(g.hi, hi);
  }
  if (g.lo >= g.hi) g.lo = g.hi = 0;
  const auto seg = [&](Eigen::Index j) { return C.col(j).segment(g.lo, g.hi - g.lo); };
  g.inv_norm.resize(k);
  for (Eigen::Index j = 0; j < k; ++j) {
    const double nj = seg(j).norm();
    g.inv_norm(j) = nj > 0 ? 1 / nj : 0.0;
  }
  g.UU.resize(k, k);
  // (dot products: a general matrix product's packing costs more than its work at these widths)
  for (Eigen::Index i = 0; i < k; ++i)
    for (Eigen::Index j = 0; j <= i; ++j) g.UU(i, j) = g.UU(j, i) = seg(i).dot(seg(j)) * g.inv_norm(i) * g.inv_norm(j);
  return g;
}

namespace {
// V = Q' U, U = C diag(inv_norm), by dot products over the rows where C is not 0 (see unit_gram).
Eigen::MatrixXd basis_products(const Eigen::MatrixXd& Q, const Eigen::MatrixXd& C, const UnitGram& g) {
  Eigen::MatrixXd V(Q.cols(), C.cols());
  const Eigen::Index m = g.hi - g.lo;
  for (Eigen::Index j = 0; j < C.cols(); ++j)
    for (Eigen::Index i = 0; i < Q.cols(); ++i) V(i, j) = Q.col(i).segment(g.lo, m).dot(C.col(j).segment(g.lo, m)) * g.inv_norm(j);
  return V;
}
}  // namespace

Projector::Projector(const Eigen::MatrixXd& M, const Eigen::VectorXd& y, double n_used)
    : Q(orthonormal(M)),
      r(Q.cols() > 0 ? Eigen::VectorXd(y - Q * (Q.transpose() * y)) : y),
      Qr(Q.transpose() * r),
      rss(r.squaredNorm()),
      n(n_used) {}

double Projector::lr(const Eigen::MatrixXd& C) const { return lr(C, unit_gram(C)); }

// The smallest eigenvalue of the projected unit columns' Gram matrix (their smallest singular
// value squared) below which lr leaves the answer to lr_qr: the Gram path's relative error is
// at most about m eps / lambda_min over m rows summed (3e-11 for a 1 500-frame channel at the
// bound; typically sqrt(m) eps / lambda_min, 1e-12), below kTieLr's 1e-9.
constexpr double kGramConditioned = 1e-2;
// The share of the residual's sum of squares the columns may explain for lr's Gram path: beyond
// it RSS_(M,C) = RSS_M - drop keeps few of drop's digits and lr_qr answers.
constexpr double kGramDrop = 0.999;

double Projector::lr(const Eigen::MatrixXd& C, const UnitGram& g) const {
  // With U the unit columns and V = Q' U, the projected columns R = U - Q V have R' R = U' U - V' V
  // and b = R' r = U' r - V' Q' r (Q' r is r's rounding: a model that explains y to 1e-7, as a
  // reference track's, leaves it at 1e-9 of r); the drop in RSS is b' (R' R)^-1 b. (From y instead,
  // U' y - V' Q' y would lose the digits y has beyond r.)
  const Eigen::Index k = C.cols();
  if (k == 0) return lr_qr(C);
  Eigen::MatrixXd S = g.UU;
  Eigen::VectorXd b(k);
  for (Eigen::Index j = 0; j < k; ++j) b(j) = C.col(j).segment(g.lo, g.hi - g.lo).dot(r.segment(g.lo, g.hi - g.lo)) * g.inv_norm(j);
  if (Q.cols() > 0) {
    const Eigen::MatrixXd V = basis_products(Q, C, g);
    S.noalias() -= V.transpose() * V;
    b.noalias() -= V.transpose() * Qr;  // r's rounding inside span(Q), as R' r has it
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(S);
  if (!(es.eigenvalues().minCoeff() > kGramConditioned)) return lr_qr(C);
  const Eigen::VectorXd z = es.eigenvectors().transpose() * b;
  const double drop = z.cwiseAbs2().cwiseQuotient(es.eigenvalues()).sum();
  if (!(rss > 0)) return 0;
  if (!(drop < kGramDrop * rss)) return lr_qr(C);
  return n * std::log(rss / (rss - drop));
}

double Projector::lr_qr(const Eigen::MatrixXd& C) const {
  // The drop in RSS is |B' r|^2 for B an orthonormal basis of C's columns after span(Q) is
  // projected out (residual_basis). Without forming B (lr runs at every grid point of every
  // scanned entry: the SVD's basis was most of a pooled search's time): R = projected_unit(Q, C)
  // = H [T; 0] (Householder, k = C's columns), the singular values of T are R's (rank as
  // residual_basis decides it), and with rank k, B = H [I; 0] up to a rotation, so
  // |B' r|^2 = |(H' r)_(1..k)|^2.
  const Eigen::Index k = C.cols();
  double drop = 0;
  if (k > 0) {
    const Eigen::MatrixXd R = projected_unit(Q, C);
    if (R.rows() < k) return -1;
    const Eigen::HouseholderQR<Eigen::MatrixXd> qr(R);
    const Eigen::MatrixXd T = qr.matrixQR().topRows(k).triangularView<Eigen::Upper>();
    const Eigen::VectorXd sv = Eigen::JacobiSVD<Eigen::MatrixXd>(T).singularValues();
    if ((sv.array() > kRankSv).count() < k) return -1;
    const Eigen::VectorXd Hr = qr.householderQ().adjoint() * r;
    drop = Hr.head(k).squaredNorm();
  }
  if (!(rss > 0)) return 0;
  return n * std::log(rss / std::max(rss - drop, 1e-300 * rss));
}

double Projector::entry_lr(const Design& d, std::size_t e, std::size_t v) const {
  if (!memo) return lr(d.Cw[e][v], d.Cg[e][v]);
  {
    const std::lock_guard<std::mutex> lock(memo->m);
    std::vector<std::vector<double>>& per = memo->lr[model];
    if (per.empty()) per.resize(d.Cw.size());
    std::vector<double>& ev = per[e];
    if (ev.empty()) ev.assign(d.Cw[e].size(), std::numeric_limits<double>::quiet_NaN());
    if (!std::isnan(ev[v])) return ev[v];
  }
  const double x = lr(d.Cw[e][v], d.Cg[e][v]);  // outside the lock: the same value whoever computes it first
  const std::lock_guard<std::mutex> lock(memo->m);
  memo->lr[model][e][v] = x;
  return x;
}

Projector projector_of(const Design& d, const std::vector<std::pair<std::size_t, std::size_t>>& model) {
  Projector P(model_matrix(d, model), d.yw, d.n_used);
  P.memo = d.lr_memo;
  P.model = model;
  return P;
}

double added_lr(const Eigen::MatrixXd& M, const Eigen::VectorXd& y, const Eigen::MatrixXd& C, double n) {
  return Projector(M, y, n).lr(C);
}

double canonical_corr(const Eigen::MatrixXd& M, const Eigen::MatrixXd& A, const Eigen::MatrixXd& B) {
  return canonical_corr_given(orthonormal(M), A, B);
}

namespace {
// S^(-1/2) of a symmetric matrix whose least eigenvalue exceeds kGramConditioned; an empty
// matrix otherwise.
Eigen::MatrixXd inverse_sqrt_if_conditioned(const Eigen::MatrixXd& S) {
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> es(S);
  if (!(es.eigenvalues().minCoeff() > kGramConditioned)) return {};
  return es.eigenvectors() * es.eigenvalues().cwiseSqrt().cwiseInverse().asDiagonal() * es.eigenvectors().transpose();
}
}  // namespace

double canonical_corr_given(const Eigen::MatrixXd& Q, const Eigen::MatrixXd& A, const Eigen::MatrixXd& B) {
  return canonical_corr_given(Q, A, unit_gram(A), B, unit_gram(B));
}

double canonical_corr_given(const Eigen::MatrixXd& Q, const Eigen::MatrixXd& A, const UnitGram& ga,
                            const Eigen::MatrixXd& B, const UnitGram& gb) {
  // From Gram matrices where both projected blocks are well conditioned (as Projector::lr): with
  // unit columns U and V = Q' U, the projected blocks' Gram matrices are Saa = Ua' Ua - Va' Va,
  // Sbb likewise and Sab = Ua' Ub - Va' Vb, and the canonical correlations are the singular
  // values of Saa^(-1/2) Sab Sbb^(-1/2).
  if (A.cols() > 0 && B.cols() > 0) {
    const Eigen::MatrixXd Va = basis_products(Q, A, ga), Vb = basis_products(Q, B, gb);
    // A' B over the rows where both may be non-zero (none: exactly 0)
    const Eigen::Index lo = std::max(ga.lo, gb.lo), m = std::max<Eigen::Index>(0, std::min(ga.hi, gb.hi) - lo);
    Eigen::MatrixXd Sab(A.cols(), B.cols());
    for (Eigen::Index i = 0; i < A.cols(); ++i)
      for (Eigen::Index j = 0; j < B.cols(); ++j)
        Sab(i, j) = m > 0 ? A.col(i).segment(lo, m).dot(B.col(j).segment(lo, m)) * ga.inv_norm(i) * gb.inv_norm(j) : 0.0;
    Eigen::MatrixXd Saa = ga.UU, Sbb = gb.UU;
    if (Q.cols() > 0) {
      Saa.noalias() -= Va.transpose() * Va;
      Sbb.noalias() -= Vb.transpose() * Vb;
      Sab.noalias() -= Va.transpose() * Vb;
    }
    const Eigen::MatrixXd Ia = inverse_sqrt_if_conditioned(Saa), Ib = inverse_sqrt_if_conditioned(Sbb);
    if (Ia.size() > 0 && Ib.size() > 0) {
      Eigen::JacobiSVD<Eigen::MatrixXd> s(Ia * Sab * Ib);
      return std::min(1.0, s.singularValues()(0));
    }
  }
  const Eigen::MatrixXd Qa = residual_basis(Q, A), Qb = residual_basis(Q, B);
  if (Qa.cols() == 0 || Qb.cols() == 0) return 1.0;  // inside the rest of the model: not separable
  Eigen::JacobiSVD<Eigen::MatrixXd> s(Qa.transpose() * Qb);
  return std::min(1.0, s.singularValues()(0));
}

std::pair<double, std::size_t> best_variant(const Design& d, const Projector& P, std::size_t e) {
  double best = -1;
  std::size_t arg = 0;
  for (std::size_t v = 0; v < d.Cw[e].size(); ++v) {
    const double lr = P.entry_lr(d, e, v);
    // Grid points whose columns are the same on the data (no observation between two step times
    // or sweep ends) give the same 2 log LR up to rounding: the first of them is kept, so the
    // choice does not hang on the last bits of the arithmetic.
    if (lr > best + kTieLr * std::max(1.0, std::abs(best))) best = lr, arg = v;
  }
  return {best, arg};
}

double as_well_margin(std::size_t grid) { return std::max(6.0, 2 * std::log(static_cast<double>(grid))); }

Rival rival(const Design& d, const Projector& P, std::size_t e, std::size_t v, std::size_t f,
            double alpha, double confound_corr, double m_family) {
  Rival r;
  std::tie(r.lr, r.v) = best_variant(d, P, f);
  r.corr = canonical_corr_given(P.Q, d.Cw[e][v], d.Cg[e][v], d.Cw[f][r.v], d.Cg[f][r.v]);
  const double k = static_cast<double>(d.pb->catalogue[f].params.size());
  const bool passes =
      r.lr > 0 && bonferroni_log_p(r.lr, k, static_cast<double>(d.Cw[f].size()), m_family) < std::log(alpha);
  r.same = r.corr > confound_corr || (passes && P.entry_lr(d, e, v) - r.lr < as_well_margin(std::max(d.Cw[e].size(), d.Cw[f].size())));
  return r;
}

}  // namespace rnav::search_detail
