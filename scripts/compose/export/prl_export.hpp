// Simulate one landing-approach realization (optionally with hidden effects, prl_effects.*)
// and write it as a flight-test CSV folder: data with a known hidden effect for diagnose.
#pragma once

#include "scripts/compose/scenario/scenario.hpp"

#include <string>

namespace rnav {

/// Returns 0 on success, else the in-process clock's exit code (and `failure`).
int export_prl_flight(const Scenario& sc, std::int64_t seed, int realization,
                      const std::string& out_dir, std::string* failure = nullptr);

}  // namespace rnav
