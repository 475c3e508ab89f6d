// From a polygon soup to a closed, oriented, 2-manifold genus-0 triangle mesh, or a clear refusal
// (stage: topology).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "spheremap/mesh.hpp"

namespace spheremap {

/// Which connected component of a mesh with several to keep.
struct ComponentChoice {
  enum class Mode {
    kRefuse,    // refuse a mesh with several components (the default)
    kLargest,   // the largest (most triangles; ties to the first)
    kNumbered,  // component `number`, in the order of their first triangle in the file
  };
  Mode mode = Mode::kRefuse;
  std::int32_t number = 0;  // with kNumbered, >= 0

  static constexpr ComponentChoice refuse() { return {}; }
  static constexpr ComponentChoice largest() { return {Mode::kLargest, 0}; }
  static constexpr ComponentChoice numbered(std::int32_t k) { return {Mode::kNumbered, k}; }
  friend constexpr bool operator==(const ComponentChoice&, const ComponentChoice&) = default;
};

struct PrepareOptions {
  /// Vertices closer than this (Euclidean) are welded; 0 welds exactly coincident ones only.
  double weld_tolerance = 0;
  /// Which connected component to keep when there are several.
  ComponentChoice component;
  /// Name used in messages (usually the input file name).
  std::string source_name = "mesh";
};

struct PrepareReport {
  std::int64_t input_vertices = 0;
  std::int64_t input_faces = 0;
  std::int64_t polygons_triangulated = 0;     // faces with more than 3 corners
  std::int64_t vertices_welded = 0;           // input vertices merged into another one
  std::int64_t unreferenced_vertices = 0;     // dropped because no triangle uses them
  std::int64_t degenerate_faces_dropped = 0;  // a corner repeated after welding
  std::int64_t duplicate_faces_dropped = 0;   // same three vertices as an earlier triangle
  std::int64_t components = 0;
  std::int64_t component_kept = 0;
  std::int64_t triangles_flipped = 0;  // re-oriented for consistency or to face outward
  int genus = 0;
  /// original_vertex[i] = index in the input file of the vertex that became vertex i (vertices keep
  /// their input order).
  std::vector<std::int32_t> original_vertex;
  /// vertex_of_input[j] = the vertex that input vertex j became (after welding), or -1 if it was dropped
  /// (unreferenced, or not in the kept component).
  std::vector<std::int32_t> vertex_of_input;
};

struct PreparedMesh {
  Mesh mesh;
  PrepareReport report;
};

/// Triangulates polygons (fan from the first corner whose diagonals are not edges), welds vertices, drops degenerate
/// and duplicate triangles and unreferenced vertices, then checks, in this order: non-manifold edges (shared by more
/// than two triangles), boundary edges, non-manifold (pinched) vertices, several components (unless
/// options.component says which), orientability, genus. Orients every triangle consistently and
/// outward (positive enclosed volume).
/// Throws MeshRefused (exit code 2) naming options.source_name, the problem, how many and the fix.
/// Throws InputError if the soup has no faces, an index out of range, a non-finite coordinate, a weld
/// tolerance below the precision of the coordinates, or options.component numbers a component the mesh
/// does not have (the message gives how many it has).
PreparedMesh prepare_mesh(const PolygonSoup& soup, const PrepareOptions& options = {});

/// Same checks for an already triangulated mesh (attributes are carried along).
PreparedMesh prepare_mesh(const Mesh& mesh, const PrepareOptions& options = {});

}  // namespace spheremap
