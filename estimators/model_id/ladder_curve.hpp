// The injection ladder (injected_limits.hpp's measure_ladder) on a known hit curve instead of
// whole searches: how many injections it spends and how close the sizes it states come to the
// curve's own 90 % points. The ladder alone, in milliseconds, so its rules can be measured over
// thousands of ladders (rnav_ladder_study, and the tests) before a diagnosis runs them.
#pragma once

#include "estimators/model_id/injected_limits.hpp"

#include <cstdint>

namespace rnav {

/// A probit hit curve in log a: P(named | a) = Phi(slope log(a / a_named) + z_power), and
/// likewise detected with a_detected; a_* are where the rate is `power` [parameter unit, the
/// Fisher limit the ladder starts from being 1]. Both from one uniform draw per injection, so a
/// named injection is detected whenever a_detected <= a_named (as in a search: named implies
/// detected).
struct HitCurve {
  double slope = 4.8;       ///< [-] probit slope in log a, > 0 (4.8: a test with P = Phi(a / SE - z_crit) at 90 %)
  double a_named = 1;       ///< [Fisher limits] size named at rate `power`, > 0
  double a_detected = 1;    ///< [Fisher limits] size detected at rate `power`, > 0, <= a_named
};

/// One ladder's outcome on a curve: the true rates at the sizes it stated, and its cost.
struct LadderOutcome {
  double named_rate = 0;     ///< the curve's named rate at the stated named size (0 when none was stated)
  double detected_rate = 0;  ///< the curve's detected rate at the stated detected size (0 when none)
  int injections = 0;        ///< injections drawn: every rung and every check batch (with io.threads > 1, also
                             ///< those a settled batch's round drew and left unread)
};

/// The ladder of io (its Fisher limit 1) on curve k at rate `power`, injection i of batch b drawn
/// from a stream of (seed, b, i) alone. Throws std::invalid_argument on a bad curve or options.
LadderOutcome ladder_on_curve(const HitCurve& k, double power, const InjectionOptions& io, std::uint64_t seed);

}  // namespace rnav
