#pragma once
// Open-addressing hash map from a directed edge (a, b) to a 32-bit value, with backward-shift
// deletion (no tombstones), sized for the front: it stays small while the growth sweeps on.
#include <cstdint>
#include <vector>

namespace expanse::detail {

class EdgeMap {
 public:
  static constexpr std::uint64_t empty_key = ~std::uint64_t{0};

  explicit EdgeMap(std::size_t expected = 1024) { rehash(capacity_for(expected)); }

  static std::uint64_t key(std::int32_t a, std::int32_t b) {
    return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) | static_cast<std::uint32_t>(b);
  }

  /// Pointer to the value of (a, b), or nullptr.
  std::int64_t* find(std::uint64_t k) {
    for (std::size_t slot = home(k);; slot = (slot + 1) & mask_) {
      if (keys_[slot] == k) return &values_[slot];
      if (keys_[slot] == empty_key) return nullptr;
    }
  }

  /// Inserts or overwrites.
  void insert(std::uint64_t k, std::int64_t value) {
    if (2 * (size_ + 1) > keys_.size()) rehash(keys_.size() * 2);
    std::size_t slot = home(k);
    while (keys_[slot] != empty_key && keys_[slot] != k) slot = (slot + 1) & mask_;
    if (keys_[slot] == empty_key) ++size_;
    keys_[slot] = k;
    values_[slot] = value;
  }

  /// Removes k if present; returns whether it was.
  bool erase(std::uint64_t k) {
    std::size_t slot = home(k);
    while (keys_[slot] != k) {
      if (keys_[slot] == empty_key) return false;
      slot = (slot + 1) & mask_;
    }
    // Backward-shift: move later members of the probe run into the hole when that keeps them
    // reachable from their home slot.
    std::size_t hole = slot;
    for (std::size_t next = (hole + 1) & mask_; keys_[next] != empty_key; next = (next + 1) & mask_) {
      const std::size_t h = home(keys_[next]);
      const bool movable = hole <= next ? (h <= hole || h > next) : (h <= hole && h > next);
      if (movable) {
        keys_[hole] = keys_[next];
        values_[hole] = values_[next];
        hole = next;
      }
    }
    keys_[hole] = empty_key;
    --size_;
    return true;
  }

  std::size_t size() const { return size_; }

 private:
  static std::size_t capacity_for(std::size_t n) {
    std::size_t c = 64;
    while (c < 2 * n) c <<= 1;
    return c;
  }
  std::size_t home(std::uint64_t k) const {
    k ^= k >> 31;
    k *= 0x9E3779B97F4A7C15ull;
    k ^= k >> 29;
    return static_cast<std::size_t>(k) & mask_;
  }
  void rehash(std::size_t capacity) {
    std::vector<std::uint64_t> old_keys(capacity, empty_key);
    std::vector<std::int64_t> old_values(capacity);
    old_keys.swap(keys_);
    old_values.swap(values_);
    mask_ = capacity - 1;
    size_ = 0;
    for (std::size_t i = 0; i < old_keys.size(); ++i) {
      if (old_keys[i] != empty_key) insert(old_keys[i], old_values[i]);
    }
  }

  std::vector<std::uint64_t> keys_;
  std::vector<std::int64_t> values_;
  std::size_t mask_ = 0;
  std::size_t size_ = 0;
};

}  // namespace expanse::detail
