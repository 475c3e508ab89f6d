// Private to the surface stage: whether the parts of a circle that other spheres cover leave nothing of
// it exposed (the SAS arcs' quick test in probe_centres.cpp).
#pragma once

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <vector>

namespace spheremap::detail {

// The part of a circle (centre + ρ (cos θ u + sin θ v)) inside another enlarged sphere: θ with
// 2ρ m cos(θ - φ) < room, where (a, b) = m (cos φ, sin φ); `spread` = 2ρm, and -spread < room < spread.
struct CoverTerm {
  double a, b, room, spread;
  std::int32_t atom;
};

// A monotone function of the angle of direction (x, y) in [0, 2π), with values in [0, 4): angles
// compared without trigonometry.
inline double pseudo_angle(double x, double y) {
  const double p = y / (std::abs(x) + std::abs(y));
  if (x < 0) return 2 - p;
  return y >= 0 ? p : 4 + p;
}

// Whether the parts in `terms` cover the whole circle with a margin far beyond rounding (1e-9 rad);
// false when they do not, or might not. Precondition: spread > 0 in every term.
//
// Without sorting: the parts are put in kCoverBuckets buckets of pseudo-angle by where they start, and
// each bucket keeps only the farthest end of its parts. The sweep then takes every part of a bucket to
// start at the bucket's upper edge: later than it does, which only shrinks the union, so "covered" stays
// certain; a bucket whose edge is not yet reached is passed over (its parts left out), which can only
// turn a covered circle into "unsure". 256 buckets (0.9–1.8° each) are narrow beside the overlaps of
// the spheres around a buried circle.
constexpr int kCoverBuckets = 256;
struct CoverScratch {
  std::array<double, kCoverBuckets> farthest{};
};
inline bool certainly_covered(const std::vector<CoverTerm>& terms, CoverScratch& scratch) {
  constexpr double kMargin = 1e-9, kWidth = 4.0 / kCoverBuckets;
  std::array<std::uint64_t, kCoverBuckets / 64> used{};
  double from_zero = 0;  // [0, from_zero) is covered by the parts that wrap past a full turn
  bool any = false;
  for (const CoverTerm& t : terms) {
    // Exposed where cos(θ - φ) > room / spread, i.e. |θ - φ| < half; covered is θ - φ in (half, 2π - half).
    // The ends are (a, b) turned by ±half, scaled by spread (pseudo_angle does not depend on length):
    // no division but pseudo_angle's.
    if (t.room < (-1 + 1e-12) * t.spread)
      continue;  // a sliver (or nothing): leaving it out only makes the answer "unsure"
    const double cosine = t.room, sine = std::sqrt(std::max(0.0, (t.spread - t.room) * (t.spread + t.room)));
    const double start = pseudo_angle(t.a * cosine - t.b * sine, t.b * cosine + t.a * sine);
    if (!(start >= 0 && start <= 4)) return false;  // not a number: cannot happen (spread > 0), kept out of the cast
    double end = pseudo_angle(t.a * cosine + t.b * sine, t.b * cosine - t.a * sine);
    // Past a full turn? The covered length is more than π exactly when cos(half) > 0.
    if (cosine > 0 ? end <= start : end < start) end += 4, from_zero = std::max(from_zero, end - 4);
    const int bucket = std::min(static_cast<int>(start * (kCoverBuckets / 4.0)), kCoverBuckets - 1);
    const std::uint64_t bit = std::uint64_t{1} << (bucket & 63);
    auto& word = used[static_cast<std::size_t>(bucket >> 6)];
    double& farthest = scratch.farthest[static_cast<std::size_t>(bucket)];
    farthest = (word & bit) ? std::max(farthest, end) : end;
    word |= bit;
    any = true;
  }
  if (!any) return false;
  double reached = from_zero;
  for (std::size_t w = 0; w < used.size(); ++w)
    for (std::uint64_t word = used[w]; word != 0; word &= word - 1) {
      const auto bucket = static_cast<int>(w * 64) + std::countr_zero(word);
      if (static_cast<double>(bucket + 1) * kWidth <= reached - kMargin)
        reached = std::max(reached, scratch.farthest[static_cast<std::size_t>(bucket)]);
    }
  return reached > 4 + kMargin;
}

}  // namespace spheremap::detail
