// Values of a pure function kept under their inputs' 128-bit key (ByteHash), those not used
// lately dropped once the values kept exceed a budget in bytes. One thread's store: not locked.
#pragma once

#include <cstddef>
#include <cstdint>
#include <unordered_map>
#include <utility>

namespace rnav {

/// Two generations (a least-recently-used order approximated at the cost of one hash lookup;
/// not an exact LRU: a whole generation goes at once):
/// values go into the young one; a value found in the old one moves to the young one; once the
/// young one holds half the budget, it becomes the old one and the old one's values go. A value
/// used since the last such turn is kept; one unused for two turns is gone. (An exact order, a
/// list spliced on every use, cost three more cache misses per lookup, a tenth of a diagnosis
/// whose Gram entries are looked up millions of times.)
template <class V>
class GenerationStore {
 public:
  using Key = std::pair<std::uint64_t, std::uint64_t>;

  /// budget_bytes: the bytes the values may hold before the oldest go, > 0.
  explicit GenerationStore(std::size_t budget_bytes) : half_(budget_bytes / 2) {}

  /// The value kept under key; nullptr when none is. Valid until the next insert or find.
  V* find(const Key& key) {
    auto it = young_.find(key);
    if (it != young_.end()) return &it->second.value;
    auto old = old_.find(key);
    if (old == old_.end()) return nullptr;
    Kept k = std::move(old->second);
    old_.erase(old);
    old_bytes_ -= k.bytes;
    return &add(key, std::move(k));
  }

  /// Keeps v (holding `bytes`) under key; a key kept already keeps its value (a pure function's:
  /// the same). The reference is valid until the next insert or find.
  V& insert(const Key& key, V v, std::size_t bytes) {
    if (V* kept = find(key)) return *kept;
    return add(key, Kept{std::move(v), bytes});
  }

  std::size_t bytes() const { return young_bytes_ + old_bytes_; }  ///< what the values kept hold [B]
  std::size_t size() const { return young_.size() + old_.size(); }

 private:
  struct Kept {
    V value;
    std::size_t bytes;
  };
  struct KeyHash {
    std::size_t operator()(const Key& k) const { return static_cast<std::size_t>(k.first ^ k.second); }
  };
  V& add(const Key& key, Kept k) {
    if (young_bytes_ + k.bytes > half_ && !young_.empty()) {  // a turn: the old generation goes
      old_ = std::move(young_);
      old_bytes_ = young_bytes_;
      young_ = {};
      young_bytes_ = 0;
    }
    young_bytes_ += k.bytes;
    return young_.emplace(key, std::move(k)).first->second.value;
  }
  std::size_t half_;
  std::unordered_map<Key, Kept, KeyHash> young_, old_;
  std::size_t young_bytes_ = 0, old_bytes_ = 0;
};

}  // namespace rnav
