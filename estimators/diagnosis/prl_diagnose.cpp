#include "estimators/diagnosis/prl_diagnose.hpp"

#include "estimators/diagnosis/gross_check.hpp"

#include "common/io/config.hpp"
#include "common/physics/prl_effect_columns.hpp"
#include "estimators/model_id/stats.hpp"

#include <algorithm>
#include <cmath>
#include <memory>

namespace rnav {

namespace {

using prl_effect::kChannels;
const char* const kChannelName[kChannels] = {"range", "course", "glide"};
const char* const kChannelUnit[kChannels] = {"m", "rad", "rad"};
const char* const kStepParam[kChannels] = {"range_m", "course_rad", "glide_rad"};
const char* const kDriftParam[kChannels] = {"range_mps", "course_radps", "glide_radps"};

// One radar plot with the nav solution around it.
struct Plot {
  double t = 0;
  Eigen::Vector3d y;               // meas - nav [m, rad, rad]
  Eigen::Vector3d meas;            // measured polar
  double D = 0, Ek = 0, Eg = 0;    // nav polar
  double nav_h_m = 0;              // the nav's height at t, as read [m] (for the gross checks)
  Eigen::Matrix3d J;               // d(D, Ek, Eg)/dp at the nav position
  Eigen::Vector3d rate;            // d(D, Ek, Eg)/dt from the nav velocity
  /// What the catalogue's columns need (prl_effect_columns.hpp).
  prl_effect::PlotGeometry geometry() const {
    prl_effect::PlotGeometry g;
    g.t_s = t, g.range_m = D, g.glide_rad = Eg, g.J = J, g.rate = rate;
    return g;
  }
};
using Plots = std::shared_ptr<const std::vector<Plot>>;

// Columns laid out channel-major (observation c n + k is plot k's channel c): row block of
// plot k is f(plot) (3 x k).
template <class F>
std::function<Eigen::MatrixXd(std::size_t)> columns(const Plots& p, int k, F f) {
  return [p, k, f](std::size_t v) {
    const auto n = static_cast<Eigen::Index>(p->size());
    Eigen::MatrixXd C(kChannels * n, k);
    for (Eigen::Index i = 0; i < n; ++i) {
      const Eigen::MatrixXd B = f((*p)[static_cast<std::size_t>(i)], v);
      for (int c = 0; c < kChannels; ++c) C.row(c * n + i) = B.row(c);
    }
    return C;
  };
}

// The nav velocity at time t: the slope of a straight line fitted by least squares to the nav
// positions within half_window_s of t (j: the segment around t),
//   v = sum (t_k - t_bar)(p_k - p_bar) / sum (t_k - t_bar)^2,
// so that the nav solution's own sample noise does not reach the rates (a 0.3 m white error at
// 10 Hz differenced over one 0.1 s step is a 4 m/s velocity error; over +-1 s it is 0.1 m/s, and
// a centred window's slope is unbiased by a constant acceleration). Fewer than three samples
// in the window: the segment's difference.
Eigen::Vector3d nav_velocity(const PrlFlightData& data, const std::vector<Eigen::Vector3d>& nav_R, std::size_t j, double t,
                             double half_window_s) {
  std::size_t lo = j, hi = j + 1;
  while (lo > 0 && t - data.nav[lo - 1].t_s <= half_window_s) --lo;
  while (hi + 1 < data.nav.size() && data.nav[hi + 1].t_s - t <= half_window_s) ++hi;
  if (hi - lo + 1 < 3) return (nav_R[j + 1] - nav_R[j]) / (data.nav[j + 1].t_s - data.nav[j].t_s);
  double tb = 0;
  Eigen::Vector3d pb = Eigen::Vector3d::Zero();
  for (std::size_t k = lo; k <= hi; ++k) tb += data.nav[k].t_s, pb += nav_R[k];
  const double m = static_cast<double>(hi - lo + 1);
  tb /= m, pb /= m;
  double stt = 0;
  Eigen::Vector3d stp = Eigen::Vector3d::Zero();
  for (std::size_t k = lo; k <= hi; ++k) {
    const double dt = data.nav[k].t_s - tb;
    stt += dt * dt, stp += dt * (nav_R[k] - pb);
  }
  return stp / stt;
}

std::vector<Plot> plots_with_nav(const PrlFlightData& data, const DiagnoseOptions& o, int& dropped) {
  const LocalLevelFrame R = data.radar_frame();
  std::vector<Eigen::Vector3d> nav_R;
  for (const auto& s : data.nav) nav_R.push_back(R.from_geodetic(s.g));
  std::vector<Plot> out;
  std::size_t j = 0;
  for (std::size_t i = 0; i < data.plots.size(); ++i) {
    const double t = data.t_s[i];
    while (j + 1 < data.nav.size() && data.nav[j + 1].t_s < t) ++j;
    if (j + 1 >= data.nav.size() || data.nav[j].t_s > t || data.nav[j + 1].t_s - data.nav[j].t_s > o.max_nav_gap_s) {
      ++dropped;
      continue;
    }
    // p(t) = (1 - a) p_j + a p_(j+1); v from the nav around t (nav_velocity)
    const double t0 = data.nav[j].t_s, t1 = data.nav[j + 1].t_s, a = (t - t0) / (t1 - t0);
    const Eigen::Vector3d p = (1 - a) * nav_R[j] + a * nav_R[j + 1];
    const Eigen::Vector3d v = nav_velocity(data, nav_R, j, t, 0.5 * o.rate_window_s);
    const Polar q = polar_from_cartesian(p);
    Plot pl;
    pl.t = t;
    pl.D = q.range_m, pl.Ek = q.course_rad, pl.Eg = q.glide_rad;
    pl.nav_h_m = (1 - a) * data.nav[j].g.h_m + a * data.nav[j + 1].g.h_m;
    pl.J = polar_jacobian(p);
    pl.rate = pl.J * v;
    const Polar& m = data.plots[i];
    pl.meas << m.range_m, m.course_rad, m.glide_rad;
    pl.y << m.range_m - q.range_m, wrap_pi(m.course_rad - q.course_rad), m.glide_rad - q.glide_rad;
    out.push_back(pl);
  }
  return out;
}

Problem prl_problem(const Plots& P, const PrlFlightData& data, const DiagnoseOptions& o) {
  const std::vector<Plot>& pl = *P;
  const auto n = static_cast<Eigen::Index>(pl.size());
  Problem pb;
  const double sig[kChannels] = {o.sigma_range_m, o.sigma_course_deg * kDegToRad, o.sigma_glide_deg * kDegToRad};
  // The nav error (Gauss-Markov, sigma_nav per axis) seen by channel c of plot k: sigma_nav g_c(k),
  // g = |row c of the polar Jacobian| = (1, 1 / (D cos Eg), 1 / D): on the angles it grows as
  // 1 / D towards the threshold. The channel's nominal component: sigma_nav RMS_k g_c, seen with
  // the gain g_c(k) / RMS g_c.
  std::vector<double> gain(kChannels * pl.size());
  for (int c = 0; c < kChannels; ++c) {
    double g2 = 0;
    for (std::size_t k = 0; k < pl.size(); ++k) {
      const Plot& x = pl[k];
      const double g[kChannels] = {1.0, 1.0 / (x.D * std::cos(x.Eg)), 1.0 / x.D};
      gain[static_cast<std::size_t>(c) * pl.size() + k] = g[c];
      g2 += g[c] * g[c] / static_cast<double>(pl.size());
    }
    for (std::size_t k = 0; k < pl.size(); ++k) gain[static_cast<std::size_t>(c) * pl.size() + k] /= std::sqrt(g2);
    Channel ch{kChannelName[c], "", "", kChannelUnit[c], sig[c]};
    ch.nominal_corr_sigma = o.nav_sigma_m * std::sqrt(g2);
    ch.nominal_corr_tau_s = o.nav_tau_s;
    pb.channels.push_back(ch);
  }
  if (o.nav_sigma_m > 0) pb.nominal_corr_gain = gain;
  pb.nuisance = Eigen::MatrixXd::Zero(kChannels * n, kChannels);
  pb.nuisance_names = {"range_bias", "azimuth_bias", "elevation_bias"};
  for (int c = 0; c < kChannels; ++c)
    for (Eigen::Index k = 0; k < n; ++k) {
      const Plot& x = pl[static_cast<std::size_t>(k)];
      pb.channel.push_back(c);
      pb.t_s.push_back(x.t);
      pb.y.push_back(x.y(c));
      pb.estimation.push_back(x.t < o.split_time_s);
      pb.nuisance(c * n + k, c) = 1;
    }
  const double t_lo = pl.front().t, t_hi = pl.back().t, span = t_hi - t_lo;
  // The deterministic entries' columns are the simulator's own (common/physics/prl_effect_columns.hpp).
  namespace fx = prl_effect;
  const Eigen::Matrix3d R_R_ENU = fx::R_R_ENU(data.azimuth_reference_deg);
  using V = std::size_t;
  using M = Eigen::MatrixXd;
  const std::string rate = "the measurement rates (range rate, azimuth and elevation rates)";
  pb.catalogue.push_back({"range_gain", {}, {"g"}, "the slant range", "", {},
                          columns(P, 1, [](const Plot& x, V) -> M { return fx::range_gain(x.geometry()); })});
  pb.catalogue.push_back({"time_offset", {}, {"tau_s"}, rate, "", {},
                          columns(P, 1, [](const Plot& x, V) -> M { return fx::time_offset(x.geometry()); })});
  pb.catalogue.push_back({"elevation_refraction", {}, {"k_rad"}, "cot(elevation)", "", {},
                          columns(P, 1, [](const Plot& x, V) -> M { return fx::elevation_refraction(x.geometry()); })});
  pb.catalogue.push_back({"azimuth_elevation_coupling", {}, {"c_rad"}, "tan(elevation) on the azimuth", "", {},
                          columns(P, 1, [](const Plot& x, V) -> M { return fx::azimuth_elevation_coupling(x.geometry()); })});
  pb.catalogue.push_back({"site_offset", {}, {"east_m", "north_m", "up_m"}, "the geometry's Jacobian (a shifted site)", "", {},
                          columns(P, 3, [R_R_ENU](const Plot& x, V) -> M { return fx::site_offset(x.geometry(), R_R_ENU); })});
  for (int c = 0; c < kChannels; ++c) {
    pb.catalogue.push_back({"bias_drift", {}, {kDriftParam[c]}, std::string("time on the ") + kChannelName[c], "", {},
                            columns(P, 1, [c, t_lo](const Plot& x, V) -> M { return fx::bias_drift(x.geometry(), c, t_lo); })});
    pb.catalogue.back().shape = true;  // a shape in time, not a physical cause
  }
  std::vector<double> steps, periods;
  for (int k = 0; k < o.step_grid; ++k) steps.push_back(t_lo + span * (0.1 + 0.8 * k / (o.step_grid - 1)));
  for (double T = 4; T <= span / 3; T *= 1.05) periods.push_back(T);
  for (int c = 0; c < kChannels; ++c) {
    pb.catalogue.push_back({"bias_step", {}, {kStepParam[c]}, std::string("a jump in the ") + kChannelName[c], "t_s", steps,
                            columns(P, 1, [c, steps](const Plot& x, V v) -> M { return fx::bias_step(x.geometry(), c, steps[v]); })});
    if (periods.empty()) continue;
    pb.catalogue.push_back(
        {"periodic", {}, {std::string("sin_") + kStepParam[c], std::string("cos_") + kStepParam[c]},
         std::string("an oscillation in the ") + kChannelName[c], "period_s", periods,
         columns(P, 2, [c, periods](const Plot& x, V v) -> M { return fx::periodic(x.geometry(), c, periods[v]); })});
  }
  // covariates for what stays unexplained (the same per channel)
  const char* const names[] = {"time", "slant range", "elevation", "azimuth", "range rate", "cot(elevation)"};
  for (int v = 0; v < 6; ++v) {
    std::vector<double> x;
    for (int c = 0; c < kChannels; ++c)
      for (const auto& q : pl) {
        const double val[] = {q.t, q.D, q.Eg, q.Ek, q.rate(0), 1 / std::tan(q.Eg)};
        x.push_back(val[v]);
      }
    pb.covariates.push_back({names[v], x});
  }
  return pb;
}

// The compensated plot (measured minus the model's predicted error) against truth after the split.
void truth_gain(const PrlFlightData& data, const std::vector<Plot>& pl, const SearchResult& r, double split,
                DiagnoseReport& rep) {
  if (data.truth.size() < 2) return;
  const LocalLevelFrame R = data.radar_frame();
  std::vector<Eigen::Vector3d> tr_R;
  for (const auto& s : data.truth) tr_R.push_back(R.from_geodetic(s.g));
  const auto n = static_cast<Eigen::Index>(pl.size());
  ChannelGain g;
  g.unit = "m";
  double a = 0, b = 0;
  std::size_t k = 0;
  for (Eigen::Index i = 0; i < n; ++i) {
    const Plot& x = pl[static_cast<std::size_t>(i)];
    if (x.t < split) continue;
    while (k + 1 < data.truth.size() && data.truth[k + 1].t_s < x.t) ++k;
    if (k + 1 >= data.truth.size() || data.truth[k].t_s > x.t) continue;
    const double w = (x.t - data.truth[k].t_s) / (data.truth[k + 1].t_s - data.truth[k].t_s);
    const Eigen::Vector3d pt = (1 - w) * tr_R[k] + w * tr_R[k + 1];
    auto err = [&](const Eigen::VectorXd& pred) {
      const Polar q{x.meas(0) - pred(i), wrap_pi(x.meas(1) - pred(n + i)), x.meas(2) - pred(2 * n + i)};
      return (cartesian_from_polar(q) - pt).squaredNorm();
    };
    a += err(r.nominal_oos);
    b += err(r.extended_oos);
    ++g.n;
  }
  if (g.n == 0) return;
  g.nominal_rms = std::sqrt(a / g.n);
  g.extended_rms = std::sqrt(b / g.n);
  rep.gain["truth_position_m"] = g;
}

}  // namespace

DiagnoseReport diagnose_prl(const PrlFlightData& data, const DiagnoseOptions& o) {
  if (!(o.sigma_range_m > 0 && o.sigma_course_deg > 0 && o.sigma_glide_deg > 0))
    throw ConfigError("diagnose prl: nominal sigmas must be > 0");
  if (!(o.max_nav_gap_s > 0)) throw ConfigError("diagnose prl: max nav gap must be > 0 s");
  if (!(o.rate_window_s >= 0) || !std::isfinite(o.rate_window_s))
    throw ConfigError("diagnose prl: rate window must be finite and >= 0 s");
  if (o.step_grid < 2) throw ConfigError("diagnose prl: step grid must be >= 2");
  if (!(o.nav_sigma_m >= 0) || !(o.nav_tau_s > 0)) throw ConfigError("diagnose prl: nav sigma must be >= 0 m and nav tau > 0 s");
  DiagnoseReport rep;
  rep.split_time_s = o.split_time_s;
  auto plots = std::make_shared<std::vector<Plot>>(plots_with_nav(data, o, rep.plots_dropped));
  rep.plots_used = static_cast<int>(plots->size());
  if (plots->size() < 30) throw ConfigError("diagnose prl: fewer than 30 plots with a nav solution around them");
  {
    std::vector<PlotGeometry> g;
    for (const Plot& p : *plots) g.push_back({p.meas(0), p.meas(1), p.meas(2), p.D, p.Ek, p.Eg, p.nav_h_m});
    check_plot_units(g, data.azimuth_reference_deg, data.radar_site.h_m);
    // truth's heights against nav's once nav's are known right (a ratio of the two cannot say which is off)
    check_truth_heights(data.nav, data.truth);
  }
  const Problem pb = prl_problem(plots, data, o);
  check_limit_entries(pb, o.search.injection, "diagnose prl");
  const SearchResult r = search_effects(pb, o.search);

  for (int c = 0; c < kChannels; ++c) {
    EffectResult e;
    e.name = pb.nuisance_names[static_cast<std::size_t>(c)];
    e.nominal = true;
    e.params = {kChannelUnit[c]};
    e.estimate = {r.nuisance_beta(c)};
    e.stderr_ = {r.nuisance_se(c)};
    e.note = "nominal parameter (the paper's constant bias)";
    rep.effects.push_back(e);
  }
  add_search_findings(pb, r, rep);
  truth_gain(data, *plots, r, o.split_time_s, rep);

  const auto n = static_cast<Eigen::Index>(plots->size());
  const std::vector<char> flags = outlier_flags(pb, r);
  for (Eigen::Index i = 0; i < n; ++i) {
    DiagnoseReport::Row row{(*plots)[static_cast<std::size_t>(i)].t, {}, {}, {}, false};
    for (int c = 0; c < kChannels; ++c) {
      const Eigen::Index j = c * n + i;
      row.y[static_cast<std::size_t>(c)] = pb.y[static_cast<std::size_t>(j)];
      row.nominal[static_cast<std::size_t>(c)] = r.nominal_fit(j);
      row.extended[static_cast<std::size_t>(c)] = r.nuisance_fit(j) + r.effect_fit(j);
      row.outlier = row.outlier || flags[static_cast<std::size_t>(j)];
    }
    rep.rows.push_back(row);
  }
  return rep;
}

}  // namespace rnav
