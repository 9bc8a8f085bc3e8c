// Optimal one-to-one assignment of targets to detections within one scan: each target takes at
// most one detection and each detection goes to at most one target, minimising
//   sum over assigned pairs of cost(t, d)  +  sum over unassigned targets of miss(t),
// where cost = +inf forbids a pair (a detection outside the target's gate). Solved per connected
// component of the allowed pairs (in a scan most components are one target and one detection),
// each by the shortest-augmenting-path Hungarian method with potentials, O(n^3) in the
// component's size. (dlib's max_cost_assignment, the Debian-packaged alternative, takes integer
// costs and a square matrix only.)
#pragma once

#include <Eigen/Dense>

#include <vector>

namespace rnav {

/// cost: targets x detections [any unit], +inf where a pair is not allowed, else finite >= 0;
/// miss: per target the cost of leaving it unassigned, finite >= 0. Returns per target the
/// assigned detection's column, or -1. Ties go to the lower index (deterministic). Throws
/// std::invalid_argument for a negative or NaN cost or a miss that is not finite and >= 0.
std::vector<long> assign_min_cost(const Eigen::MatrixXd& cost, const std::vector<double>& miss);

}  // namespace rnav
