// Two independent 64-bit hashes of a byte string, for memo keys of pure functions' inputs: a
// false match of two different inputs has probability about 2^-128.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <utility>

namespace rnav {

/// Two mixes of the 8-byte words: FNV-1a's xor-multiply, and a multiply-rotate-multiply (different
/// constants and structure, so one's collisions are not the other's). Feed bytes and values;
/// key() is the pair.
struct ByteHash {
  std::uint64_t a = 14695981039346656037ull, b = 0x9e3779b97f4a7c15ull;
  void bytes(const void* p, std::size_t n) {
    const auto* s = static_cast<const unsigned char*>(p);
    std::size_t i = 0;
    for (; i + 8 <= n; i += 8) {
      std::uint64_t w;
      std::memcpy(&w, s + i, 8);
      word(w);
    }
    std::uint64_t tail = 0;
    std::memcpy(&tail, s + i, n - i);
    word(tail ^ (static_cast<std::uint64_t>(n) << 56));
  }
  void word(std::uint64_t w) {
    a = (a ^ w) * 1099511628211ull;
    a ^= a >> 29;
    b ^= w * 0xc2b2ae3d27d4eb4full;
    b = ((b << 31) | (b >> 33)) * 0x165667b19e3779f9ull;
  }
  template <class T>
  void value(const T& v) {
    bytes(&v, sizeof v);
  }
  std::pair<std::uint64_t, std::uint64_t> key() const { return {a, b}; }
};

}  // namespace rnav
