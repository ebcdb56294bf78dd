#pragma once
// The search's state -> node table: open addressing with linear probing (a flat array, no
// allocation per insert), cleared between plans.

#include <cstdint>
#include <vector>

namespace fieldlidar::planning {

class StateTable {
 public:
  static constexpr std::uint32_t kEmpty = 0xffffffffu;

  void clear() {
    if (keys_.empty()) resize(1u << 14);
    std::fill(keys_.begin(), keys_.end(), kEmpty);
    size_ = 0;
  }
  /// The value of `key`, or nullptr.
  std::int32_t* find(std::uint32_t key) {
    for (std::uint32_t i = hash(key);; i = (i + 1) & mask_) {
      if (keys_[i] == key) return &values_[i];
      if (keys_[i] == kEmpty) return nullptr;
    }
  }
  void set(std::uint32_t key, std::int32_t value) {
    if (2 * (size_ + 1) > keys_.size()) grow();
    for (std::uint32_t i = hash(key);; i = (i + 1) & mask_) {
      if (keys_[i] == key) {
        values_[i] = value;
        return;
      }
      if (keys_[i] == kEmpty) {
        keys_[i] = key;
        values_[i] = value;
        ++size_;
        return;
      }
    }
  }

 private:
  std::uint32_t hash(std::uint32_t k) const { return (k * 2654435769u) & mask_; }
  void resize(std::size_t n) {
    keys_.assign(n, kEmpty);
    values_.assign(n, 0);
    mask_ = std::uint32_t(n - 1);
  }
  void grow() {
    std::vector<std::uint32_t> keys;
    std::vector<std::int32_t> values;
    keys.swap(keys_);
    values.swap(values_);
    resize(keys.size() * 2);
    size_ = 0;
    for (std::size_t i = 0; i < keys.size(); ++i)
      if (keys[i] != kEmpty) set(keys[i], values[i]);
  }
  std::vector<std::uint32_t> keys_;
  std::vector<std::int32_t> values_;
  std::uint32_t mask_ = 0;
  std::size_t size_ = 0;
};

}  // namespace fieldlidar::planning
