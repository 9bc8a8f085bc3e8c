// Sim time in integer microseconds: every node puts its samples on the same grid.
#pragma once

#include <cmath>
#include <cstdint>

namespace rnav {

/// Seconds -> integer microseconds (rounded).
inline std::int64_t to_us(double t_s) { return std::llround(t_s * 1e6); }

}  // namespace rnav
