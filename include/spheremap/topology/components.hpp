// Connected components of a closed triangle mesh, with their size, shape and topology (stage: topology).
#pragma once

#include <cstdint>
#include <vector>

#include "spheremap/mesh.hpp"

namespace spheremap {

struct MeshComponent {
  std::vector<std::int32_t> triangles;  // indices into mesh.triangles, ascending
  std::int64_t vertices = 0;
  double area = 0;
  /// Signed enclosed volume (divergence theorem): positive for a surface oriented outward (a piece),
  /// negative for one oriented toward the inside of a void it bounds (a cavity of an outward solid).
  double signed_volume = 0;
  /// From the Euler characteristic V - E + F = 2 - 2g with E = 3F/2 (every edge in two triangles): only
  /// meaningful for closed 2-manifold components, which is what the contours of this library are.
  int genus = 0;
};

/// Components connected through shared vertices, largest area first (ties: smallest first triangle).
/// Preconditions: triangle indices valid. Throws nothing beyond std::bad_alloc.
std::vector<MeshComponent> mesh_components(const Mesh& mesh);

/// The sub-mesh of one component: its vertices (in ascending original order) with their attributes.
/// Preconditions: `component` is one of mesh_components(mesh). Throws nothing beyond std::bad_alloc.
Mesh extract_component(const Mesh& mesh, const MeshComponent& component);
/// The same, made in place from a mesh that is no longer needed (no second copy of a large surface).
Mesh extract_component(Mesh&& mesh, const MeshComponent& component);

}  // namespace spheremap
