#include "common/node/site_context.hpp"

#include <cmath>

namespace rnav {

void resolve_azimuth_reference(const RunwayOptions& runway, RadarSiteOptions& radar) {
  if (radar.azimuth_reference_deg < 0) radar.azimuth_reference_deg = std::fmod(runway.heading_deg + 180.0, 360.0);
}

LocalLevelFrame SiteContext::landing_frame() const {
  return LocalLevelFrame(runway.threshold, std::fmod(runway.heading_deg + 180.0, 360.0));
}

Geodetic SiteContext::radar_site() const {
  Geodetic g = landing_frame().to_geodetic(Eigen::Vector3d(radar.x_m, 0.0, radar.z_m));
  g.h_m = runway.threshold.h_m + radar.antenna_height_m;
  return g;
}

LocalLevelFrame SiteContext::radar_frame() const {
  return LocalLevelFrame(radar_site(), radar.azimuth_reference_deg);
}

SiteContext read_site_context(const nlohmann::json& doc) {
  Section root(doc, "");
  SiteContext c;
  options_io::read_section(root, "runway", c.runway);
  options_io::read_section(root, "radar", c.radar);
  options_io::read_section(root, "runner", c.runner);
  root.finish_nested();  // the other sections belong to other readers
  resolve_azimuth_reference(c.runway, c.radar);
  return c;
}

RunnerOptions read_runner_options(const nlohmann::json& doc) {
  Section root(doc, "");
  RunnerOptions r;
  options_io::read_section(root, "runner", r);
  root.finish_nested();
  return r;
}

}  // namespace rnav
