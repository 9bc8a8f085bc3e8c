// The landing site, shared by every process of the landing scenario: the runway (origin and
// orientation of the landing frame L) and the radar (PRL) site (origin of the radar frame R).
#pragma once

#include "common/physics/frames.hpp"
#include "common/io/options_io.hpp"

namespace rnav {

/// Runway: origin and orientation of the landing frame L.
struct RunwayOptions {
  /// Threshold on WGS84. Default: Vienna (LOWW) runway 29 threshold, approximate public
  /// coordinates (not from the AIP); the airfield of our real ADS-B approaches.
  Geodetic threshold{48.10153, 16.58495, 228.0};
  double heading_deg = 295.9;  ///< landing true heading [deg], [0, 360)
};

/// Radar (PRL) site and azimuth reference. Site given in L, surveyed (known to the estimator).
struct RadarSiteOptions {
  double x_m = -900.0;  ///< [m] along the runway axis from the threshold (negative: beside the runway), [-5000, 5000]
  double z_m = 180.0;   ///< [m] lateral offset from the centreline in L, [-3000, 3000]
  double antenna_height_m = 4.0;  ///< [m] antenna above the threshold's ellipsoidal height, [0, 100]
  /// [deg] true bearing of the radar's x-axis (course angle 0); default: the runway axis
  /// pointing away from the runway (landing heading + 180). [0, 360)
  double azimuth_reference_deg = -1;  // -1 = default, resolved by resolve_azimuth_reference
};

/// Sets radar.azimuth_reference_deg's default (-1): the landing heading + 180, in [0, 360).
void resolve_azimuth_reference(const RunwayOptions& runway, RadarSiteOptions& radar);

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

}  // namespace options_io
}  // namespace rnav
