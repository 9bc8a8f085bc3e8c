// Geodetic frames for the landing radar: WGS84 (via GeographicLib), local-level frames
// rotated to a bearing (landing frame L at the threshold, radar frame R at the radar),
// and the radar's polar coordinates.
//
// Local-level frame F with origin O and x-axis bearing beta (deg, clockwise from true north):
//   x_F = horizontal unit vector at bearing beta,   in ENU: ( sin b, cos b, 0)
//   y_F = up (WGS84 ellipsoid normal at O),         in ENU: ( 0,     0,     1)
//   z_F = x_F cross y_F (bearing beta + 90 deg),    in ENU: ( cos b, -sin b, 0)
// F is the tangent plane at O: a point's y_F is NOT its height above O's ellipsoid height
// (at 30 km the two differ by about 70 m, the Earth's curvature).
#pragma once

#include <Eigen/Dense>
#include <GeographicLib/LocalCartesian.hpp>

#include <vector>

namespace rnav {

/// WGS84 geodetic position.
struct Geodetic {
  double lat_deg = 0;  ///< latitude [deg], north positive, [-90, 90]
  double lon_deg = 0;  ///< longitude [deg], east positive
  double h_m = 0;      ///< height above the WGS84 ellipsoid [m]
};

/// A geodetic position with its time of validity.
struct GeoSample {
  double t_s = 0;  ///< time of validity [s] (the data set's time scale, e.g. Unix seconds UTC)
  Geodetic g;      ///< geodetic (WGS84) position at t_s
};

/// Radar polar coordinates in a local-level frame R.
struct Polar {
  double range_m = 0;     ///< slant range D [m], >= 0
  double course_rad = 0;  ///< course angle Ek = atan2(z, x) [rad], clockwise positive, (-pi, pi]
  double glide_rad = 0;   ///< glide angle Eg = atan2(y, hypot(x, z)) [rad], [-pi/2, pi/2]
};

/// A local-level Cartesian frame on WGS84 (see the file comment for its axes).
class LocalLevelFrame {
 public:
  /// @param origin       origin O on WGS84
  /// @param bearing_deg  true bearing of the x-axis [deg], clockwise from north, any finite value
  LocalLevelFrame(const Geodetic& origin, double bearing_deg);

  /// p_OP_F: position of geodetic point P from the origin, in F [m].
  Eigen::Vector3d from_geodetic(const Geodetic& p) const;
  /// Geodetic point at p_OP_F.
  Geodetic to_geodetic(const Eigen::Vector3d& p_OP_F) const;
  /// Rotate a velocity given in the north-east-down frame at geodetic point P into F.
  Eigen::Vector3d from_ned(const Geodetic& at, const Eigen::Vector3d& v_N) const;
  /// Rotate a velocity given in F into the north-east-down frame at geodetic point P.
  Eigen::Vector3d to_ned(const Geodetic& at, const Eigen::Vector3d& v_F) const;

  const Geodetic& origin() const { return origin_; }
  double bearing_deg() const { return bearing_deg_; }
  /// Position of the origin in ECEF [m].
  const Eigen::Vector3d& origin_ecef() const { return o_ecef_; }
  /// R_F_ECEF: rotation taking ECEF vectors into F.
  const Eigen::Matrix3d& R_F_ECEF() const { return R_F_ECEF_; }

 private:
  Geodetic origin_;
  double bearing_deg_;
  GeographicLib::LocalCartesian lc_;  // ENU at the origin
  Eigen::Matrix3d R_F_ENU_;
  Eigen::Matrix3d R_F_ECEF_;
  Eigen::Vector3d o_ecef_;
};

/// The rigid transform taking coordinates in frame `from` into frame `to` (both local-level
/// frames are rigid transforms of ECEF, so this is exact):
///   p_To = R_To_ECEF (o_From + R_ECEF_From p_From - o_To)
Eigen::Isometry3d transform(const LocalLevelFrame& to, const LocalLevelFrame& from);

/// R_ECEF_NED at a geodetic point: rotation taking NED vectors at P into ECEF.
Eigen::Matrix3d R_ECEF_NED(const Geodetic& at);

/// Polar coordinates of p_RA_R (position of A from the radar, in R).
/// D = |p|; Ek = atan2(z, x); Eg = atan2(y, hypot(x, z)).
Polar polar_from_cartesian(const Eigen::Vector3d& p_RA_R);
/// Inverse of polar_from_cartesian:
/// x = D cos Eg cos Ek; y = D sin Eg; z = D cos Eg sin Ek.
Eigen::Vector3d cartesian_from_polar(const Polar& q);
/// Jacobian d(D, Ek, Eg)/d(x, y, z) of polar_from_cartesian at p_RA_R (p off the y-axis).
Eigen::Matrix3d polar_jacobian(const Eigen::Vector3d& p_RA_R);

/// Angle wrapped into (-pi, pi].
double wrap_pi(double a);
/// Of several angles [rad], the wrapped difference wrap_pi(a - ref) of the one nearest ref (the
/// first of equals); +inf for none (a frame without detections).
double nearest_wrapped(const std::vector<double>& angles_rad, double ref_rad);

constexpr double kDegToRad = 0.017453292519943295;

}  // namespace rnav
