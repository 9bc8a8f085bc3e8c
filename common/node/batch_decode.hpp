// Decoding a batch message from untrusted bytes (the network, an LCM log). LCM's generated
// decode() sizes the batch's array from its count field before it checks that the bytes hold
// that many elements, so a corrupt count of 2^31 asks for tens of gigabytes. Every batch type
// (lcmtypes/*_batch_t.lcm) starts with `batch_header_t header; int32_t n;`: the count is checked
// against the message's size first (an element takes at least one byte).
#pragma once

#include <rnav/batch_header_t.hpp>

#include <cstdint>

namespace rnav {

/// [bytes] Offset of a batch's count `n`: the 8-byte type fingerprint, then batch_header_t as
/// nested (no fingerprint of its own), its size taken from the generated type.
inline int batch_count_offset() {
  static const int offset = 8 + batch_header_t()._getEncodedSizeNoHash();
  return offset;
}

/// Decode batch type B from `size` bytes; false if the count is negative or larger than the
/// message could hold, or if B::decode does not consume exactly `size` bytes.
template <class B> bool decode_batch(const void* data, int size, B& out) {
  const int at = batch_count_offset();
  if (size < at + 4) return false;
  const auto* p = static_cast<const std::uint8_t*>(data) + at;
  const std::int32_t n = static_cast<std::int32_t>((std::uint32_t{p[0]} << 24) | (std::uint32_t{p[1]} << 16) |
                                                   (std::uint32_t{p[2]} << 8) | std::uint32_t{p[3]});
  if (n < 0 || n > size) return false;
  return out.decode(data, 0, size) == size;
}

}  // namespace rnav
