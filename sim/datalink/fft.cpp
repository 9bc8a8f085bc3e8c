#include "sim/datalink/fft.hpp"

#include <stdexcept>
#include <unsupported/Eigen/FFT>

namespace rnav::datalink {

namespace {

Eigen::FFT<double>& engine() {
  thread_local Eigen::FFT<double> f;  // default flags: inv() scales by 1/L
  return f;
}

}  // namespace

Signal dft(const Signal& x) {
  if (x.empty()) throw std::invalid_argument("x: empty sequence");
  Signal X;
  engine().fwd(X, x);
  return X;
}

Signal idft(const Signal& X) {
  if (X.empty()) throw std::invalid_argument("X: empty sequence");
  Signal x;
  engine().inv(x, X);
  return x;
}

}  // namespace rnav::datalink
