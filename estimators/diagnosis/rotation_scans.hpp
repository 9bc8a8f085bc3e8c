// A rotating radar that stamps each detection with its own illumination time (no common scan
// time) writes nearly one detection per stamp. Read as stamped, every detection would be a scan
// of its own: one ship per scan, its gate compared with whatever single return the beam gave at
// that instant (clutter, land, another ship on its bearing). Its detections are read instead as
// scans of one rotation each. The beam turns at omega [rad/s], so between two detections within
// one rotation the bearing advances by
//   (b_j - b_i) mod 2 pi = omega (t_j - t_i)   (clockwise; counter-clockwise with -b)
// up to the bearing noise, clutter included (it is lit by the same beam). omega is estimated in
// two steps: a coarse median over consecutive detections, then the median over pairs
// 0.3 - 0.7 of a coarse period apart (an advance near pi, far from the 2 pi ambiguity, so noise
// of a degree is 0.5 % of it). The sensor rotates if at least half of those pairs agree with
// the median within 5 %; its rotation k is then the detections with
//   k = floor((t - t_first) / P),  P = 2 pi / omega.
// A cut between rotations can put a ship lit near the cut's bearing twice or not at all in one
// rotation; the association then keeps one of the two.
#pragma once

#include <vector>

namespace rnav {

struct RotationEstimate {
  double period_s = 0;            ///< [s] rotation period P; 0: the detections do not follow one rotating beam
  int direction = 0;              ///< +1 clockwise, -1 counter-clockwise, 0 not rotating
  double agreeing_fraction = 0;   ///< of the refining pairs, the fraction within 5 % of the median rate
  int pairs = 0;                  ///< refining pairs
};

/// t_s non-decreasing [s], bearing_rad [rad] of each detection (empty scans left out); needs at
/// least kMinRotationDetections detections, else period 0.
RotationEstimate rotation_period(const std::vector<double>& t_s, const std::vector<double>& bearing_rad);

constexpr int kMinRotationDetections = 30;  ///< fewer detections: not judged (period 0)

}  // namespace rnav
