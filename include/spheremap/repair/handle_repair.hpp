// The handle repair: makes the outer surface of a sampled solid genus 0 by the smallest change found.
//
// Glossary (the same words in the code, the report and the docs):
// - solid: the samples above the level, {field > level}; its contour (contour_isosurface) is the surface.
// - handle: what gives the surface genus: seen from the solid a ring to cut through, seen from the
//   outside a tunnel to fill. The outer surface (the largest component) is repaired; detached pieces and
//   cavities are left as they are.
// - growth: a topology-preserving growth of the solid (from its deepest sample) or of the outside (from
//   the grid border); the samples each leaves out lie across the handles.
// - membrane: a connected cluster of samples a growth left out: where a closure may go.
// - closure (Closure): samples moved across the level, a cut or a fill (ClosureKind).
// - per-handle repair (repair_handles -> PerHandleRepair): one round of small closures, one per handle
//   or junction of handles, chosen for the least area change.
// - global closure (close_all_handles): the fallback, one closure of everything one growth left out:
//   every handle cut, or every tunnel filled.
// - outer-genus repair (repair_outer_genus -> OuterGenusRepair): rounds of the per-handle repair until
//   the outer surface has genus 0, else the global closure; RepairMethod says which was kept.
// - On the report side (pipeline), HandleRepairReport describes an OuterGenusRepair in Å and
//   ClosureReport each of its closures.
#pragma once

#include <cstdint>
#include <optional>
#include <vector>

#include "spheremap/mesh.hpp"
#include "spheremap/repair/closure.hpp"
#include "spheremap/repair/global_closure.hpp"
#include "spheremap/repair/per_handle_repair.hpp"
#include "spheremap/surface/grid.hpp"
#include "spheremap/topology/components.hpp"

namespace spheremap {

/// How repair_outer_genus reached genus 0.
enum class RepairMethod {
  kNone,        ///< the outer surface had genus 0 already
  kPerHandle,   ///< rounds of repair_handles
  kGlobalFill,  ///< the global closure: every tunnel filled
  kGlobalCut,   ///< the global closure: every handle cut
};

/// "none", "per-handle", "fill" or "cut": the text of report.json's `topology_repair.method`.
const char* to_string(RepairMethod method);

/// What repair_outer_genus did.
struct OuterGenusRepair {
  int outer_genus_before = 0;  // genus of the largest contour component before
  RepairMethod method = RepairMethod::kNone;
  /// The closures applied: those of every round of repair_handles, in order (kPerHandle); the global
  /// closure (kGlobalFill, kGlobalCut; none if it moved no sample); none (kNone).
  std::vector<Closure> closures;
  std::int64_t samples_changed = 0;
  double area_change = 0;  // per_handle: the sum of the closures' area_change
  int rounds = 0;          // rounds of repair_handles until the outer surface had genus 0 (kPerHandle)
  /// mesh_components of the final contour, when the overload that returns that contour computed them on
  /// the way (a kPerHandle repair): a caller need not compute them again.
  std::optional<std::vector<MeshComponent>> final_components;
};

/// Makes the largest component of the contour {field = level} (the outer surface of a molecule) genus 0
/// with the smallest change we can find: repair_handles (asked for the outer genus), checked by
/// contouring, repeated on the changed field (asked for the genus left) while it still changes something
/// (at most 4 rounds); if the largest component still has handles, the field is restored and
/// close_all_handles applied (always genus 0, one component). Other components (detached pieces,
/// cavities) are left as they are by the per-handle repair. Modifies `field`. `threads` is passed to
/// contour_isosurface and the growths; the result does not depend on it.
/// Preconditions and throws: as close_all_handles (when the outer surface has handles).
OuterGenusRepair repair_outer_genus(Grid3<double>& field, double level, int threads = 0);
OuterGenusRepair repair_outer_genus(Grid3<float>& field, double level, int threads = 0);

/// The same, for a caller that already knows the genus of the largest component of the field's contour
/// (`outer_genus_before` >= 0) and wants the contour of the field as repaired: `final_contour` receives
/// it (contour_isosurface(field, level, threads, minimum_fraction)), so that no contour is computed twice.
OuterGenusRepair repair_outer_genus(Grid3<float>& field, double level, int outer_genus_before, int threads,
                                    double minimum_fraction, Mesh& final_contour);

}  // namespace spheremap
