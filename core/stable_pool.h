// Objects made one at a time during a step whose addresses hold until the
// pool is cleared: blocks of block_size, kept across clears, so that once a
// step has made as many as any step before it, making them allocates
// nothing, and memory follows what was used, not a worst case. Internal to
// core/.
#pragma once

#include <cstddef>
#include <memory>
#include <vector>

namespace bitstep {

template <class T, size_t block_size = 64>
class StablePool {
 public:
  T& push(const T& value) {
    const size_t block = used_ / block_size;
    if (block == blocks_.size()) blocks_.push_back(std::make_unique<T[]>(block_size));
    T& slot = blocks_[block][used_ % block_size];
    slot = value;
    ++used_;
    return slot;
  }
  void clear() { used_ = 0; }
  size_t size() const { return used_; }

 private:
  std::vector<std::unique_ptr<T[]>> blocks_;
  size_t used_ = 0;
};

}  // namespace bitstep
