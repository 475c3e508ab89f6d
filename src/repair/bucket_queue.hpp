// Private to the handle repair: the priority queue of its growths.
#pragma once

#include <algorithm>
#include <cstddef>
#include <vector>

namespace spheremap::detail {

// A priority queue over small integer keys (smaller key first): one FIFO per key, so pushes and pops
// are O(1) and the order (first offered first within a key, which grows fronts evenly) is
// deterministic. A push below the current key moves the front back, as a heap would. Index is the
// sample index type: 32 bits whenever the grid allows, which halves the queue's memory.
template <typename Index>
class BucketQueue {
 public:
  explicit BucketQueue(std::size_t keys) : buckets_(std::max<std::size_t>(keys, 1)) {}
  void push(std::size_t key, Index sample) {
    key = std::min(key, buckets_.size() - 1);
    buckets_[key].items.push_back(sample);
    front_ = std::min(front_, key);
    ++size_;
  }
  [[nodiscard]] bool empty() const { return size_ == 0; }
  // The sample that pop() will return `ahead` calls after the next one, if it is already in the current
  // bucket (for prefetching); else null.
  [[nodiscard]] const Index* peek(std::size_t ahead) const {
    const Bucket& bucket = buckets_[front_];
    const std::size_t at = bucket.head + ahead;
    return at < bucket.items.size() ? &bucket.items[at] : nullptr;
  }
  Index pop() {
    while (buckets_[front_].head == buckets_[front_].items.size()) ++front_;
    Bucket& bucket = buckets_[front_];
    const Index s = bucket.items[bucket.head++];
    if (bucket.head == bucket.items.size()) {
      // A drained bucket gives its memory back when it held many samples (a front passing through): the
      // queue then stays as large as the fronts, not as the sum of every bucket's peak.
      if (bucket.items.capacity() > kKeptCapacity) std::vector<Index>().swap(bucket.items);
      bucket.items.clear();
      bucket.head = 0;
    }
    --size_;
    return s;
  }

 private:
  static constexpr std::size_t kKeptCapacity = 4096;
  struct Bucket {
    std::vector<Index> items;
    std::size_t head = 0;
  };
  std::vector<Bucket> buckets_;
  std::size_t front_ = 0, size_ = 0;
};

}  // namespace spheremap::detail
