#include "sim/datalink/code_metrics.hpp"

#include "sim/datalink/fft.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace rnav::datalink {

double peak_factor(const Signal& s) {
  if (s.empty()) throw std::invalid_argument("s: empty signal");
  // PF = max |s_j| / sqrt(mean |s_j|^2)
  double peak = 0, power = 0;
  for (const auto& x : s) {
    peak = std::max(peak, std::abs(x));
    power += std::norm(x);
  }
  if (!(power > 0)) throw std::invalid_argument("s: all-zero signal has no peak factor");
  return peak / std::sqrt(power / static_cast<double>(s.size()));
}

std::vector<long> periodic_correlation_exact(const std::vector<int>& a, const std::vector<int>& b) {
  if (a.empty()) throw std::invalid_argument("a: empty sequence");
  if (b.size() != a.size())
    throw std::invalid_argument("b: length " + std::to_string(b.size()) + " differs from a's " + std::to_string(a.size()));
  const std::size_t N = a.size();
  // R_ab(tau) = sum_i a_i b_{(i+tau) mod N}
  std::vector<long> r(N, 0);
  for (std::size_t tau = 0; tau < N; ++tau) {
    long sum = 0;
    for (std::size_t i = 0; i < N; ++i) sum += static_cast<long>(a[i]) * b[(i + tau) % N];
    r[tau] = sum;
  }
  return r;
}

namespace {

void check_pair(const Signal& a, const Signal& b) {
  if (a.empty()) throw std::invalid_argument("a: empty sequence");
  if (b.size() != a.size())
    throw std::invalid_argument("b: length " + std::to_string(b.size()) + " differs from a's " + std::to_string(a.size()));
}

// conj(R_ab) = IDFT(conj(A) B), from the DFTs A, B of a, b.
Signal correlation_from_spectra(const Signal& A, const Signal& B) {
  Signal X(A.size());
  for (std::size_t m = 0; m < A.size(); ++m) X[m] = std::conj(A[m]) * B[m];
  Signal r = idft(X);
  for (auto& x : r) x = std::conj(x);
  return r;
}

}  // namespace

Signal periodic_correlation(const Signal& a, const Signal& b) {
  check_pair(a, b);
  return correlation_from_spectra(dft(a), dft(b));
}

std::vector<double> power_spectrum(const Signal& s) {
  if (s.empty()) throw std::invalid_argument("s: empty signal");
  // P_m = |S_m|^2 / L^2
  const Signal S = dft(s);
  const double L2 = static_cast<double>(s.size()) * static_cast<double>(s.size());
  std::vector<double> p(S.size());
  for (std::size_t m = 0; m < S.size(); ++m) p[m] = std::norm(S[m]) / L2;
  return p;
}

CorrelationBank::CorrelationBank(const std::vector<Signal>& codes) {
  if (codes.empty()) throw std::invalid_argument("codes: no code given");
  const std::size_t N = codes.front().size();
  if (N < 2) throw std::invalid_argument("codes: length " + std::to_string(N) + " < 2");
  for (std::size_t i = 0; i < codes.size(); ++i) {
    if (codes[i].size() != N)
      throw std::invalid_argument("codes: code " + std::to_string(i) + " has length " + std::to_string(codes[i].size()) +
                                  ", code 0 has " + std::to_string(N));
    spectra_.push_back(dft(codes[i]));
  }
}

Signal CorrelationBank::correlation(int i, int j) const {
  return correlation_from_spectra(spectra_.at(static_cast<std::size_t>(i)), spectra_.at(static_cast<std::size_t>(j)));
}

double CorrelationBank::max_offpeak_auto(int i) const {
  if (i < 0 || i >= size()) throw std::invalid_argument("i: code " + std::to_string(i) + " outside [0, " + std::to_string(size()) + ")");
  const Signal r = correlation(i, i);
  double m = 0;
  for (std::size_t tau = 1; tau < r.size(); ++tau) m = std::max(m, std::abs(r[tau]));
  return m;
}

double CorrelationBank::max_cross(int i, int j) const {
  if (i < 0 || i >= size()) throw std::invalid_argument("i: code " + std::to_string(i) + " outside [0, " + std::to_string(size()) + ")");
  if (j < 0 || j >= size() || j == i)
    throw std::invalid_argument("j: code " + std::to_string(j) + " is out of range or equal to i = " + std::to_string(i));
  const Signal r = correlation(i, j);
  double m = 0;
  for (const auto& x : r) m = std::max(m, std::abs(x));
  return m;
}

}  // namespace rnav::datalink
