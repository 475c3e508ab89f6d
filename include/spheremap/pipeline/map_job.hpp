// The `map` job end to end: file -> prepared mesh -> sphere map -> metrics -> outputs.
#pragma once

#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "spheremap/metrics/distortion.hpp"
#include "spheremap/molecule/structure.hpp"
#include "spheremap/surface/ses.hpp"
#include "spheremap/sphere/map.hpp"
#include "spheremap/topology/components.hpp"
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
  /// triangles of about target_edge_length): a molecular surface always (a 0.5 Å grid gives about 20
  /// times more triangles than a map needs), a mesh file only when simplify_mesh_files is true.
  /// The defaults (target edge 1, tolerance 0.1) are meant for Å; target_edge_length = 0 maps the surface
  /// as it is. For a mesh file, user-given poles are kept.
  SimplifyOptions simplify;
  bool simplify_mesh_files = false;
};

/// One handle or tunnel the repair removed.
struct HandleChangeReport {
  std::string kind;              // "cut" (a handle cut through) or "fill" (a tunnel spanned)
  std::int64_t samples = 0;      // grid samples moved to the other side
  double volume = 0;             // Å³ (samples x grid³): removed by a cut, added by a fill
  /// Å², what this change did to the area of the contour (every component, almost always the outer
  /// surface), on the field as it was when applied: the changes add up to the surface's area change.
  double area_change = 0;
  int handles_removed = 0;       // 1, or more for a change that spans several handles at once
  Vec3 centre{};                 // mean position of the samples
  std::vector<std::string> lining_residues;  // "chain:NAMEnumber[icode]", nearest atoms of the samples, sorted
};

/// What the handle repair of a molecular surface changed (all zero when nothing was needed).
struct TopologyRepair {
  int genus_before = 0;           // of the outer surface before repair (also with --keep-topology)
  /// "none"; "per-handle" (each handle cut or each tunnel filled, whichever is smaller); or, when that
  /// does not reach genus 0, the global fallback "fill" (every tunnel filled) or "cut" (every handle cut).
  std::string method = "none";
  /// Rounds of the per-handle repair, each a pair of growths over the whole grid (another one when a
  /// round left handles: a change that split off a piece larger than the repair's search counts like a
  /// handle removed, and the clusters not chosen may not stand in for a change skipped); 0 for "none"
  /// and for the global fallback.
  int rounds = 0;
  std::int64_t samples_changed = 0;
  double volume_changed = 0;      // Å³ (samples changed x grid³)
  double area_before = 0, area_after = 0;  // Å², of the outer surface (the largest component)
  std::vector<HandleChangeReport> changes;  // per handle ("per-handle"), or one entry for a global fallback
};

/// One closed component of a molecular surface.
struct SurfaceComponentReport {
  std::string kind;  // "outer" (the largest), "piece" (a detached part), "cavity" (an enclosed void)
  std::int64_t vertices = 0, triangles = 0;
  double area = 0;    // Å²
  double volume = 0;  // Å³ enclosed (a cavity's void volume, positive)
  int genus = 0;
  bool mapped = false;
  std::vector<std::string> residues;  // residues of the atoms nearest its vertices, sorted (at most 200)
  std::int64_t residue_count = 0;     // all of them
};

/// A molecular surface with its components analysed.
struct MolecularSurface {
  Mesh mesh;  // every component, with atom provenance
  std::vector<Atom> atoms;  // the atoms it was made of (what `atomid` indexes)
  std::vector<MeshComponent> components;          // largest area first
  std::vector<SurfaceComponentReport> reports;    // same order
  std::vector<StageTime> timings;                 // wall-clock seconds of its stages ("field", "contour", ...)
};

/// True for the extensions read_structure reads.
bool is_structure_file(const std::filesystem::path& path);

/// The solvent-excluded surface of a structure file, every component, with atom provenance attributes.
/// Throws InputError as read_structure and solvent_excluded_field do.
Mesh molecular_surface(const std::filesystem::path& path, const StructureOptions& structure,
                       const SurfaceOptions& surface, StructureReport* report = nullptr);

/// Atoms to their SES with full atom provenance (add_atom_provenance), the outer surface (largest
/// component) repaired to genus 0 by repair_outer_genus unless keep_topology; components analysed.
/// With full_provenance false, vertices get only the integer attributes of add_nearest_atoms (`atomid`
/// and the others): the text ones cost time and memory on millions of vertices, and a caller that
/// simplifies the surface first adds them to what it keeps (add_atom_provenance).
/// Throws InputError as solvent_excluded_field does.
MolecularSurface repaired_surface(const std::vector<Atom>& atoms, const SurfaceOptions& surface, bool keep_topology,
                                  TopologyRepair* repair, bool full_provenance = true);

struct MapJobResult {
  std::filesystem::path input;
  bool from_structure = false;  // the mesh is the molecular surface of a structure file
  std::int64_t atoms = 0;
  StructureReport structure;
  TopologyRepair topology;
  std::vector<SurfaceComponentReport> components;  // of the molecular surface; the mapped one flagged
  std::int64_t component_index = 0;                // which of them was mapped
  double surface_seconds = 0;
  std::vector<StageTime> surface_timings;  // the parts of surface_seconds (MolecularSurface::timings)
  PreparedMesh prepared;
  bool simplified = false;          // prepared.mesh is a simplification (simplify_surface) of the surface
  SimplifyReport simplification;    // when simplified
  double simplify_seconds = 0;
  SphereMap map;
  DistortionMetrics metrics;
  double read_seconds = 0, prepare_seconds = 0, metrics_seconds = 0;
};

/// Reads, prepares, maps and measures. A structure file becomes its solvent-excluded surface, of which
/// the largest component (the outer surface; or options.prepare.component = k: the k-th largest) is
/// mapped after handle repair (unless keep_topology, when a
/// surface of genus > 0 is refused with its genus). Throws InputError (unreadable input) or MeshRefused (a mesh that
/// cannot be mapped); a map that is not certified is returned normally (see map.certificate).
MapJobResult run_map_job(const std::filesystem::path& input, const MapJobOptions& options);

/// One input mapped with several weightings (options.map.weights is replaced by each in turn): the file
/// is read, surfaced and prepared once (each result repeats those shared timings). Results in the order of
/// `weights`; the same throws as run_map_job,
/// and std::invalid_argument if `weights` is empty.
std::vector<MapJobResult> run_map_jobs(const std::filesystem::path& input, const MapJobOptions& options,
                                       const std::vector<Weights>& weights);

/// A structure file's molecular surface, every closed genus-0 component mapped on its own sphere (the
/// outer surface first, then pieces and cavities by decreasing area; components of genus > 0 are listed
/// in each result's `components` but not mapped). The surface is computed once. Throws InputError for a
/// mesh file (use prepare options there), and as run_map_job.
std::vector<MapJobResult> run_map_job_components(const std::filesystem::path& input, const MapJobOptions& options);

/// Same, from a mesh in memory (`name` is used in messages and the report).
MapJobResult run_map_job(const Mesh& mesh, const std::string& name, const MapJobOptions& options);

/// The report as JSON (every figure defined in the README).
nlohmann::json make_report(const MapJobResult& result, const MapJobOptions& options);

/// A few lines for a terminal.
std::string summary_text(const MapJobResult& result);

/// Writes `surface.ply`, `sphere.ply` and `report.json` into `directory` (created if missing), each
/// atomically. Both PLY files have the same vertices in the same order and the same triangles, with
/// per-vertex `theta`, `phi` and `input_vertex` (index in the input file) plus the input's attributes.
/// Throws InputError if a file cannot be written.
void write_map_outputs(const std::filesystem::path& directory, const MapJobResult& result,
                       const MapJobOptions& options);

}  // namespace spheremap
