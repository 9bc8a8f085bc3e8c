#pragma once
// A trust-region Newton ascent of a smooth function of two variables in a box, its derivatives
// from finite-difference stencils evaluated in batches (the noise identification's refinement of
// (log tau, logit lambda): one batch of models costs little more than one model).
//
// Each step evaluates one batch: the trial point and the stencil around it (5 more points, a
// step of half the step's length, within [h_min, h]). The gradient g and Hessian H at the
// current point come from its stencil (central differences, one-sided at a face of the box:
// every point stays inside); the step s maximises
//   m(s) = g's + s'Hs / 2  over |s| <= Delta  (Levenberg: (mu I - H) s = g, mu >= 0),
// clipped to the box. The trial point is taken when f rose; the radius doubles after a step that
// reached it and did at least 3/4 of what m promised, and shrinks to a quarter of a step that
// did less than 1/4 or failed.

#include <Eigen/Dense>

#include <cmath>
#include <functional>
#include <vector>

namespace rnav {

/// The options of box_ascent. The coordinates are the caller's, scaled so that one unit is a
/// comparable change in either (the noise identification: one grid step).
struct BoxAscentOptions {
  double h = 0.05;              ///< largest stencil step in either coordinate, > 0 (the box must be wider than 4 h)
  double h_min = 0.005;         ///< smallest, in (0, h]: a stencil's step is half the step that reached its point, within these
  Eigen::Vector2d tol{1e-3, 1e-3};  ///< converged once a step is under this in each coordinate, > 0
  double f_tol = 0;             ///< converged once a step promises a rise under this (f's unit), >= 0
  double delta0 = 1;            ///< initial trust radius, > 0
  double delta_max = 8;         ///< largest trust radius, >= delta0
  int max_batches = 12;         ///< batches evaluated at most (the first stencil's included), >= 1
  /// For a caller that needs the maximum only where it exceeds f_out (f's unit; -inf: always):
  /// gives up once H is negative definite and f plus out_margin times the rise to the top of the
  /// quadratic model (-g'H^-1 g / 2) stays under f_out.
  double f_out = -INFINITY;
  double out_margin = 10;       ///< > 0 [-]
};

/// Where box_ascent stopped.
struct BoxAscentResult {
  Eigen::Vector2d x;       ///< the best point evaluated (x0 if none rose)
  double f = 0;            ///< f there
  int batches = 0;         ///< batches evaluated
  int evaluations = 0;     ///< points evaluated
  bool converged = false;  ///< a step under tol, or one promising under f_tol: false when max_batches ended it
  bool finite = true;      ///< false: a stencil value was not finite (derivatives undefined; x is then the last good point)
  bool out_of_reach = false;  ///< given up below f_out (BoxAscentOptions::f_out)
};

/// f's values at each of the points given (at most 6 per call), in their order.
using BatchFunction = std::function<std::vector<double>(const std::vector<Eigen::Vector2d>&)>;

/// The maximum of f in the box [lo, hi] near x0 (inside it, f(x0) = f0 finite), by the ascent
/// above. Throws std::invalid_argument on x0 outside the box, a box not wider than 4 h, a
/// non-finite f0 or invalid options.
BoxAscentResult box_ascent(const BatchFunction& f, const Eigen::Vector2d& x0, double f0, const Eigen::Vector2d& lo,
                           const Eigen::Vector2d& hi, const BoxAscentOptions& o);

}  // namespace rnav
