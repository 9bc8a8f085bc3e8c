#include "scenario.hpp"

#include "options_io.hpp"

#include <cmath>
#include <filesystem>
#include <limits>

namespace rnav {

std::int64_t to_us(double t_s) { return std::llround(t_s * 1e6); }

namespace options_io {  // the visit() overloads must be found by read_section's ADL


template <class V> void visit(RunwayOptions& o, V& v) {
  v.num("threshold_lat_deg", o.threshold.lat_deg, -89, 89);
  v.num("threshold_lon_deg", o.threshold.lon_deg, -180, 180);
  v.num("threshold_h_m", o.threshold.h_m, -500, 9000);
  v.num("heading_deg", o.heading_deg, 0, 360);
}
template <class V> void visit(RadarSiteOptions& o, V& v) {
  v.num("x_m", o.x_m, -5000, 5000);
  v.num("z_m", o.z_m, -3000, 3000);
  v.num("antenna_height_m", o.antenna_height_m, 0, 100);
  v.num("azimuth_reference_deg", o.azimuth_reference_deg, -1, 360);
}
template <class V> void visit(TrajectoryOptions& o, V& v) {
  v.num("start_x_m", o.start_x_m, 1000, 200000);
  v.num("start_y_m", o.start_y_m, 10, 15000);
  v.num("start_z_m", o.start_z_m, -100000, 100000);
  v.num("speed_mps", o.speed_mps, 10, 300);
  v.num("intercept_x_m", o.intercept_x_m, 0, 200000);
  v.num("bank_deg", o.bank_deg, 1, 60);
  v.num("glide_deg", o.glide_deg, 0.5, 10);
  v.num("aim_x_m", o.aim_x_m, -5000, 5000);
  v.num("end_x_m", o.end_x_m, -5000, 50000);
  v.num("step_s", o.step_s, 0.01, 10);
  v.str("replay_csv", o.replay_csv);
  v.num("replay_smoothing_s", o.replay_smoothing_s, 1, 300);
  v.num("replay_max_gap_s", o.replay_max_gap_s, 1e-3, 120);
}
template <class V> void visit(PrlOptions& o, V& v) {
  v.num("period_s", o.period_s, 0.01, 60);
  v.num("phase_s", o.phase_s, 0, 60);
  v.num("max_range_m", o.max_range_m, 100, 500000);
  v.num("bias_range_m", o.bias_range_m, -1000, 1000);
  v.num("bias_course_deg", o.bias_course_deg, -10, 10);
  v.num("bias_glide_deg", o.bias_glide_deg, -10, 10);
  v.num("noise2s_range_m", o.noise2s_range_m, 0, 1000);
  v.num("noise2s_course_deg", o.noise2s_course_deg, 0, 10);
  v.num("noise2s_glide_deg", o.noise2s_glide_deg, 0, 10);
  v.num("drift_sigma_range_m", o.drift_sigma_range_m, 0, 1000);
  v.num("drift_sigma_course_deg", o.drift_sigma_course_deg, 0, 10);
  v.num("drift_sigma_glide_deg", o.drift_sigma_glide_deg, 0, 10);
  v.num("drift_tau_s", o.drift_tau_s, 1, kInf);
}
template <class V> void visit(PrlEffectsOptions& o, V& v) {
  v.num("range_gain", o.range_gain, -0.1, 0.1);
  v.num("time_offset_s", o.time_offset_s, -10, 10);
  v.num("elevation_refraction_rad", o.elevation_refraction_rad, -0.01, 0.01);
  v.num("azimuth_elevation_coupling_rad", o.azimuth_elevation_coupling_rad, -1, 1);
  v.num("site_offset_east_m", o.site_offset_east_m, -1000, 1000);
  v.num("site_offset_north_m", o.site_offset_north_m, -1000, 1000);
  v.num("site_offset_up_m", o.site_offset_up_m, -1000, 1000);
  v.num("drift_range_mps", o.drift_range_mps, -10, 10);
  v.num("drift_course_radps", o.drift_course_radps, -0.01, 0.01);
  v.num("drift_glide_radps", o.drift_glide_radps, -0.01, 0.01);
  v.num("step_time_s", o.step_time_s, -1, 1e6);
  v.num("step_range_m", o.step_range_m, -1000, 1000);
  v.num("step_course_rad", o.step_course_rad, -0.1, 0.1);
  v.num("step_glide_rad", o.step_glide_rad, -0.1, 0.1);
  v.num("noise_scale", o.noise_scale, 1e-3, 100);
  v.num("outlier_prob", o.outlier_prob, 0, 0.5);
  v.num("outlier_scale", o.outlier_scale, 1, 1000);
  v.num("correlated_noise_tau_s", o.correlated_noise_tau_s, 0, 1e5);
  v.num("periodic_period_s", o.periodic_period_s, 0, 1e5);
  v.num("periodic_range_m", o.periodic_range_m, -1000, 1000);
  v.num("periodic_course_rad", o.periodic_course_rad, -0.1, 0.1);
  v.num("periodic_glide_rad", o.periodic_glide_rad, -0.1, 0.1);
}
template <class V> void visit(SnsinsOptions& o, V& v) {
  v.num("link_period_s", o.link_period_s, 0.01, 60);
  v.num("link_phase_s", o.link_phase_s, 0, 60);
  v.num("latency_s", o.latency_s, 0, 10);
  v.num("corr_sigma_m", o.corr_sigma_m, 0, 1000);
  v.num("corr_tau_s", o.corr_tau_s, 0.01, kInf);
  v.num("white_sigma_m", o.white_sigma_m, 0, 1000);
  v.num("sns_period_s", o.sns_period_s, 0.001, 10);
  v.num("ins_tau_s", o.ins_tau_s, 0, 10000);
  v.num("vel_sigma_mps", o.vel_sigma_mps, 0, 100);
  v.intervals("dropouts", o.dropouts, 0, 1e6);
}
template <class V> void visit(DatalinkOptions& o, V& v) {
  v.flag("enabled", o.enabled);
  v.num("peak_power_w", o.peak_power_w, 1e-15, 1e9);
  v.choice("family", o.family, {"gold", "gold-qpsk", "ab2", "ab3", "tent", "ab2-phase", "ab3-phase", "tent-phase"});
  v.integer("code_length", o.code_length, 127, 1023);
  v.choice("filter", o.filter, {"rc", "brick"});
  v.num("bandwidth_chips", o.bandwidth_chips, 1e-3, 100);
  v.num("rolloff", o.rolloff, 1e-3, 1);
  v.num("pf_quantile", o.pf_quantile, 0, 1);
  v.integer("pf_codes", o.pf_codes, 2, 4096);
  v.integer("samples_per_chip", o.samples_per_chip, 4, 256);
  v.num("chip_rate_hz", o.chip_rate_hz, 1, 1e11);
  v.num("frequency_hz", o.frequency_hz, 1e6, 1e12);
  v.num("tx_gain_dbi", o.tx_gain_dbi, -50, 60);
  v.num("rx_gain_dbi", o.rx_gain_dbi, -50, 60);
  v.num("noise_figure_db", o.noise_figure_db, 0, 40);
  v.num("noise_temperature_k", o.noise_temperature_k, 1e-3, 1e5);
  v.num("system_loss_db", o.system_loss_db, 0, 200);
  v.integer("message_bits", o.message_bits, 1, 10000000);
}
template <class V> void visit(PrlBiasOptions& o, V& v) {
  v.num("switch_time_s", o.switch_time_s, 0, 1e6);
  v.num("delta_range_m", o.delta_range_m, 1e-6, 1e4);
  v.num("delta_course_deg", o.delta_course_deg, 1e-9, 10);
  v.num("delta_glide_deg", o.delta_glide_deg, 1e-9, 10);
  v.num("tau_s", o.tau_s, 1, kInf);
  v.num("noise2s_range_m", o.noise2s_range_m, 1e-6, 1000);
  v.num("noise2s_course_deg", o.noise2s_course_deg, 1e-9, 10);
  v.num("noise2s_glide_deg", o.noise2s_glide_deg, 1e-9, 10);
  v.flag("add_nav_variance", o.add_nav_variance);
  v.num("nav_wait_s", o.nav_wait_s, 0, 60);
  v.num("max_nav_gap_s", o.max_nav_gap_s, 0.01, 60);
  v.flag("compensate_during_estimation", o.compensate_during_estimation);
}
template <class V> void visit(LoggerOptions& o, V& v) {
  v.list("table_ranges_m", o.table_ranges_m, 0, 1e6);
  v.num("table_halfwidth_m", o.table_halfwidth_m, 1, 1e5);
  v.choice("table_range_origin", o.table_range_origin, {"radar", "threshold"});
  v.num("range_bin_m", o.range_bin_m, 10, 1e5);
}

// Every section of a scenario, in file order.
template <class F> void for_each_section(Scenario& sc, F&& f) {
  f("runway", sc.runway);
  f("radar", sc.radar);
  f("trajectory", sc.trajectory);
  f("prl", sc.prl);
  f("prl_effects", sc.prl_effects);
  f("snsins", sc.snsins);
  f("datalink", sc.datalink);
  f("prl_bias", sc.prl_bias);
  f("logger", sc.logger);
  f("runner", sc.runner);
}

}  // namespace options_io
using namespace options_io;

namespace {

// The datalink section's combinations (checked whether or not the link is enabled, so a file
// that enables it later is already known to be consistent).
void check_datalink(const Scenario& sc) {
  const DatalinkOptions& d = sc.datalink;
  if (d.code_length != 127 && d.code_length != 511 && d.code_length != 1023)
    throw ConfigError("scenario key 'datalink.code_length' = " + std::to_string(d.code_length) +
                      " must be 127, 511 or 1023 (the Gold lengths with a stored preferred pair)");
  if ((d.family == "gold" || d.family == "gold-qpsk") && d.pf_codes > d.code_length + 2)
    throw ConfigError("scenario key 'datalink.pf_codes' = " + std::to_string(d.pf_codes) + " exceeds the Gold family's " +
                      std::to_string(d.code_length + 2) + " codes at datalink.code_length = " + std::to_string(d.code_length));
  const double edge = d.filter == "rc" ? (1 + d.rolloff) * d.bandwidth_chips : d.bandwidth_chips;
  if (!(edge < 0.5 * static_cast<double>(d.samples_per_chip)))
    throw ConfigError("scenario key 'datalink.samples_per_chip' = " + std::to_string(d.samples_per_chip) +
                      ": the filter's band edge " + value_text(edge) + " chip rates must lie below half of it");
  // One message's air time must end before the next message is sent.
  const double air_s = static_cast<double>(d.message_bits) * static_cast<double>(d.code_length) / d.chip_rate_hz;
  if (air_s > sc.snsins.link_period_s)
    throw ConfigError("scenario key 'datalink.message_bits': a message of " + std::to_string(d.message_bits) + " bits takes " +
                      value_text(air_s) + " s at datalink.chip_rate_hz / datalink.code_length, longer than "
                      "snsins.link_period_s = " + value_text(sc.snsins.link_period_s) + " s");
}

}  // namespace

Scenario Scenario::from_json(const nlohmann::json& doc) {
  Scenario sc;
  read_scenario(doc, "prl", sc, [](Section&) {});

  if (sc.radar.azimuth_reference_deg < 0)
    sc.radar.azimuth_reference_deg = std::fmod(sc.runway.heading_deg + 180.0, 360.0);
  const double step = sc.trajectory.step_s;
  require_multiple(sc.prl.period_s, step, "prl.period_s");
  require_multiple(sc.prl.phase_s, step, "prl.phase_s");
  require_multiple(sc.snsins.link_period_s, step, "snsins.link_period_s");
  require_multiple(sc.snsins.link_phase_s, step, "snsins.link_phase_s");
  require_multiple(sc.runner.window_s, step, "runner.window_s");
  if (sc.runner.flush_s <= sc.prl_bias.nav_wait_s + sc.snsins.latency_s)
    throw ConfigError("scenario key 'runner.flush_s' must exceed prl_bias.nav_wait_s + "
                      "snsins.latency_s so every plot is decided before the realization ends");
  if (sc.trajectory.end_x_m >= sc.trajectory.intercept_x_m)
    throw ConfigError("scenario key 'trajectory.end_x_m' must be below trajectory.intercept_x_m");
  check_datalink(sc);
  if (sc.logger.table_ranges_m.empty())
    throw ConfigError("scenario key 'logger.table_ranges_m' must list at least one range");
  return sc;
}

Scenario Scenario::load(const std::string& file, const std::vector<std::string>& overrides) {
  Scenario sc = load_scenario<Scenario>(file, overrides);
  // trajectory.replay_csv: a relative path in the file is relative to the file's directory;
  // one given by an override (--set) is relative to the working directory, like any argument.
  bool from_override = false;
  for (const auto& o : overrides)
    if (o.rfind("trajectory.replay_csv=", 0) == 0) from_override = true;
  std::string& csv = sc.trajectory.replay_csv;
  if (!csv.empty() && std::filesystem::path(csv).is_relative()) {
    const std::filesystem::path base =
        from_override ? std::filesystem::current_path() : std::filesystem::absolute(file).parent_path();
    csv = (base / csv).lexically_normal().string();
  }
  return sc;
}

LocalLevelFrame Scenario::landing_frame() const {
  return LocalLevelFrame(runway.threshold, std::fmod(runway.heading_deg + 180.0, 360.0));
}

Geodetic Scenario::radar_site() const {
  Geodetic g = landing_frame().to_geodetic(Eigen::Vector3d(radar.x_m, 0.0, radar.z_m));
  g.h_m = runway.threshold.h_m + radar.antenna_height_m;
  return g;
}

LocalLevelFrame Scenario::radar_frame() const {
  return LocalLevelFrame(radar_site(), radar.azimuth_reference_deg);
}

std::vector<std::string> Scenario::node_names() const {
  std::vector<std::string> n{"trajectory", "snsins"};
  if (datalink.enabled) n.push_back("datalink");
  for (const char* m : {"prl", "prl_bias", "logger"}) n.push_back(m);
  return n;
}

void Scenario::print(std::ostream& os) const {
  print_scenario(*this, os, [](nlohmann::json&) {});
}

}  // namespace rnav
