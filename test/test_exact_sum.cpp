// Unit tests of common/physics/exact_sum.hpp: correctly rounded sums against an exact integer
// reference, independence of order and sharding (the property MPI-sharded ensembles rely on),
// ties, inf/NaN, overflow and the exact text form.
#include "common/physics/exact_sum.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <random>
#include <stdexcept>
#include <vector>

using rnav::ExactSum;

namespace {

double sum_in_order(const std::vector<double>& v) {
  ExactSum s;
  for (double x : v) s.add(x);
  return s.value();
}

bool same_bits(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }

}  // namespace

TEST_CASE("ExactSum: the correctly rounded sum of integers spanning 50 binary orders", "[exact_sum]") {
  // Every value is an integer k * 2^e (|k| < 2^53, e in 0..50), so the exact sum fits an
  // __int128 (below 2^120 for 20000 terms) and its conversion to double is correctly rounded:
  // an independent reference. A plain left-to-right double sum misses it by many ulps.
  std::mt19937_64 g(7);
  std::uniform_int_distribution<long long> k(-(1LL << 53) + 1, (1LL << 53) - 1);
  std::uniform_int_distribution<int> e(0, 50);
  std::vector<double> v;
  __int128 exact = 0;
  for (int i = 0; i < 20000; ++i) {
    const long long ki = k(g);
    const int ei = e(g);
    v.push_back(std::ldexp(static_cast<double>(ki), ei));
    exact += static_cast<__int128>(ki) * (static_cast<__int128>(1) << ei);  // (a negative value may not be shifted)
  }
  const double ref = static_cast<double>(exact);
  CHECK(same_bits(sum_in_order(v), ref));
  double naive = 0;
  for (double x : v) naive += x;
  CHECK(naive != ref);  // the reference is not one a plain sum would also give
  // Scaled by 2^-80 (exact for doubles): the same bits scaled.
  for (double& x : v) x = std::ldexp(x, -80);
  CHECK(same_bits(sum_in_order(v), std::ldexp(ref, -80)));
}

TEST_CASE("ExactSum: any order and any sharding give the same bits", "[exact_sum]") {
  std::mt19937_64 g(11);
  std::normal_distribution<double> n(0, 1);
  std::uniform_int_distribution<int> e(-40, 40);
  std::vector<double> v;
  for (int i = 0; i < 5000; ++i) v.push_back(std::ldexp(n(g), e(g)));
  const double whole = sum_in_order(v);
  ExactSum in_order;
  for (double x : v) in_order.add(x);
  const std::string whole_text = in_order.to_text();
  CHECK(whole_text.find(' ') != std::string::npos);  // more than one partial: the text is not trivially unique
  for (int trial = 0; trial < 20; ++trial) {
    std::shuffle(v.begin(), v.end(), g);
    const int shards = 1 + trial % 7;
    std::vector<ExactSum> part(shards);
    for (std::size_t i = 0; i < v.size(); ++i) part[i % shards].add(v[i]);
    std::shuffle(part.begin(), part.end(), g);
    ExactSum merged;
    for (const auto& p : part) merged.merge(p);
    INFO("trial " << trial << ", " << shards << " shards");
    CHECK(same_bits(merged.value(), whole));
    CHECK(merged.to_text() == whole_text);  // the state file is the same bytes, too
    // Through the text form, too (what a shard's state file holds).
    ExactSum via_text;
    for (const auto& p : part) via_text.merge(ExactSum::from_text(p.to_text(), "shard"));
    CHECK(same_bits(via_text.value(), whole));
  }
}

TEST_CASE("ExactSum: half-way cases round to even unless the rest decides", "[exact_sum]") {
  const double u = std::ldexp(1.0, -53);  // half an ulp of 1
  CHECK(sum_in_order({1.0, u}) == 1.0);                                      // tie: to even
  CHECK(sum_in_order({1.0, u, std::ldexp(1.0, -100)}) == std::nextafter(1.0, 2.0));  // just above
  CHECK(sum_in_order({1.0, u, -std::ldexp(1.0, -100)}) == 1.0);              // just below
  CHECK(sum_in_order({1e100, 1.0, -1e100}) == 1.0);                          // cancellation
  CHECK(sum_in_order(std::vector<double>(10, 0.1)) == 1.0);                  // fsum's classic
  CHECK(sum_in_order({}) == 0.0);
}

TEST_CASE("ExactSum: inf and NaN propagate as in a plain sum and overflow throws", "[exact_sum]") {
  const double inf = std::numeric_limits<double>::infinity();
  CHECK(sum_in_order({1.0, inf, 2.0}) == inf);
  CHECK(std::isnan(sum_in_order({inf, 1.0, -inf})));
  ExactSum s;
  s.add(inf);
  CHECK(ExactSum::from_text(s.to_text(), "x").value() == inf);
  ExactSum big(std::numeric_limits<double>::max());
  CHECK_THROWS_AS(big.add(std::numeric_limits<double>::max()), std::overflow_error);
}

TEST_CASE("ExactSum: malformed text names its source", "[exact_sum]") {
  for (const char* bad : {"0x1p+0 zz", "0x1p+1 0x1p+0", "0x0p+0", "0x1p+0|5", "nan"}) {
    INFO(bad);
    CHECK_THROWS_WITH(ExactSum::from_text(bad, "stats_state.json by_time[3]"),
                      Catch::Contains("stats_state.json by_time[3]: not an exact sum"));
  }
  CHECK(ExactSum::from_text("", "x").value() == 0.0);
}

TEST_CASE("ExactSum: many partials (beyond the inline ones) stay exact and order-free", "[exact_sum]") {
  // 2^(-60 k), k = 0 ... 15, with alternating signs: no two fit one double, so 16 partials.
  std::vector<double> v;
  for (int k = 0; k < 16; ++k) v.push_back((k % 2 ? -1.0 : 1.0) * std::ldexp(1.0, -60 * k));
  ExactSum ref;
  for (double x : v) ref.add(x);
  const std::string text = ref.to_text();
  CHECK(std::count(text.begin(), text.end(), ' ') == 15);  // 16 partials held
  std::mt19937_64 g(3);
  for (int trial = 0; trial < 10; ++trial) {
    std::shuffle(v.begin(), v.end(), g);
    ExactSum a, b;
    for (std::size_t i = 0; i < v.size(); ++i) (i % 3 ? a : b).add(v[i]);
    b.merge(a);
    CHECK(b.to_text() == text);
    CHECK(same_bits(b.value(), ref.value()));
    // Cancelling every term leaves exactly zero.
    for (double x : v) b.add(-x);
    CHECK(b.value() == 0.0);
    CHECK(b.to_text().empty());
  }
}
