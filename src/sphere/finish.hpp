// Private to the sphere stage: the last steps of every map. Superposition (first, so that the
// certificate is of the very numbers that are written), certificate, and untangling on the sphere when
// the map is not certified but covers the sphere once (local moves can remove folds and collapse, not
// change how often the image covers it).
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "../util/stage_timer.hpp"
#include "spheremap/geometry/superposition.hpp"
#include "spheremap/mesh.hpp"
#include "spheremap/sphere/certify.hpp"
#include "spheremap/sphere/map.hpp"
#include "spheremap/topology/connectivity.hpp"
#include "untangle.hpp"

namespace spheremap::detail {

/// A map after its last steps.
struct Finished {
  std::vector<Vec3> sphere;
  Superposition superposition;
  Certificate certificate;
  std::vector<double> solid_angles;  // of the input's triangles on `sphere`, from the certificate
  std::int64_t untangling_moves = 0;
  bool untangled = false;  // untangling ran
};

/// The input's rings (the untangling works on the input's triangles, not the split working mesh), and
/// what the untangling needs of the input, built at its first call and shared by the others (a map
/// untangles up to one candidate per equalizing round).
class InputStars {
 public:
  explicit InputStars(const Mesh& mesh, const VertexRings& rings) : mesh_(mesh), rings_(rings) {}
  [[nodiscard]] const VertexRings& rings() const { return rings_; }
  const UntanglingFrame& untangling_frame() {
    if (!frame_) frame_ = detail::untangling_frame(mesh_, rings_);
    return *frame_;
  }

 private:
  const Mesh& mesh_;
  const VertexRings& rings_;
  std::optional<UntanglingFrame> frame_;
};

/// Superposes `sphere` (the input's vertices) on the mesh, certifies it and, with options.repair, untangles
/// it when it is not certified but covers the sphere once. Laps "superpose", "untangle" (if it ran) and
/// "certify" on `timer` when given.
/// Preconditions: sphere.size() == mesh.positions.size(), unit vectors; `input` built on `mesh`.
Finished finish_map(const Mesh& mesh, InputStars& input, std::vector<Vec3> sphere, const MapOptions& options,
                    StageTimer* timer = nullptr);

}  // namespace spheremap::detail
