// The molecular-surface stage of a map job (stage: pipeline): structure file -> atoms -> solvent-excluded
// surface -> handle repair of the outer surface -> components described for the report.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "spheremap/geometry/vec.hpp"
#include "spheremap/mesh.hpp"
#include "spheremap/molecule/structure.hpp"
#include "spheremap/repair/handle_repair.hpp"
#include "spheremap/sphere/map.hpp"
#include "spheremap/surface/ses.hpp"
#include "spheremap/topology/components.hpp"

namespace spheremap {

/// One closure of the handle repair (a handle cut or a tunnel filled), for the report.
struct ClosureReport {
  ClosureKind kind = ClosureKind::kCut;  // to_string: "cut" (a handle cut through) or "fill" (a tunnel spanned)
  std::int64_t samples = 0;              // grid samples moved to the other side
  double volume = 0;                     // Å³ (samples x grid³): removed by a cut, added by a fill
  /// Å², what this change did to the area of the contour (every component, almost always the outer
  /// surface), on the field as it was when applied: the changes add up to the surface's area change.
  double area_change = 0;
  int handles_removed = 0;                   // 1, or more for a change that spans several handles at once
  Vec3 centre{};                             // mean position of the samples
  std::vector<std::string> lining_residues;  // "chain:NAMEnumber[icode]", nearest atoms of the samples, sorted
};

/// What the handle repair of a molecular surface changed (all zero when nothing was needed): an
/// OuterGenusRepair in Å, for the report.
struct HandleRepairReport {
  int genus_before = 0;  // of the outer surface before repair (also with --keep-topology)
  /// kNone; kPerHandle (each handle cut or each tunnel filled, whichever is smaller); or, when that does
  /// not reach genus 0, the global closure kGlobalFill (every tunnel filled) or kGlobalCut (every handle cut).
  RepairMethod method = RepairMethod::kNone;
  /// Rounds of the per-handle repair, each a pair of growths over the whole grid (another one when a
  /// round left handles: a change that split off a piece larger than the repair's search counts like a
  /// handle removed, and the clusters not chosen may not stand in for a change skipped); 0 for "none"
  /// and for the global fallback.
  int rounds = 0;
  std::int64_t samples_changed = 0;
  double volume_changed = 0;               // Å³ (samples changed x grid³)
  double area_before = 0, area_after = 0;  // Å², of the outer surface (the largest component)
  std::vector<ClosureReport> closures;     // per handle (kPerHandle), or one for the global closure
};

/// What a closed component of a molecular surface is.
enum class SurfaceComponentKind {
  kOuter,   // the largest component: the outer surface
  kPiece,   // a detached part (positive enclosed volume)
  kCavity,  // an enclosed void (negative enclosed volume)
};
/// "outer", "piece", "cavity": the text of the report's components[].kind.
const char* to_string(SurfaceComponentKind kind);

/// One closed component of a molecular surface.
struct SurfaceComponentReport {
  SurfaceComponentKind kind = SurfaceComponentKind::kOuter;
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
  Mesh mesh;                // every component, with atom provenance
  std::vector<Atom> atoms;  // the structure's atoms (what `atomid` indexes); those of radius 0 made no surface
  std::vector<MeshComponent> components;        // largest area first
  std::vector<SurfaceComponentReport> reports;  // same order
  std::vector<StageTime> timings;               // wall-clock seconds of its stages ("field", "contour", ...)
};

/// True for the extensions read_structure reads (.pdb .ent .cif .mmcif .pqr, any case, optionally .gz).
/// Looks at the name only; does not throw.
bool is_structure_file(const std::filesystem::path& path);

/// The solvent-excluded surface of a structure file, every component, with atom provenance attributes
/// (no handle repair: see repaired_surface); atoms of radius 0 make no surface. Fills `report` when given.
/// Throws InputError as read_structure and solvent_excluded_field do.
Mesh molecular_surface(const std::filesystem::path& path, const StructureOptions& structure,
                       const SurfaceOptions& surface, StructureReport* report = nullptr);

/// Atoms to their SES with full atom provenance (add_atom_provenance), the outer surface (largest
/// component) repaired to genus 0 by repair_outer_genus unless keep_topology; components analysed. Atoms of
/// radius 0 (a PQR's hydrogens) make no surface: `atomid` indexes `atoms` all the same.
/// What the repair did goes to `*repair` when given.
/// With full_provenance false, vertices get only the integer attributes of add_nearest_atoms (`atomid`
/// and the others): the text ones cost time and memory on millions of vertices, and a caller that
/// simplifies the surface first adds them to what it keeps (add_atom_provenance).
/// Preconditions: atoms non-empty, radii >= 0, at least one positive (as read_structure gives them).
/// Throws InputError as solvent_excluded_field does (e.g. a grid too large for the memory budget).
MolecularSurface repaired_surface(const std::vector<Atom>& atoms, const SurfaceOptions& surface, bool keep_topology,
                                  HandleRepairReport* repair, bool full_provenance = true);

}  // namespace spheremap
