// Private to the sphere stage: a better start for the optimization on the sphere, made on a coarser copy
// of the mesh (the area objective's multilevel start).
#pragma once

#include <cstdint>
#include <vector>

#include "spheremap/mesh.hpp"
#include "spheremap/sphere/optimize.hpp"

namespace spheremap::detail {

/// Meshes with fewer vertices than this get no coarse start: their own steps are cheap enough.
inline constexpr std::int64_t kCoarseStartMinVertices = 20000;

struct CoarseStart {
  std::int64_t coarse_vertices = 0;   // of the coarse mesh optimized (the finest one when nested)
  int levels = 0;                     // coarse meshes, each about a tenth of the one above
  int iterations = 0;                 // Newton steps on all of them
  std::int64_t untangling_moves = 0;  // moves that made the prolonged maps valid
};

/// A valid map of `mesh` near the minimum of `options`' energy at the scale of a mesh ten times coarser:
/// the mesh is simplified (keeping the poles, and every triangle positively oriented on `sphere`, so that
/// the kept vertices' points are a valid coarse map), that map is optimized (with a coarse start of its
/// own when it is still large), and every vertex is carried along with the coarse triangle of the old
/// coarse map that holds its point (in barycentric coordinates of the central projection); the few
/// triangles this folds are untangled.
/// Returns false, `sphere` unchanged, when `sphere` is not a valid map (a triangle not positively
/// oriented), the mesh has fewer than kCoarseStartMinVertices vertices,
/// simplifies to more than a quarter of them, a point cannot be located, or the result is not a valid map
/// with the poles where they were; else true with the map in `sphere` and `report` filled.
/// Preconditions: `mesh` closed, oriented, genus 0; `sphere` a valid map of it (every triangle positively
/// oriented, unit vectors); north != south are vertices, the optimization's fixed points. Deterministic.
bool coarse_start(const Mesh& mesh, std::vector<Vec3>& sphere, std::int32_t north, std::int32_t south,
                  const SphereOptimizeOptions& options, CoarseStart& report);

}  // namespace spheremap::detail
