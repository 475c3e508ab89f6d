// What every picture of a map draws from (stage: render): the original surface, its globe (the sphere map
// superposed on it), the residue under each vertex and the per-vertex properties. Built from a map job in
// memory or from a finished output folder read back (pipeline/map_folder.hpp), so that both draw alike.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "spheremap/mesh.hpp"
#include "spheremap/properties/property.hpp"

namespace spheremap {

/// A residue as pictures and `locate` name it.
struct ResidueLabel {
  std::string chain;
  std::int32_t number = 0;
  std::string insertion_code;  // empty when blank
  std::string name;            // e.g. "LYS"
};

/// "A:45" or "A:45B" (chain, number, insertion code): the form `--outline` and `locate --residue` take.
/// Never throws (but std::bad_alloc).
std::string residue_id(const ResidueLabel& residue);

struct Globe {
  std::string name;                 // the structure or mesh, for titles (e.g. "1crn")
  std::vector<Vec3> surface;        // the original surface
  std::vector<Vec3> sphere;         // the globe: unit vectors superposed on the surface (sphere.ply)
  std::vector<Triangle> triangles;  // shared by both, counter-clockwise seen from outside
  /// Per vertex: the index into `residues` of the residue of its atom, or -1; empty for a mesh without atoms.
  std::vector<std::int32_t> vertex_residue;
  std::vector<ResidueLabel> residues;  // sorted by chain, number, insertion code
  std::vector<SurfaceProperty> properties;
  /// Why a structure's globe has no residues (e.g. its folder lost atoms.csv); empty: none are expected (a mesh).
  std::string no_residues_reason;
};

/// Why `globe` has no residues, for messages: its no_residues_reason, or that it was made from a mesh file.
/// Never throws (but std::bad_alloc).
std::string no_residues_text(const Globe& globe);

/// The globe of a mapped `surface` (positions, triangles, and its atom attributes vertex_chain,
/// vertex_residue_number, vertex_insertion_code, vertex_residue_name when present) and its `sphere`.
/// Preconditions: sphere.size() == surface.vertex_count(); every property has one value per vertex.
/// Throws std::invalid_argument naming the first precondition that fails.
Globe make_globe(const Mesh& surface, const std::vector<Vec3>& sphere, std::vector<SurfaceProperty> properties,
                 std::string name);

/// The property of `globe` named `name`, or nullptr. Never throws.
const SurfaceProperty* find_globe_property(const Globe& globe, std::string_view name);

/// The names of globe's properties, comma-separated (for messages). Never throws (but std::bad_alloc).
std::string globe_property_names(const Globe& globe);

/// The properties pictures show until the property registry fills MapJobResult::properties: octant (of
/// the globe point, categorical), and from the surface's atom attributes chain_index (categorical, chains
/// in order of first atom), sequence_position (per chain, 0 at its first polymer residue on the surface to 1
/// at its last, by residue number and insertion code; no value on ligands, ions and waters), residue_number, b_factor
/// (Å²) and charge (e), each when the surface carries what it needs. Precondition: sphere.size() ==
/// surface.vertex_count(). Never throws (but std::bad_alloc).
std::vector<SurfaceProperty> properties_from_attributes(const Mesh& surface, const std::vector<Vec3>& sphere);

}  // namespace spheremap
