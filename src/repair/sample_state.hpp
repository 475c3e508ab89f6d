// Private to the handle repair: one byte of state per grid sample, for the whole repair.
#pragma once

#include <atomic>
#include <cstdint>

namespace spheremap::detail {

constexpr std::uint8_t kInSolid = 1;    // reached by the solid's growth
constexpr std::uint8_t kInOutside = 2;  // reached by the outside's growth
constexpr std::uint8_t kQueued = 4;     // in the growth's queue
constexpr std::uint8_t kClustered = 8;  // in a cluster of left-out samples
constexpr std::uint8_t kToggled = 16;   // in the set whose Euler change is being counted
constexpr std::uint8_t kInside = 32;    // field > level (kept in the state so that growths read one array)
constexpr std::uint8_t kMark = 64;      // in the cluster being moved

// The two growths run at once on two threads (grow_both). Each writes only the state bytes of its own
// side's samples (the solid's growth the inside ones, the outside's the outside ones), and reads the other
// side's bytes only for bits that never change there (kInside) or that only its own side ever has (its
// member bit): each decision is the one it would be with the growths one after the other. The bytes are
// still shared, so they are read and written as relaxed atomics (plain moves on x86-64); a byte has one
// writer, so a load then a store is a safe update.
inline std::uint8_t load_state(const std::uint8_t* state, std::int64_t s) {
  return std::atomic_ref<std::uint8_t>(const_cast<std::uint8_t&>(state[s])).load(std::memory_order_relaxed);
}
inline void store_state(std::uint8_t* state, std::int64_t s, std::uint8_t value) {
  std::atomic_ref<std::uint8_t>(state[s]).store(value, std::memory_order_relaxed);
}

}  // namespace spheremap::detail
