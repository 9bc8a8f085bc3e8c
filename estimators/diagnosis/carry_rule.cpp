#include "estimators/diagnosis/carry_rule.hpp"

#include "common/io/config.hpp"
#include "estimators/model_id/stats.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace rnav {

void check_carry_options(const CarryOptions& o) {
  if (!std::isfinite(o.tolerance) || !(o.tolerance == 0 || o.tolerance >= 1))
    throw ConfigError("carry: tolerance must be >= 1 (the most a carried value may raise a fitted pair's error, x nominal) or 0 "
                      "(no check), got " + short_num(o.tolerance));
  if (o.min_n < 1) throw ConfigError("carry: min_n must be >= 1, got " + std::to_string(o.min_n));
  if (o.max_choices < 2) throw ConfigError("carry: max_choices must be >= 2, got " + std::to_string(o.max_choices));
}

namespace {

// Grid points per effect: 11 (0, 0.1, ..., 1) while 11^m <= max_choices, else the most n >= 2
// with n^m <= max_choices (2 when even that does not fit: 2^m choices).
int points_per_effect(std::size_t m, int max_choices) {
  for (int n = 11; n > 2; --n) {
    double total = 1;
    for (std::size_t k = 0; k < m; ++k) total *= n;
    if (total <= max_choices) return n;
  }
  return 2;
}

AppliedEffect scaled(const AppliedEffect& e, double share) {
  AppliedEffect out = e;
  for (double& v : out.value) v *= share;
  return out;
}

}  // namespace

CarriedHardware carry_no_harm(const std::vector<AppliedEffect>& fitted, const std::vector<FittedRecording>& recordings,
                              const CarryOptions& o) {
  check_carry_options(o);
  CarriedHardware c;
  c.tolerance = o.tolerance;
  c.fitted = fitted;
  const std::size_t m = fitted.size();
  // per recording: each hardware effect's prediction (empty: no observations there), the sum of
  // its own effects' predictions, and its pairs' errors with those alone (each ratio's denominator)
  std::vector<std::vector<Eigen::VectorXd>> pred;
  std::vector<Eigen::VectorXd> own_pred;
  std::vector<std::vector<LeaveOneOutRow>> own_rows;
  for (const FittedRecording& r : recordings) {
    pred.push_back(r.scorer->predictions(fitted));
    Eigen::VectorXd sum = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(r.scorer->observations()));
    const std::vector<Eigen::VectorXd> own = r.scorer->predictions(r.own);
    for (std::size_t k = 0; k < own.size(); ++k) {
      if (own[k].size() == 0)
        throw std::logic_error("carry_no_harm: the recording's own effect " + r.own[k].name + " has no observations in it");
      sum += own[k];
    }
    own_rows.push_back(r.scorer->rows(sum));
    own_pred.push_back(std::move(sum));
  }
  auto score = [&](const std::vector<double>& share) {
    std::vector<LeaveOneOutRow> rows;
    for (std::size_t r = 0; r < recordings.size(); ++r) {
      Eigen::VectorXd sum = own_pred[r];
      for (std::size_t k = 0; k < m; ++k)
        if (pred[r][k].size() > 0 && share[k] != 0) sum += share[k] * pred[r][k];
      std::vector<LeaveOneOutRow> x = recordings[r].scorer->rows(sum);
      for (std::size_t i = 0; i < x.size(); ++i) x[i].nominal_rms = own_rows[r][i].extended_rms;  // the same pairs, in order
      rows.insert(rows.end(), x.begin(), x.end());
    }
    return summarize(rows, o.min_n);
  };
  const std::vector<double> ones(m, 1.0);
  c.whole = score(ones);
  c.share = ones;
  c.chosen = c.whole;
  c.choices = 1;
  if (o.tolerance > 0 && m > 0) {
    const int n = points_per_effect(m, o.max_choices);
    // every combination of shares (k_1 .. k_m) / (n - 1), the last effect's share varying fastest
    std::vector<int> idx(m, 0);
    std::vector<double> share(m, 0.0);
    bool found = false;
    double best_geomean = 0, best_total = 0;
    c.choices = 0;
    while (true) {
      double total = 0;
      for (std::size_t k = 0; k < m; ++k) total += share[k] = static_cast<double>(idx[k]) / (n - 1);
      const LeaveOneOutSummary s = score(share);
      ++c.choices;
      // no pairs to check: nothing is made worse (geometric mean 1)
      const double g = s.pairs > 0 ? s.geomean : 1.0, worst = s.pairs > 0 ? s.worst : 1.0;
      const double eps = 1e-12;
      if (worst <= o.tolerance + eps &&
          (!found || g < best_geomean - eps || (std::abs(g - best_geomean) <= eps && total > best_total))) {
        found = true;
        best_geomean = g;
        best_total = total;
        c.share = share;
        c.chosen = s;
      }
      std::size_t k = m;
      while (k > 0 && idx[k - 1] == n - 1) idx[--k] = 0;
      if (k == 0) break;
      ++idx[k - 1];
    }
    // all shares 0 leaves every pair at its nominal error (ratio 1 <= tolerance)
    if (!found) throw std::logic_error("carry_no_harm: no choice within tolerance, not even carrying nothing");
  }
  for (std::size_t k = 0; k < m; ++k)
    if (c.share[k] > 0) c.carried.push_back(scaled(fitted[k], c.share[k]));
  return c;
}

nlohmann::ordered_json carry_json(const CarriedHardware& c) {
  auto summary = [](const LeaveOneOutSummary& s) {
    return nlohmann::ordered_json{{"min_n", s.min_n}, {"pairs", s.pairs}, {"geomean_ratio", s.geomean}, {"worst_ratio", s.worst},
                                  {"worst", s.worst_key}};
  };
  auto str_or_null = [](const std::string& x) { return x.empty() ? nlohmann::ordered_json(nullptr) : nlohmann::ordered_json(x); };
  nlohmann::ordered_json j;
  j["tolerance"] = c.tolerance;
  j["choices"] = c.choices;
  j["fitted_recordings"] = {{"whole", summary(c.whole)}, {"chosen", summary(c.chosen)}};
  j["effects"] = nlohmann::ordered_json::array();
  for (std::size_t k = 0; k < c.fitted.size(); ++k) {
    const AppliedEffect& e = c.fitted[k];
    nlohmann::ordered_json x;
    x["name"] = e.name;
    x["scope"] = {{"sensor", str_or_null(e.sensor)}, {"target", str_or_null(e.target)}};
    x["share"] = c.share[k];
    x["fitted"] = e.value;
    x["estimate"] = scaled(e, c.share[k]).value;
    if (std::isfinite(e.scan_value)) x["scanned"] = {{"value", e.scan_value}};
    j["effects"].push_back(x);
  }
  return j;
}

std::string carry_text(const CarriedHardware& c, const std::string& indent) {
  std::ostringstream o;
  for (std::size_t k = 0; k < c.fitted.size(); ++k) {
    const AppliedEffect& e = c.fitted[k];
    o << indent << e.key() << ": share " << short_num(c.share[k]) << " (";
    for (std::size_t j = 0; j < e.value.size(); ++j) o << (j ? ", " : "") << short_num(c.share[k] * e.value[j]);
    o << " of";
    for (std::size_t j = 0; j < e.value.size(); ++j) o << (j ? ", " : " ") << short_num(e.value[j]);
    o << ")\n";
  }
  return o.str();
}

}  // namespace rnav
