// The discrete Fourier transform pair of the codes library (Eigen's unsupported FFT, kissfft
// back end: any length, mixed radix), with the sign and scaling conventions written down once:
//   dft:   X_m = sum_{j=0}^{L-1} x_j e^{-2 pi i m j / L}
//   idft:  x_j = (1/L) sum_{m=0}^{L-1} X_m e^{+2 pi i m j / L}
// Plans are cached per thread (one Eigen::FFT object per thread), so repeated lengths are cheap.
#pragma once

#include "sim/datalink/signal.hpp"

namespace rnav::datalink {

/// X = DFT(x); x must not be empty (throws std::invalid_argument naming "x").
Signal dft(const Signal& x);
/// x = IDFT(X), including the 1/L; X must not be empty (throws naming "X").
Signal idft(const Signal& X);

}  // namespace rnav::datalink
