#include "loggers/prl_stats.hpp"

#include "common/io/atomic_file.hpp"
#include "loggers/realization_set.hpp"
#include "loggers/state_json.hpp"

#include <nlohmann/json.hpp>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace rnav {

namespace {

constexpr double kRadToDeg = 57.29577951308232;
constexpr double kZ95 = 1.959963984540054;  // two-sided 95 % normal quantile

using state_json::exact_text;
using state_json::member;

std::string range_key(double r) {
  char b[32];
  std::snprintf(b, sizeof b, "%.0f", r);
  return b;
}

// The columns' building blocks, in the order the rows hold the values.
struct Axis {
  const char* name;  // the column name's suffix
  const char* text;  // what it is
};
// A plot error's components as PlotErrors holds them (apoi, toi, ...): X, Z, Y of the landing frame.
constexpr Axis kErrorAxes[3] = {{"x", "X (landing frame, along the runway axis)"},
                                {"z", "Z (landing frame, lateral)"},
                                {"y", "Y (landing frame, up)"}};
// The true aircraft position's components (PlotErrors::p_true_L): x, y, z of the landing frame.
constexpr Axis kPositionAxes[3] = {{"x", "X (landing frame, along the runway axis, from the threshold)"},
                                   {"y", "Y (landing frame, up)"},
                                   {"z", "Z (landing frame, lateral)"}};
// The plot errors: raw (APOI) and compensated (TOI).
constexpr Axis kErrorKinds[2] = {{"apoi", "APOI (raw plot) error"}, {"toi", "TOI (compensated plot) error"}};
// The bias filter's polar channels as written: range in m, the angles converted to deg.
struct Channel {
  const char* name;
  const char* unit;
  const char* text;
};
constexpr Channel kChannels[3] = {{"range", "m", "range channel"},
                                  {"course", "deg", "course (azimuth) channel"},
                                  {"glide", "deg", "glide (elevation) channel"}};
const std::string kBiasErr = "bias-estimate error (the filter's estimate minus the radar's systematic error)";

// What logger.table_range_origin measures a Table 2 range from.
std::string table_origin(const LoggerOptions& o) {
  return o.table_range_origin == "radar" ? "the radar antenna (slant range)" : "the runway threshold";
}

}  // namespace

bool PaperTable2::has(double r) { return r == 25000 || r == 4000; }
std::array<double, 3> PaperTable2::apoi(double r) {
  if (r == 25000) return {4.62, 45.12, 67.79};
  if (r == 4000) return {5.39, 7.64, 12.94};
  throw std::invalid_argument("the paper's Table 2 has no range " + range_key(r));
}
std::array<double, 3> PaperTable2::toi(double r) {
  if (r == 25000) return {3.71, 37.23, 54.81};
  if (r == 4000) return {0.04, 0.08, -0.07};
  throw std::invalid_argument("the paper's Table 2 has no range " + range_key(r));
}

PrlStats::PrlStats(const LoggerOptions& o, const SiteContext& site)
    : logger_(o),
      site_(site),
      table_apoi_(o.table_ranges_m.size()),
      table_toi_(o.table_ranges_m.size()),
      table_plots_(o.table_ranges_m.size(), -1) {}

void PrlStats::add_realization(const std::vector<PlotErrors>& plots, long realization) {
  if (realization < 0) realization = held_.empty() ? 0 : *held_.rbegin() + 1;
  if (held_.count(realization))
    throw std::runtime_error("realization " + std::to_string(realization) + " added twice");
  const auto& ranges = logger_.table_ranges_m;
  // Validate first, then add: a rejected realization leaves no partial contribution.
  // Within this realization (a fixed order wherever it runs): plain sums.
  using Local = Moments<3, PlainSum>;
  std::vector<Local> a(ranges.size()), t(ranges.size()), be(ranges.size());
  for (const auto& p : plots)
    for (std::size_t i = 0; i < ranges.size(); ++i)
      if (std::abs(p.range_table_m - ranges[i]) <= logger_.table_halfwidth_m) {
        a[i].add(p.apoi);
        t[i].add(p.toi);
        be[i].add(p.bias_err);
      }
  for (std::size_t i = 0; i < ranges.size(); ++i) {
    if (a[i].n == 0)
      throw std::runtime_error("realization has no plot within " +
                               fixed(logger_.table_halfwidth_m, 0) + " m of table range " +
                               range_key(ranges[i]) + " m (logger.table_ranges_m)");
    if (table_plots_[i] >= 0 && table_plots_[i] != a[i].n)
      throw std::runtime_error("table range " + range_key(ranges[i]) +
                               " m: realizations differ in the number of plots in the bin");
  }
  for (const auto& p : plots) {
    auto& tb = by_time_[p.utime];
    tb.range_true_m = p.range_true_m;
    tb.range_table_m = p.range_table_m;
    tb.p_true_L = p.p_true_L;
    tb.apoi.add(p.apoi);
    tb.toi.add(p.toi);
    tb.bias_err.add(p.bias_err);
    tb.bias_var.add(p.bias_var);
    auto& rb = by_range_[static_cast<long>(std::floor(p.range_true_m / logger_.range_bin_m))];
    rb.first.add(p.apoi);
    rb.second.add(p.toi);
  }
  // realizations.csv: this realization's mean errors per Table 2 bin and per slant-range bin.
  std::map<long, std::array<Local, 3>> bins;  // bin index -> (apoi, toi, bias_err)
  for (const auto& p : plots) {
    auto& m = bins[static_cast<long>(std::floor(p.range_true_m / logger_.range_bin_m))];
    m[0].add(p.apoi);
    m[1].add(p.toi);
    m[2].add(p.bias_err);
  }
  std::string& rows = realization_rows_[realization];
  auto row = [&](const char* kind, double lo, double hi, const Local& ap, const Local& to, const Local& bi) {
    const double scale[3] = {1, kRadToDeg, kRadToDeg};
    rows += std::to_string(realization) + "," + kind + "," + fixed(lo, 0) + "," + fixed(hi, 0) + "," + std::to_string(ap.n);
    for (const auto* m : {&ap, &to})
      for (int k = 0; k < 3; ++k) rows += "," + exact_text(m->mean(k));
    for (int k = 0; k < 3; ++k) rows += "," + exact_text(bi.mean(k) * scale[k]);
    rows += "\n";
  };
  for (std::size_t i = 0; i < ranges.size(); ++i)
    row("table", ranges[i] - logger_.table_halfwidth_m, ranges[i] + logger_.table_halfwidth_m, a[i], t[i], be[i]);
  for (const auto& [bin, m] : bins)
    row("range", bin * logger_.range_bin_m, (bin + 1) * logger_.range_bin_m, m[0], m[1], m[2]);
  for (std::size_t i = 0; i < ranges.size(); ++i) {
    table_plots_[i] = a[i].n;
    std::array<double, 3> ma, mt;
    for (int k = 0; k < 3; ++k) {
      ma[k] = a[i].mean(k);
      mt[k] = t[i].mean(k);
    }
    table_apoi_[i].add(ma);
    table_toi_[i].add(mt);
  }
  held_.insert(realization);
  ++n_real_;
}

std::string PrlStats::table2_text(std::int64_t seed) const {
  std::ostringstream o;
  o << "Table 2: systematic error (ensemble mean over " << n_real_ << " realizations, seed "
    << seed << "), metres, landing frame\n";
  o << "range: distance from the " << logger_.table_range_origin << " [m]; +- half-width of the 95 % band [m]\n";
  const char* rows[2] = {"APOI", "TOI"};
  {
    char b[256];
    std::snprintf(b, sizeof b, "%-10s  %6s %8s +- %-8s %8s +- %-8s %8s +- %-8s | paper X, Z, Y [m]\n", "range", "row",
                  "X [m]", "95 %", "Z [m]", "95 %", "Y [m]", "95 %");
    o << b;
  }
  for (std::size_t i = 0; i < logger_.table_ranges_m.size(); ++i) {
    const double r = logger_.table_ranges_m[i];
    for (int row = 0; row < 2; ++row) {
      const auto& m = row == 0 ? table_apoi_[i] : table_toi_[i];
      char b[256];
      std::snprintf(b, sizeof b, "%8.0f m  %6s ", r, rows[row]);
      o << b;
      for (int k = 0; k < 3; ++k) {
        if (m.n >= 2)
          std::snprintf(b, sizeof b, "%8.2f +- %-8.2f ", m.mean(k),
                        kZ95 * m.sd(k) / std::sqrt(static_cast<double>(m.n)));
        else  // one realization: no spread to estimate a band from
          std::snprintf(b, sizeof b, "%8.2f +- %-8s ", m.mean(k), "n/a");
        o << b;
      }
      if (PaperTable2::has(r)) {
        const auto p = row == 0 ? PaperTable2::apoi(r) : PaperTable2::toi(r);
        std::snprintf(b, sizeof b, "| %6.2f %6.2f %6.2f", p[0], p[1], p[2]);
        o << b;
      }
      o << "\n";
    }
  }
  return o.str();
}

void PrlStats::write(const std::string& dir, std::int64_t seed) const {
  if (realization_rows_.size() != held_.size())
    throw std::logic_error("PrlStats::write: merged shards' realizations.csv rows are not held here (write_statistics, "
                           "then join the shards' files)");
  write_statistics(dir, seed);
  // Per realization (in order) and bin: "table" rows are Table 2's bins (true distance in the
  // sense of logger.table_range_origin within +-table_halfwidth_m of a table range), whose
  // ensemble means table2.json holds; "range" rows the 1 km slant-range bins of stats_range.csv.
  const auto columns = realizations_columns();
  write_file_atomic(dir, "realizations.csv", csv_header(columns) + all_rows());
  write_csv_units(dir, "realizations.csv", columns);
}

std::vector<CsvColumnDoc> PrlStats::realizations_columns() const {
  const std::string of_bin = ", this realization's mean over the bin's plots";
  const std::string edge = " (table bins: true distance from " + table_origin(logger_) +
                           ", logger.table_range_origin; range bins: true slant range from the radar)";
  std::vector<CsvColumnDoc> c{
      {"realization", "", "realization index in the ensemble"},
      {"bin", "", "bin kind: table (a Table 2 bin) or range (a slant-range bin of stats_range.csv)"},
      {"lo_m", "m", "lower edge of the bin" + edge},
      {"hi_m", "m", "upper edge of the bin" + edge},
      {"plots", "", "this realization's plots in the bin"}};
  for (const auto& k : kErrorKinds)
    for (const auto& a : kErrorAxes) c.push_back({std::string(k.name) + "_" + a.name + "_m", "m", std::string(k.text) + " along " + a.text + of_bin});
  for (const auto& ch : kChannels)
    c.push_back({std::string("biaserr_") + ch.name + "_" + ch.unit, ch.unit, kBiasErr + ", " + ch.text + of_bin});
  return c;
}

std::vector<CsvColumnDoc> PrlStats::stats_time_columns() const {
  std::vector<CsvColumnDoc> c{
      {"t_s", "s", "plot time since sim time 0 (runner.epoch_utime)"},
      {"range_m", "m", "true slant range of the aircraft from the radar"},
      {"range_table_m", "m", "true distance of the aircraft from " + table_origin(logger_) + " (logger.table_range_origin)"},
      {"n", "", "realizations averaged (their plots at this time)"}};
  for (const auto& k : kErrorKinds)
    for (const char* s : {"mean", "rms"})
      for (const auto& a : kErrorAxes)
        c.push_back({std::string(k.name) + "_" + s + "_" + a.name + "_m", "m",
                     std::string(k.text) + " along " + a.text + ", ensemble " + (s == std::string("mean") ? "mean" : "RMS")});
  for (const char* s : {"mean", "rms"})
    for (const auto& ch : kChannels)
      c.push_back({std::string("biaserr_") + s + "_" + ch.name + "_" + ch.unit, ch.unit,
                   kBiasErr + ", " + ch.text + ", ensemble " + (s == std::string("mean") ? "mean" : "RMS")});
  for (const auto& ch : kChannels)
    c.push_back({std::string("filter_sd_") + ch.name + "_" + ch.unit, ch.unit,
                 std::string("the bias filter's own 1 sigma of its estimate, ") + ch.text +
                     " (square root of its variance's ensemble mean)"});
  for (const auto& a : kPositionAxes)
    c.push_back({std::string("aircraft_") + a.name + "_m", "m", std::string("true aircraft position along ") + a.text});
  return c;
}

std::vector<CsvColumnDoc> PrlStats::stats_range_columns() const {
  std::vector<CsvColumnDoc> c{{"range_lo_m", "m", "lower edge of the bin of true slant range from the radar"},
                              {"range_hi_m", "m", "upper edge of the bin of true slant range from the radar"},
                              {"n", "", "plots in the bin, over all realizations"}};
  for (const auto& k : kErrorKinds)
    for (const char* s : {"mean", "rms"})
      for (const auto& a : kErrorAxes)
        c.push_back({std::string(k.name) + "_" + s + "_" + a.name + "_m", "m",
                     std::string(k.text) + " along " + a.text + ", " + (s == std::string("mean") ? "mean" : "RMS") +
                         " over the bin's plots of every realization"});
  return c;
}

void PrlStats::write_statistics(const std::string& dir, std::int64_t seed) const {
  if (n_real_ == 0) throw std::runtime_error("no complete realization to write");
  std::filesystem::create_directories(dir);
  const auto& ranges = logger_.table_ranges_m;
  // table2.json: the interface users and checks script against.
  nlohmann::ordered_json t2;
  t2["realizations"] = n_real_;
  t2["seed"] = seed;
  nlohmann::ordered_json detail;
  detail["realizations"] = n_real_;
  detail["seed"] = seed;
  detail["unit"] = "m, landing frame L (X along the runway axis, Z lateral, Y up)";
  detail["range_origin"] = logger_.table_range_origin;
  detail["range_definition"] = std::string("true distance from the ") +
                               (logger_.table_range_origin == "radar" ? "radar antenna (slant range)"
                                                                          : "runway threshold") +
                               "; per realization the mean over plots within +-halfwidth_m, then "
                               "the ensemble mean";
  detail["halfwidth_m"] = logger_.table_halfwidth_m;
  for (const char* row : {"APOI", "TOI"}) {
    t2[row] = nlohmann::ordered_json::object();
    for (std::size_t i = 0; i < ranges.size(); ++i) {
      const auto& m = std::string(row) == "APOI" ? table_apoi_[i] : table_toi_[i];
      nlohmann::ordered_json mean = nlohmann::ordered_json::array(), se = mean, within = mean;
      for (int k = 0; k < 3; ++k) {
        const double s = m.sd(k) / std::sqrt(static_cast<double>(m.n));
        mean.push_back(m.mean(k));
        se.push_back(s);
        within.push_back(std::abs(m.mean(k)) <= kZ95 * s);
      }
      t2[row][range_key(ranges[i])] = mean;
      auto& d = detail[row][range_key(ranges[i])];
      d["mean"] = mean;
      d["stderr"] = se;
      d["band95_halfwidth"] = {kZ95 * se[0].get<double>(), kZ95 * se[1].get<double>(),
                               kZ95 * se[2].get<double>()};
      d["zero_within_band95"] = within;
      d["plots_per_realization"] = table_plots_[i];
      if (PaperTable2::has(ranges[i]))
        d["paper"] = std::string(row) == "APOI" ? PaperTable2::apoi(ranges[i])
                                                : PaperTable2::toi(ranges[i]);
    }
  }
  write_file_atomic(dir, "table2.json", t2.dump(2) + "\n");
  write_file_atomic(dir, "table2_detail.json", detail.dump(2) + "\n");
  write_file_atomic(dir, "table2.txt", table2_text(seed));

  const auto time_columns = stats_time_columns();
  std::ostringstream ts;
  ts << csv_header(time_columns);
  for (const auto& [utime, b] : by_time_) {
    ts << fixed((utime - site_.runner.epoch_utime) * 1e-6, 3) << "," << fixed(b.range_true_m, 2) << ","
       << fixed(b.range_table_m, 2) << "," << b.apoi.n;
    for (const auto* m : {&b.apoi, &b.toi}) {
      for (int k = 0; k < 3; ++k) ts << "," << fixed(m->mean(k));
      for (int k = 0; k < 3; ++k) ts << "," << fixed(m->rms(k));
    }
    const double scale[3] = {1, kRadToDeg, kRadToDeg};
    for (int k = 0; k < 3; ++k) ts << "," << fixed(b.bias_err.mean(k) * scale[k], 9);
    for (int k = 0; k < 3; ++k) ts << "," << fixed(b.bias_err.rms(k) * scale[k], 9);
    for (int k = 0; k < 3; ++k) ts << "," << fixed(std::sqrt(b.bias_var.mean(k)) * scale[k], 9);
    for (int k = 0; k < 3; ++k) ts << "," << fixed(b.p_true_L[k], 2);
    ts << "\n";
  }
  write_file_atomic(dir, "stats_time.csv", ts.str());
  write_csv_units(dir, "stats_time.csv", time_columns);

  const auto range_columns = stats_range_columns();
  std::ostringstream rs;
  rs << csv_header(range_columns);
  for (const auto& [bin, m] : by_range_) {
    rs << fixed(bin * logger_.range_bin_m, 0) << "," << fixed((bin + 1) * logger_.range_bin_m, 0)
       << "," << m.first.n;
    for (const auto* mm : {&m.first, &m.second}) {
      for (int k = 0; k < 3; ++k) rs << "," << fixed(mm->mean(k));
      for (int k = 0; k < 3; ++k) rs << "," << fixed(mm->rms(k));
    }
    rs << "\n";
  }
  write_file_atomic(dir, "stats_range.csv", rs.str());
  write_csv_units(dir, "stats_range.csv", range_columns);
  write_file_atomic(dir, "ensemble_state.json", state(seed).dump() + "\n");
}

std::string PrlStats::all_rows() const {
  std::string s;
  for (const auto& [r, rows] : realization_rows_) s += rows;
  return s;
}

nlohmann::ordered_json PrlStats::state(std::int64_t seed) const {
  using J = nlohmann::ordered_json;
  J j;
  j["kind"] = "landing";
  j["format"] = 1;
  j["seed"] = seed;
  j["realizations"] = n_real_;
  j["by_time"] = J::array();
  for (const auto& [utime, b] : by_time_)
    j["by_time"].push_back({{"utime", utime}, {"range_true_m", exact_text(b.range_true_m)}, {"range_table_m", exact_text(b.range_table_m)},
                            {"p_true_L", {exact_text(b.p_true_L[0]), exact_text(b.p_true_L[1]), exact_text(b.p_true_L[2])}},
                            {"apoi", b.apoi.state()}, {"toi", b.toi.state()}, {"bias_err", b.bias_err.state()},
                            {"bias_var", b.bias_var.state()}});
  j["by_range"] = J::array();
  for (const auto& [bin, m] : by_range_) j["by_range"].push_back({{"bin", bin}, {"apoi", m.first.state()}, {"toi", m.second.state()}});
  j["table"] = J::array();
  for (std::size_t i = 0; i < table_apoi_.size(); ++i)
    j["table"].push_back({{"plots", table_plots_[i]}, {"apoi", table_apoi_[i].state()}, {"toi", table_toi_[i].state()}});
  j["held"] = realization_intervals(held_);
  return j;
}

namespace {

double read_full(const nlohmann::json& j, const std::string& what) { return state_json::read_exact(j, what, true); }

}  // namespace

void PrlStats::merge_state(const nlohmann::json& j, std::int64_t seed, const std::string& what) {
  if (member(j, "kind", what) != "landing" || member(j, "format", what) != 1)
    throw std::invalid_argument(what + ": not a landing-radar ensemble state (format 1)");
  if (member(j, "seed", what) != seed)
    throw std::invalid_argument(what + ": seed " + member(j, "seed", what).dump() + ", the merged ensemble's is " + std::to_string(seed));
  const auto& ranges = logger_.table_ranges_m;
  // Parse everything into a PrlStats of its own first: a rejected shard changes nothing here.
  PrlStats o(logger_, site_);
  o.n_real_ = member(j, "realizations", what).get<long>();
  o.held_ = rnav::realization_set(member(j, "held", what), what);
  for (long r : o.held_)
    if (held_.count(r)) throw std::invalid_argument(what + ": realization " + std::to_string(r) + " is already in the merged ensemble");
  if (static_cast<long>(o.held_.size()) != o.n_real_)
    throw std::invalid_argument(what + ": " + std::to_string(o.n_real_) + " realizations but 'held' names " +
                                std::to_string(o.held_.size()));
  for (const auto& b : member(j, "by_time", what)) {
    const std::string w = what + " by_time[" + member(b, "utime", what).dump() + "]";
    auto& tb = o.by_time_[member(b, "utime", w).get<std::int64_t>()];
    tb.range_true_m = read_full(member(b, "range_true_m", w), w + ".range_true_m");
    tb.range_table_m = read_full(member(b, "range_table_m", w), w + ".range_table_m");
    const auto& p = member(b, "p_true_L", w);
    if (!p.is_array() || p.size() != 3) throw std::invalid_argument(w + ".p_true_L: expected 3 numbers");
    for (int k = 0; k < 3; ++k) tb.p_true_L[k] = read_full(p[k], w + ".p_true_L");
    tb.apoi = Moments<3>::from_state(member(b, "apoi", w), w + ".apoi");
    tb.toi = Moments<3>::from_state(member(b, "toi", w), w + ".toi");
    tb.bias_err = Moments<3>::from_state(member(b, "bias_err", w), w + ".bias_err");
    tb.bias_var = Moments<3>::from_state(member(b, "bias_var", w), w + ".bias_var");
  }
  for (const auto& b : member(j, "by_range", what)) {
    const std::string w = what + " by_range";
    auto& rb = o.by_range_[member(b, "bin", w).get<long>()];
    rb.first = Moments<3>::from_state(member(b, "apoi", w), w + ".apoi");
    rb.second = Moments<3>::from_state(member(b, "toi", w), w + ".toi");
  }
  const auto& table = member(j, "table", what);
  if (!table.is_array() || table.size() != ranges.size())
    throw std::invalid_argument(what + ": table has " + std::to_string(table.size()) + " ranges, the scenario " +
                                std::to_string(ranges.size()));
  for (std::size_t i = 0; i < ranges.size(); ++i) {
    o.table_plots_[i] = member(table[i], "plots", what).get<long>();
    o.table_apoi_[i] = Moments<3>::from_state(member(table[i], "apoi", what), what + " table.apoi");
    o.table_toi_[i] = Moments<3>::from_state(member(table[i], "toi", what), what + " table.toi");
    if (n_real_ > 0 && o.n_real_ > 0 && table_plots_[i] != o.table_plots_[i])
      throw std::invalid_argument(what + ": table range " + range_key(ranges[i]) +
                                  " m: realizations differ in the number of plots in the bin");
  }
  // Every check passed: add.
  for (auto& [utime, b] : o.by_time_) {
    auto it = by_time_.find(utime);
    if (it == by_time_.end()) {
      by_time_.emplace(utime, b);
      continue;
    }
    if (it->second.p_true_L != b.p_true_L || it->second.range_true_m != b.range_true_m)
      throw std::invalid_argument(what + ": the true aircraft position at utime " + std::to_string(utime) +
                                  " differs from the merged ensemble's (another scenario?)");
    it->second.apoi.merge(b.apoi);
    it->second.toi.merge(b.toi);
    it->second.bias_err.merge(b.bias_err);
    it->second.bias_var.merge(b.bias_var);
  }
  for (auto& [bin, m] : o.by_range_) {
    by_range_[bin].first.merge(m.first);
    by_range_[bin].second.merge(m.second);
  }
  for (std::size_t i = 0; i < ranges.size(); ++i) {
    if (o.n_real_ > 0) table_plots_[i] = o.table_plots_[i];
    table_apoi_[i].merge(o.table_apoi_[i]);
    table_toi_[i].merge(o.table_toi_[i]);
  }
  held_.insert(o.held_.begin(), o.held_.end());
  n_real_ += o.n_real_;
}

}  // namespace rnav
