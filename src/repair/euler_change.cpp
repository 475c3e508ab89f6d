#include "euler_change.hpp"

#include <array>

#include "lattice.hpp"
#include "sample_state.hpp"

namespace spheremap::detail {

template <typename T>
int euler_change(const Grid3<T>& field, double level, const std::vector<std::int64_t>& samples, ClosureKind kind,
                 std::uint8_t* state) {
  const bool filled = kind == ClosureKind::kFill;
  const LatticeStar& star = lattice_star();
  const Lattice lattice(field.size);
  const T* values = field.values.data();
  for (const auto v : samples) state[v] |= kToggled;
  auto inside_now = [&](std::int64_t t) { return t >= 0 && values[t] > level; };
  int before = 0, after = 0;
  for (const auto v : samples) {
    std::array<std::int64_t, 14> nb{};
    lattice.neighbours(v, [&](int n, std::int64_t t) { nb[n] = t; });
    auto counted_here = [&](std::int64_t t) { return t < 0 || !(state[t] & kToggled) || t > v; };
    auto inside_after = [&](std::int64_t t) { return t >= 0 && ((state[t] & kToggled) ? filled : values[t] > level); };
    const bool v_before = inside_now(v), v_after = filled;
    before += v_before ? 1 : 0;
    after += v_after ? 1 : 0;
    for (int a = 0; a < 14; ++a) {
      if (!counted_here(nb[a])) continue;
      before -= (v_before && inside_now(nb[a])) ? 1 : 0;
      after -= (v_after && inside_after(nb[a])) ? 1 : 0;
    }
    for (const auto& [a, b] : star.triangles) {
      if (!counted_here(nb[a]) || !counted_here(nb[b])) continue;
      before += (v_before && inside_now(nb[a]) && inside_now(nb[b])) ? 1 : 0;
      after += (v_after && inside_after(nb[a]) && inside_after(nb[b])) ? 1 : 0;
    }
    for (const auto& [a, b, d] : star.tetrahedra) {
      if (!counted_here(nb[a]) || !counted_here(nb[b]) || !counted_here(nb[d])) continue;
      before -= (v_before && inside_now(nb[a]) && inside_now(nb[b]) && inside_now(nb[d])) ? 1 : 0;
      after -= (v_after && inside_after(nb[a]) && inside_after(nb[b]) && inside_after(nb[d])) ? 1 : 0;
    }
  }
  for (const auto v : samples) state[v] &= static_cast<std::uint8_t>(~kToggled);
  return after - before;
}

template int euler_change(const Grid3<double>&, double, const std::vector<std::int64_t>&, ClosureKind, std::uint8_t*);
template int euler_change(const Grid3<float>&, double, const std::vector<std::int64_t>&, ClosureKind, std::uint8_t*);

}  // namespace spheremap::detail
