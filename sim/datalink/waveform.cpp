#include "sim/datalink/waveform.hpp"

#include "sim/datalink/fft.hpp"

#include <cmath>
#include <cstdlib>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace rnav::datalink {

namespace {

constexpr double kMaxBandwidth = 1000.0;

std::string number_text(double x) {
  std::ostringstream o;
  o.precision(15);
  o << x;
  return o.str();
}

void check_bandwidth(double b) {
  if (!std::isfinite(b) || b <= 0 || b > kMaxBandwidth) {
    throw std::invalid_argument("bandwidth: " + number_text(b) + " chip rates is outside (0, " + number_text(kMaxBandwidth) + "]");
  }
}

double parse_number(const std::string& text, const std::string& what, const std::string& whole) {
  char* end = nullptr;
  const double x = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || !std::isfinite(x))
    throw std::invalid_argument("filter: '" + whole + "': " + what + " '" + text + "' is not a number");
  return x;
}

}  // namespace

Filter Filter::none() { return Filter(Kind::none, std::numeric_limits<double>::infinity(), 0.0); }

Filter Filter::brick_wall(double bandwidth) {
  check_bandwidth(bandwidth);
  return Filter(Kind::brick_wall, bandwidth, 0.0);
}

Filter Filter::raised_cosine(double bandwidth, double rolloff) {
  check_bandwidth(bandwidth);
  if (!std::isfinite(rolloff) || rolloff <= 0 || rolloff > 1)
    throw std::invalid_argument("rolloff: " + number_text(rolloff) + " is outside (0, 1] (use a brick wall for 0)");
  return Filter(Kind::raised_cosine, bandwidth, rolloff);
}

Filter Filter::parse(const std::string& text) {
  if (text == "none") return none();
  std::vector<std::string> part;
  std::stringstream ss(text);
  for (std::string p; std::getline(ss, p, ':');) part.push_back(p);
  if (part.size() == 2 && part[0] == "brick") return brick_wall(parse_number(part[1], "bandwidth", text));
  if (part.size() == 3 && part[0] == "rc")
    return raised_cosine(parse_number(part[1], "bandwidth", text), parse_number(part[2], "rolloff", text));
  throw std::invalid_argument("filter: '" + text + "' is not none, brick:B or rc:B:BETA");
}

double Filter::bandwidth() const { return bandwidth_; }

double Filter::band_edge() const {
  switch (kind_) {
    case Kind::none: return std::numeric_limits<double>::infinity();
    case Kind::brick_wall: return bandwidth_;
    case Kind::raised_cosine: return (1 + rolloff_) * bandwidth_;
  }
  return 0;
}

double Filter::response(double f) const {
  const double a = std::abs(f);
  switch (kind_) {
    case Kind::none: return 1.0;
    case Kind::brick_wall: return a <= bandwidth_ ? 1.0 : 0.0;
    case Kind::raised_cosine: {
      const double lo = (1 - rolloff_) * bandwidth_, hi = (1 + rolloff_) * bandwidth_;
      if (a <= lo) return 1.0;
      if (a > hi) return 0.0;
      // H = 1/2 [1 + cos(pi (|f| - (1-beta) B) / (2 beta B))]
      return 0.5 * (1 + std::cos(M_PI * (a - lo) / (2 * rolloff_ * bandwidth_)));
    }
  }
  return 0;
}

std::string Filter::name() const {
  switch (kind_) {
    case Kind::none: return "none";
    case Kind::brick_wall: return "brick:" + number_text(bandwidth_);
    case Kind::raised_cosine: return "rc:" + number_text(bandwidth_) + ":" + number_text(rolloff_);
  }
  return "";
}

Signal bpsk_waveform(const Signal& chips, int samples_per_chip, const Filter& filter) {
  if (chips.empty()) throw std::invalid_argument("chips: empty code");
  if (samples_per_chip < 1 || samples_per_chip > 4096)
    throw std::invalid_argument("samples_per_chip: " + std::to_string(samples_per_chip) + " outside [1, 4096]");
  const std::size_t N = chips.size(), S = static_cast<std::size_t>(samples_per_chip), L = N * S;
  if (filter.kind() == Filter::Kind::none) {
    // s_j = c_{floor(j / S)}
    Signal s(L);
    for (std::size_t j = 0; j < L; ++j) s[j] = chips[j / S];
    return s;
  }
  if (!(filter.band_edge() < 0.5 * static_cast<double>(S)))
    throw std::invalid_argument("samples_per_chip: " + std::to_string(S) + " is too few for filter " + filter.name() +
                                " (its band edge " + number_text(filter.band_edge()) + " chip rates must be below S/2)");
  const Signal C = dft(chips);
  // b_m = H(m/N) a_m,  a_m = (1/N) C_{m mod N} e^{-i pi m/N} sinc(m/N), placed at DFT bin m mod L.
  Signal b(L, 0.0);
  const long half = static_cast<long>(L / 2);
  for (std::size_t q = 0; q < L; ++q) {
    const long m = static_cast<long>(q) <= half ? static_cast<long>(q) : static_cast<long>(q) - static_cast<long>(L);
    const double f = static_cast<double>(m) / static_cast<double>(N);
    const double h = filter.response(f);
    if (h == 0) continue;
    const double sinc = m == 0 ? 1.0 : std::sin(M_PI * f) / (M_PI * f);
    const long qm = ((m % static_cast<long>(N)) + static_cast<long>(N)) % static_cast<long>(N);
    b[q] = h * sinc * std::polar(1.0, -M_PI * f) * C[static_cast<std::size_t>(qm)] / static_cast<double>(N);
  }
  // y_j = sum_m b_m e^{2 pi i m j / L} = L * IDFT(b)_j
  Signal y = idft(b);
  for (auto& v : y) v *= static_cast<double>(L);
  return y;
}

Signal apply_filter(const Signal& x, int samples_per_chip, const Filter& filter) {
  if (x.empty()) throw std::invalid_argument("x: empty signal");
  if (samples_per_chip < 1) throw std::invalid_argument("samples_per_chip: " + std::to_string(samples_per_chip) + " < 1");
  if (filter.kind() == Filter::Kind::none) return x;
  const std::size_t L = x.size();
  Signal X = dft(x);
  for (std::size_t q = 0; q < L; ++q) {
    // f_q = m_q S / L chip rates, m_q the signed harmonic
    const double m = 2 * q <= L ? static_cast<double>(q) : static_cast<double>(q) - static_cast<double>(L);
    X[q] *= filter.response(m * samples_per_chip / static_cast<double>(L));
  }
  return idft(X);
}

}  // namespace rnav::datalink
