// Private to the handle repair: moving a membrane to the thinnest section of its handle or tunnel nearby.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "lattice.hpp"
#include "spheremap/graph/max_flow.hpp"

namespace spheremap::detail {

// The growths put a membrane where their two fronts meet: where the handle is thinnest or the tunnel
// narrowest by the depth that orders them (an inscribed radius), which is not where its cross-section is
// smallest (a slit is narrow but wide). Within `reach` lattice steps of the membrane, the sides of the
// handle (or tunnel) are labelled by a breadth-first race from the membrane's faces (the connected groups
// of grown samples next to it) through the grown set; a minimum vertex cut (maximum_flow, unit capacity
// per sample) then separates the far ends of the sides (where the race stopped, or where two sides met
// again around the handle) through the sides and the membrane: the smallest cross-section within reach,
// in samples. A cluster where several membranes meet (more than two faces) gets the union of the cuts
// isolating each face from the others, all but the largest (the classic approximation of a multiway
// cut). The caller checks what the new membrane changes (Euler characteristic, area) before using it.
// One mover per thread: it keeps its buffers from one membrane to the next, and only reads `state`.
class MembraneMover {
 public:
  MembraneMover(const Lattice& lattice, const std::array<std::int64_t, 3>& size, const std::uint8_t* state, int reach)
      : lattice_(lattice), size_(size), state_(state), reach_(reach) {}

  // The new membrane (sorted sample indices) if one with fewer samples than `membrane` exists, else empty.
  // `member_bit`: kInSolid for a cut (the membrane's samples are inside), kInOutside for a fill.
  std::vector<std::int64_t> move(const std::vector<std::int64_t>& membrane, std::uint8_t member_bit);

  // Completes a new membrane (every sample within the box of the last move, all on the side `inside`)
  // with what changing it would enclose or split off: the samples of its side next to it, connected
  // through that side within the box, that do not reach the box's outer layer (a handle's or a tunnel's
  // sides lead out of the box; a crevice at the rim of a fill, closed by it, does not). Changed too, they
  // leave no void (or piece) that the Euler characteristic would count as a handle removed. Returns false
  // if the membrane is a cut that does not touch the outside. Which samples are inside: the kInside bit
  // of the state (the field is not changed while membranes are moved).
  bool complete(std::vector<std::int64_t>& membrane, bool inside);

 private:
  // Labels: 0 none, sides 1 to kMaxFaces, then the membrane and samples waiting for their side.
  static constexpr std::uint8_t kNone = 0, kMaxFaces = 8, kFace = 254, kPending = 255;
  static constexpr std::int64_t kMaxBoxSamples = std::int64_t{1} << 22;
  [[nodiscard]] static bool is_side(std::uint8_t label) { return label != kNone && label <= kMaxFaces; }
  // Whether out of a labelled sample (label `from`) leads into its neighbour (label `to`): the neighbour
  // is labelled too, and the two are not on different sides.
  [[nodiscard]] static bool joined(std::uint8_t from, std::uint8_t to) {
    return to != kNone && to != kPending && !(is_side(from) && is_side(to) && from != to);
  }

  bool set_box(const std::vector<std::int64_t>& membrane);
  [[nodiscard]] std::int64_t local(std::int64_t s) const;
  [[nodiscard]] std::int64_t global(std::int64_t b) const;
  [[nodiscard]] bool interior(std::int64_t b) const;
  [[nodiscard]] bool is_inside(std::int64_t b) const;
  int label_faces(const std::vector<std::int64_t>& membrane, std::uint8_t member_bit);
  int label_sides(const std::vector<std::int64_t>& membrane, std::uint8_t member_bit);
  std::vector<std::int64_t> minimum_cut(int side, std::int64_t limit);

  const Lattice& lattice_;
  std::array<std::int64_t, 3> size_;
  const std::uint8_t* state_;
  int reach_;
  // The box searched: the membrane's bounding box grown by reach + 1, clipped to the grid.
  std::array<std::int64_t, 3> low_{}, extent_{};
  std::array<std::int64_t, 14> offset_{};
  std::int64_t count_ = 0;
  std::vector<std::uint8_t> label_, terminal_, seen_;  // per sample of the box
  std::vector<std::uint16_t> distance_;                // per sample of the box
  std::vector<std::int32_t> node_;                     // per sample of the box: its number in region_
  std::vector<std::int64_t> region_;                   // the labelled samples (box indices)
  FlowNetwork network_;
};

}  // namespace spheremap::detail
