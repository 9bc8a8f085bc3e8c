// The one signal type of the codes library: a periodic complex sequence (chips, or samples of a
// waveform), one period held. Binary (BPSK) chips are +1/-1 with zero imaginary part.
#pragma once

#include <complex>
#include <vector>

namespace rnav::datalink {

using Signal = std::vector<std::complex<double>>;

/// Integer chips (e.g. GoldFamily::chips) as a Signal.
inline Signal to_signal(const std::vector<int>& chips) {
  Signal s(chips.size());
  for (std::size_t i = 0; i < chips.size(); ++i) s[i] = static_cast<double>(chips[i]);
  return s;
}

}  // namespace rnav::datalink
