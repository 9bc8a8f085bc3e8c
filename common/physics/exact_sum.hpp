// ExactSum: the sum of doubles, held exactly and rounded once (Shewchuk's non-overlapping
// expansions, "Adaptive Precision Floating-Point Arithmetic", 1997; the final rounding as in
// Python's math.fsum). Because the held sum is exact, value() - the correctly rounded (to
// nearest, ties to even) exact sum - does not depend on the order of add() and merge() calls:
// an ensemble split into shards, each summed on its own and merged in any order, gives the
// same bits as one process summing every realization in turn.
//
// Inputs: any doubles. +-inf and NaN are kept apart (value() is then inf or NaN, as a plain sum
// would be); a finite sum whose magnitude exceeds DBL_MAX throws std::overflow_error.
// Cost: add() is O(k) for k held partials; k stays small (1 to 3) for values of similar
// magnitude, which are held inline (no allocation up to kInline partials).
#pragma once

#include <string>
#include <vector>

namespace rnav {

class ExactSum {
 public:
  ExactSum() = default;
  explicit ExactSum(double x) { add(x); }
  /// Add x exactly.
  void add(double x);
  /// Add every term of another sum exactly (the result is that of adding its inputs here).
  void merge(const ExactSum& o);
  /// The exact sum rounded to the nearest double (ties to even).
  double value() const;
  ExactSum& operator+=(double x) {
    add(x);
    return *this;
  }

  /// The held sum, exactly, as text: its canonical expansion (v1 = round(S), v2 = round(S - v1),
  /// ...; the same text for the same exact sum S, whatever the order of the terms) as C99 hex
  /// floats in increasing magnitude separated by ' ', then (if any input was inf or NaN) '|' and
  /// their plain sum. "" is the empty sum.
  std::string to_text() const;
  /// Inverse of to_text(); throws std::invalid_argument naming `what` on malformed text
  /// (an unreadable number, partials not in increasing magnitude).
  static ExactSum from_text(const std::string& text, const std::string& what);

 private:
  static constexpr int kInline = 6;
  const double* data() const { return heap_.empty() ? inline_ : heap_.data(); }
  double* data() { return heap_.empty() ? inline_ : heap_.data(); }
  void push(double x);
  // The partials: non-overlapping, increasing magnitude, non-zero; size_ of them, in inline_
  // until more than kInline are needed, then in heap_ (which stays in use from then on).
  double inline_[kInline] = {};
  std::vector<double> heap_;
  int size_ = 0;
  double nonfinite_ = 0;  // plain sum of the inf/NaN inputs (0: none)
};

}  // namespace rnav
