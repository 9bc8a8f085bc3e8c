#include "common/physics/exact_sum.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <stdexcept>

namespace rnav {

void ExactSum::add(double x) {
  if (!std::isfinite(x)) {
    nonfinite_ += x;
    return;
  }
  // Two-sum of x with each partial in increasing magnitude: hi + lo = x + y exactly
  // (Knuth's branch-free TwoSum: hi = fl(x + y), b = hi - x, lo = (x - (hi - b)) + (y - b));
  // the non-zero lo's stay, hi moves on.
  double* p = data();
  int i = 0;
  for (int j = 0; j < size_; ++j) {
    const double y = p[j];
    const double hi = x + y;
    const double b = hi - x;
    const double lo = (x - (hi - b)) + (y - b);
    if (lo != 0) p[i++] = lo;
    x = hi;
  }
  if (!std::isfinite(x)) throw std::overflow_error("ExactSum: the sum exceeds the double range");
  size_ = i;
  if (x != 0) push(x);
}

void ExactSum::push(double x) {
  if (heap_.empty() && size_ < kInline) {
    inline_[size_++] = x;
    return;
  }
  if (heap_.empty()) heap_.assign(inline_, inline_ + size_);
  heap_.resize(static_cast<std::size_t>(size_));
  heap_.push_back(x);
  ++size_;
}

void ExactSum::merge(const ExactSum& o) {
  const double* p = o.data();
  for (int j = 0; j < o.size_; ++j) add(p[j]);
  if (o.nonfinite_ != 0 || std::isnan(o.nonfinite_)) nonfinite_ += o.nonfinite_;
}

double ExactSum::value() const {
  if (nonfinite_ != 0 || std::isnan(nonfinite_)) return nonfinite_;
  // From the largest partial down, until a rounding error appears; then round half-way cases
  // by the sign of the rest (the partials below), as math.fsum does.
  const double* p = data();
  int n = size_;
  if (n == 0) return 0.0;
  double hi = p[--n], lo = 0;
  while (n > 0) {
    const double x = hi, y = p[--n];
    hi = x + y;
    const double yr = hi - x;
    lo = y - yr;
    if (lo != 0) break;
  }
  if (n > 0 && ((lo < 0 && p[n - 1] < 0) || (lo > 0 && p[n - 1] > 0))) {
    const double y = lo * 2, x = hi + y;
    if (y == x - hi) hi = x;
  }
  return hi;
}

std::string ExactSum::to_text() const {
  // Canonical: the greedy expansion of the exact sum S (v1 = round(S), v2 = round(S - v1), ...),
  // which depends on S alone - not on the order the terms came in.
  std::vector<double> canon;
  ExactSum rest = *this;
  rest.nonfinite_ = 0;
  while (rest.size_ > 0) {
    const double v = rest.value();
    canon.push_back(v);
    rest.add(-v);
  }
  std::string s;
  char b[40];
  for (auto it = canon.rbegin(); it != canon.rend(); ++it) {
    const double p = *it;
    std::snprintf(b, sizeof b, "%a", p);
    if (!s.empty()) s += ' ';
    s += b;
  }
  if (nonfinite_ != 0 || std::isnan(nonfinite_)) {
    std::snprintf(b, sizeof b, "|%g", nonfinite_);
    s += b;
  }
  return s;
}

ExactSum ExactSum::from_text(const std::string& text, const std::string& what) {
  const auto bad = [&](const std::string& why) {
    return std::invalid_argument(what + ": not an exact sum (" + why + "): '" + text.substr(0, 80) + "'");
  };
  ExactSum e;
  std::string body = text;
  const auto bar = text.find('|');
  if (bar != std::string::npos) {
    body = text.substr(0, bar);
    const std::string nf = text.substr(bar + 1);
    char* end = nullptr;
    e.nonfinite_ = std::strtod(nf.c_str(), &end);
    if (nf.empty() || *end != '\0' || std::isfinite(e.nonfinite_)) throw bad("the part after '|' must be inf, -inf or nan");
  }
  const char* p = body.c_str();
  while (*p) {
    if (*p == ' ') {
      ++p;
      continue;
    }
    char* end = nullptr;
    const double x = std::strtod(p, &end);
    if (end == p || (*end != ' ' && *end != '\0') || !std::isfinite(x) || x == 0) throw bad("a partial is not a finite non-zero number");
    if (e.size_ > 0) {
      // Partials are held in increasing magnitude.
      if (std::abs(x) <= std::abs(e.data()[e.size_ - 1])) throw bad("partials out of order");
    }
    e.push(x);
    p = end;
  }
  return e;
}

}  // namespace rnav
