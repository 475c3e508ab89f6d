// The offline viewer: one self-contained index.html showing a molecular surface and its map on the sphere
// side by side, coloured by per-vertex properties, with picking back to atoms and residues.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "spheremap/mesh.hpp"
#include "spheremap/properties/colour_scale.hpp"

namespace spheremap {

/// One atom as the viewer names it. Texts are shown as given (UTF-8; invalid bytes shown as U+FFFD).
struct ViewerAtom {
  std::string chain;         // e.g. "A"
  std::string residue_name;  // e.g. "GLY"
  std::int32_t residue_number = 0;
  std::string insertion_code;  // usually empty
  std::string atom_name;       // e.g. "CA"
};

/// A per-vertex value the viewer can colour by.
struct ViewerProperty {
  std::string name;  // shown in the picker, e.g. "electrostatics"
  std::string unit;  // shown on the colour bar, e.g. "kT/e"; may be empty
  ScaleKind scale = ScaleKind::sequential;
  ValueRange range;                     // the colour bar's range when the page opens (editable there)
  std::vector<float> values;            // one per vertex; NaN = no value (drawn grey)
  std::vector<std::string> categories;  // categorical only, optional: the name of class k (e.g. chain "A")
};

/// Everything index.html shows. The surface and the sphere share the triangles: vertex v of the
/// surface is mapped to vertex v of the sphere.
struct ViewerData {
  std::string title;                       // e.g. "1crn: molecular surface and sphere map"
  std::vector<Vec3> surface_positions;     // the original surface (e.g. in Å)
  std::vector<Vec3> sphere_positions;      // the map, on (or near) the unit sphere, superposed on the surface
  std::vector<Triangle> triangles;         // counter-clockwise seen from outside
  std::vector<std::int32_t> vertex_atoms;  // per vertex: index into atoms, or -1 (none); empty = none at all
  std::vector<ViewerAtom> atoms;
  std::vector<ViewerProperty> properties;  // may be empty (the surfaces are then drawn in one colour)
};

/// The page, complete: HTML with the viewer's script (three.js bundled at build time) and `data`
/// embedded (arrays as little-endian binary, zlib-deflated, base64; names in a JSON manifest). Opens from
/// file:// with no network. Deterministic: the same data gives the same bytes. Texts from `data` are
/// escaped for HTML and JSON, so no name can end the script or the page early.
/// Preconditions: surface and sphere have the same vertex count (>= 3) and finite coordinates; at least one
/// triangle, every index in range; vertex_atoms empty or one per vertex, each -1 or an index into atoms;
/// every property has one value per vertex and a finite range with hi > lo (categorical: not checked).
/// Throws std::invalid_argument naming the first precondition that fails.
std::string viewer_html(const ViewerData& data);

/// Writes viewer_html(data) to `path` atomically (a temporary file beside it, then rename).
/// Throws as viewer_html, and InputError naming the file if it cannot be written.
void write_viewer_html(const std::filesystem::path& path, const ViewerData& data);

}  // namespace spheremap
