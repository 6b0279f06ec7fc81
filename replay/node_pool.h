// Memory for a session's containers that is kept when freed and handed
// out again: once a match is warm, a tick's map nodes reuse the nodes of
// the ticks forgotten, and the allocator is not called (replay/session.h).
// Blocks are kept by their size in bytes; a container of one type asks
// for one size, so the kept blocks are as many as the container ever held
// at once.
#pragma once

#include <cstddef>
#include <new>
#include <utility>
#include <vector>

namespace bitstep {

class NodePool {
 public:
  NodePool() = default;
  NodePool(const NodePool&) = delete;
  NodePool& operator=(const NodePool&) = delete;
  ~NodePool() {
    for (auto& [size, free] : lists_) {
      while (free != nullptr) {
        Block* next = free->next;
        ::operator delete(free);
        free = next;
      }
    }
  }

  void* take(std::size_t size) {
    Block*& free = list(size);
    if (free == nullptr) return ::operator new(size < sizeof(Block) ? sizeof(Block) : size);
    Block* block = free;
    free = block->next;
    return block;
  }
  void give(void* p, std::size_t size) {
    Block*& free = list(size);
    free = new (p) Block{free};
  }

 private:
  struct Block {
    Block* next;
  };
  // Few sizes (one per container type): a short list, found by a scan.
  Block*& list(std::size_t size) {
    for (auto& [kept, free] : lists_) {
      if (kept == size) return free;
    }
    lists_.emplace_back(size, nullptr);  // once per size, while warming up
    return lists_.back().second;
  }
  std::vector<std::pair<std::size_t, Block*>> lists_;
};

// A standard allocator over a NodePool (which must outlive the container).
template <class T>
struct PoolAllocator {
  using value_type = T;
  NodePool* pool;
  explicit PoolAllocator(NodePool* p) : pool(p) {}
  template <class U>
  PoolAllocator(const PoolAllocator<U>& other) : pool(other.pool) {}  // NOLINT: a rebind, as the standard asks
  T* allocate(std::size_t n) { return static_cast<T*>(pool->take(n * sizeof(T))); }
  void deallocate(T* p, std::size_t n) { pool->give(p, n * sizeof(T)); }
  template <class U>
  bool operator==(const PoolAllocator<U>& other) const {
    return pool == other.pool;
  }
};

}  // namespace bitstep
