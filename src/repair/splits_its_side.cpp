#include "splits_its_side.hpp"

#include <algorithm>
#include <limits>
#include <utility>

#include "lattice.hpp"

namespace spheremap::detail {
namespace {

// Union-find over the labels of the search, with, per root, the samples of its label queued and not yet
// searched: a root whose count drops to zero has run out.
class Labels {
 public:
  int make(std::int64_t queued) {
    parent_.push_back(static_cast<int>(parent_.size()));
    pending_.push_back(queued);
    ++roots_;
    return parent_.back();
  }
  int find(int a) {
    while (parent_[static_cast<std::size_t>(a)] != a)
      a = parent_[static_cast<std::size_t>(a)] =
          parent_[static_cast<std::size_t>(parent_[static_cast<std::size_t>(a)])];
    return a;
  }
  void unite(int a, int b) {
    a = find(a), b = find(b);
    if (a == b) return;
    if (b < a) std::swap(a, b);
    parent_[static_cast<std::size_t>(b)] = a;
    pending_[static_cast<std::size_t>(a)] += pending_[static_cast<std::size_t>(b)];
    --roots_;
  }
  std::int64_t& pending(int root) { return pending_[static_cast<std::size_t>(root)]; }
  [[nodiscard]] int roots() const { return roots_; }

 private:
  std::vector<int> parent_;
  std::vector<std::int64_t> pending_;
  int roots_ = 0;
};

// Sample -> label, open addressing: the searches are small and many (one per closure applied).
class SampleLabels {
 public:
  explicit SampleLabels(std::size_t capacity) : keys_(capacity, -1), labels_(capacity) {}
  // The slot of t: holding its label (known(slot)), or where to store it.
  [[nodiscard]] std::size_t slot_of(std::int64_t t) const {
    const std::size_t mask = keys_.size() - 1;
    auto slot = static_cast<std::size_t>((static_cast<std::uint64_t>(t) * 0x9E3779B97F4A7C15ull) >> 20) & mask;
    while (keys_[slot] != -1 && keys_[slot] != t) slot = (slot + 1) & mask;
    return slot;
  }
  [[nodiscard]] bool known(std::size_t slot) const { return keys_[slot] != -1; }
  [[nodiscard]] int label(std::size_t slot) const { return labels_[slot]; }
  void store(std::size_t slot, std::int64_t t, int label) {
    keys_[slot] = t;
    labels_[slot] = label;
    ++stored_;
  }
  [[nodiscard]] bool half_full() const { return 2 * stored_ > keys_.size(); }

 private:
  std::vector<std::int64_t> keys_;
  std::vector<int> labels_;
  std::size_t stored_ = 0;
};

// Whether no moved sample touches the side it joined (beyond the grid is outside).
template <typename T>
bool apart_from_new_side(const Lattice& lattice, const T* values, double level, const std::vector<std::int64_t>& moved,
                         bool new_inside) {
  auto is_moved = [&](std::int64_t t) { return std::binary_search(moved.begin(), moved.end(), t); };
  bool joins = false;
  for (const auto s : moved) {
    lattice.neighbours(s, [&](int, std::int64_t t) {
      joins = joins || (t < 0 ? !new_inside : (values[t] > level) == new_inside && !is_moved(t));
    });
    if (joins) break;
  }
  return !joins;
}

}  // namespace

template <typename T>
bool closure_splits_its_side(const Grid3<T>& field, double level, const std::vector<std::int64_t>& samples,
                             ClosureKind kind, std::int64_t budget) {
  const Lattice lattice(field.size);
  const T* values = field.values.data();
  const bool left_inside = kind == ClosureKind::kCut;
  if (apart_from_new_side(lattice, values, level, samples, !left_inside)) return true;
  auto on_left_side = [&](std::int64_t t) { return t >= 0 && (values[t] > level) == left_inside; };
  constexpr std::int64_t kEndless = std::numeric_limits<std::int64_t>::max() / 2;
  Labels labels;
  const int beyond = left_inside ? -1 : labels.make(kEndless);  // the outside beyond the grid never runs out
  std::size_t capacity = 1024;
  while (capacity < 4 * static_cast<std::size_t>(budget) + 64 * samples.size()) capacity *= 2;
  SampleLabels table(capacity);
  std::vector<std::pair<std::int64_t, int>> queue;
  for (const auto s : samples)
    lattice.neighbours(s, [&](int, std::int64_t t) {
      if (!on_left_side(t)) return;
      const auto slot = table.slot_of(t);
      if (table.known(slot)) return;
      table.store(slot, t, labels.make(1));
      queue.emplace_back(t, table.label(slot));
    });
  budget += static_cast<std::int64_t>(queue.size());
  for (std::size_t head = 0; head < queue.size() && labels.roots() > 1; ++head) {
    if (static_cast<std::int64_t>(head) >= budget || table.half_full()) return false;
    const auto [u, label] = queue[head];
    lattice.neighbours(u, [&](int, std::int64_t t) {
      if (t < 0) {
        if (beyond >= 0) labels.unite(label, beyond);
        return;
      }
      if (!on_left_side(t)) return;
      const auto slot = table.slot_of(t);
      if (table.known(slot)) {
        labels.unite(label, table.label(slot));
        return;
      }
      table.store(slot, t, label);
      queue.emplace_back(t, label);
      ++labels.pending(labels.find(label));
    });
    if (--labels.pending(labels.find(label)) == 0 && labels.roots() > 1) return true;
  }
  return false;
}

template bool closure_splits_its_side(const Grid3<double>&, double, const std::vector<std::int64_t>&, ClosureKind,
                                      std::int64_t);
template bool closure_splits_its_side(const Grid3<float>&, double, const std::vector<std::int64_t>&, ClosureKind,
                                      std::int64_t);

}  // namespace spheremap::detail
