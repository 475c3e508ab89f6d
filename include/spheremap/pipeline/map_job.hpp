// The `map` job end to end (stage: pipeline): file -> prepared mesh (a structure: its molecular surface
// first, pipeline/molecular_surface.hpp) -> sphere map -> metrics -> outputs (report: pipeline/report.hpp).
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "spheremap/metrics/distortion.hpp"
#include "spheremap/molecule/structure.hpp"
#include "spheremap/pipeline/molecular_surface.hpp"
#include "spheremap/properties/property.hpp"
#include "spheremap/properties/registry.hpp"
#include "spheremap/sphere/map.hpp"
#include "spheremap/surface/ses.hpp"
#include "spheremap/topology/prepare.hpp"
#include "spheremap/topology/simplify.hpp"

namespace spheremap {

struct MapJobOptions {
  PrepareOptions prepare;
  /// map.poles, if set, are vertex indices of the input (0-based, in file order), translated through
  /// welding; run_map_job throws InputError if one does not exist or was dropped.
  MapOptions map;
  bool ascii = false;  // ASCII PLY outputs (full precision) instead of binary
  /// For structure files (.pdb .ent .cif .mmcif .pqr, optionally .gz): which atoms, and the surface.
  StructureOptions structure;
  /// carve_cavities is off by default (MSMS's outer surface): with it, each enclosed cavity that holds a
  /// probe becomes its own reported component, but a pocket within a probe diameter of the outside
  /// opens into the outer surface and changes it.
  SurfaceOptions surface;
  /// Structure files: skip the handle repair and refuse a surface of genus > 0 (the paper's filter).
  bool keep_topology = false;
  /// The surface is simplified before it is mapped (simplify_surface: a subset of its vertices, well-shaped
  /// triangles of about target_edge_length): a molecular surface always (a fine grid gives many times more
  /// triangles than a map needs), a mesh file only when simplify_mesh_files is true.
  /// The defaults (target edge 1, tolerance 0.1) are meant for Å; target_edge_length = 0 maps the surface
  /// as it is. For a mesh file, user-given poles are kept.
  SimplifyOptions simplify;
  bool simplify_mesh_files = false;
  /// The surface properties (properties/registry.hpp): which, electrostatics, --values files.
  PropertyOptions properties;
  /// --color: the property the PLY's red green blue show (colour_property); empty: the default choice.
  std::string colour;
};

struct MapJobResult {
  std::filesystem::path input;
  bool from_structure = false;  // the mesh is the molecular surface of a structure file
  std::int64_t atoms = 0;
  StructureReport structure;
  HandleRepairReport topology;
  std::vector<SurfaceComponentReport> components;  // of the molecular surface; the mapped one flagged
  std::int64_t component_index = 0;                // which of them was mapped
  double surface_seconds = 0;
  std::vector<StageTime> surface_timings;  // the parts of surface_seconds (MolecularSurface::timings)
  PreparedMesh prepared;
  bool simplified = false;        // prepared.mesh is a simplification (simplify_surface) of the surface
  SimplifyReport simplification;  // when simplified
  double simplify_seconds = 0;
  SphereMap map;
  DistortionMetrics metrics;
  /// Per-vertex properties of prepared.mesh (electrostatics, hydrophobicity, ...), in the registry's order.
  std::vector<SurfaceProperty> properties;
  PropertyReport property_report;     // how they were computed (electrostatics, --values counts, warnings)
  std::vector<Atom> structure_atoms;  // a structure's atoms (what `atomid` indexes); empty for a mesh file
  double properties_seconds = 0;      // the sum of property_report.timings
  double read_seconds = 0, prepare_seconds = 0, metrics_seconds = 0;
};

/// Reads, prepares, maps and measures one input file. A structure file becomes its solvent-excluded
/// surface, of which the largest component (the outer surface; or options.prepare.component numbered k:
/// the k-th largest) is mapped after handle repair (unless keep_topology, when a surface of genus > 0 is
/// refused with its genus).
/// Throws InputError (unreadable input, bad poles or component number) or MeshRefused (a mesh that
/// cannot be mapped); a map that is not certified is returned normally (see map.certificate).
MapJobResult run_map_job(const std::filesystem::path& input, const MapJobOptions& options);

/// One input mapped with several weightings (options.map.weights is replaced by each in turn): the file
/// is read, surfaced and prepared once (each result repeats those shared timings). Results in the order
/// of `weights`. Precondition: `weights` non-empty (else std::invalid_argument). Throws as run_map_job.
std::vector<MapJobResult> run_map_jobs(const std::filesystem::path& input, const MapJobOptions& options,
                                       const std::vector<Weights>& weights);

/// A structure file's molecular surface, every closed genus-0 component mapped on its own sphere (the
/// outer surface first, then pieces and cavities by decreasing area; components of genus > 0 are listed
/// in each result's `components` but not mapped). The surface is computed once.
/// Throws InputError for a mesh file (use options.prepare.component there), and as run_map_job.
std::vector<MapJobResult> run_map_job_components(const std::filesystem::path& input, const MapJobOptions& options);

/// Same as run_map_job, from a mesh in memory (`name` is used in messages and the report).
/// Throws as run_map_job.
MapJobResult run_map_job(const Mesh& mesh, const std::string& name, const MapJobOptions& options);

/// A few lines for a terminal: sizes, repair, map, certificate, distortion, total time (not the
/// structure's warnings: the command prints them on stderr). Does not throw
/// (but std::bad_alloc).
std::string summary_text(const MapJobResult& result);

/// The files write_map_outputs writes into its folder.
inline constexpr const char* kSurfaceFile = "surface.ply";
inline constexpr const char* kSphereFile = "sphere.ply";
inline constexpr const char* kReportFile = "report.json";
inline constexpr const char* kSurfaceGlbFile = "surface.glb";  // glTF 2.0 twins of the PLY files
inline constexpr const char* kSphereGlbFile = "sphere.glb";
inline constexpr const char* kAtomsFile = "atoms.csv";        // structures: one row per atom, by `atomid`
inline constexpr const char* kResiduesFile = "residues.csv";  // structures: one row per residue
/// What the command's `map` adds beside them (render/map_pictures.hpp): the viewer and the pictures folder.
inline constexpr const char* kViewerFile = "index.html";
inline constexpr const char* kPicturesFolder = "pictures";

/// Every file name a map run may write into its folder (write_map_outputs and the outputs added to it):
/// what a new run replaces (pipeline/output_folder.hpp) and a batch clears. A new output file of the map
/// job adds its name here. Does not throw.
const std::vector<std::string>& map_output_names();

/// Writes `surface.ply`, `sphere.ply`, their glTF 2.0 twins `surface.glb` and `sphere.glb` (io/gltf.hpp:
/// COLOR_0 the PLY's colours, each property as attribute `_<NAME>`), for a structure `atoms.csv` and `residues.csv`
/// (map_tables.hpp), and `report.json` (make_report) into `directory` (created if missing), each atomically,
/// report.json last. Both PLY files have the same vertices in the same order and the same triangles, with per-vertex
/// `theta`, `phi` (double), `input_vertex`, for a structure `atomid` (int), every property as float `vertex_<name>`,
/// the vertex normal of the surface `nx ny nz` (float) and `red green blue` (uchar) of the colour property
/// (options.colour, colour_property); text provenance (atom, residue, chain names) is in atoms.csv only.
/// A mesh file's own vertex attributes are kept. Precondition: `result` and `options` are those of one
/// run_map_job*. Throws InputError if a file cannot be written or options.colour names no property;
/// the files this call wrote are removed again first (and the folder, if this call created it and it is
/// left empty): no partial output.
void write_map_outputs(const std::filesystem::path& directory, const MapJobResult& result,
                       const MapJobOptions& options);

}  // namespace spheremap
