// Removing handles from a sampled solid so that its contour has genus 0 (stage: surface).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "spheremap/mesh.hpp"
#include "spheremap/surface/contour.hpp"
#include "spheremap/surface/grid.hpp"
#include "spheremap/topology/components.hpp"

namespace spheremap {

struct HandleCut {
  bool filled = false;                        // true: tunnels were filled; false: handles were cut
  std::int64_t samples_removed = 0;           // samples whose side changed
  std::vector<std::int64_t> removed_samples;  // their grid indices, ascending
  double area_change = 0;                     // change of the contour's area (all components), area units of the grid
};

/// Makes the solid {field > level} a topological ball, as seen by contour_isosurface (the Freudenthal
/// triangulation of the grid), by topology-preserving growth (Kriegeskorte & Goebel 2001; Han, Xu &
/// Prince 2002) in two ways, keeping the one that changes fewer samples:
/// - cut: grow a set from the deepest inside sample of the largest inside piece, adding inside samples
///   by decreasing value only when simple — their link (14 lattice neighbours, a triangulated sphere)
///   meets the set in a non-empty connected part whose complement in the link is non-empty and
///   connected (for a full subcomplex of a 2-sphere this is contractibility, by Alexander duality), so
///   the set stays a ball; inside samples never added (where a loop would close) go half a grid step
///   below `level`; other pieces too;
/// - fill: the same growth of the outside from the whole grid border, by decreasing distance to the
///   solid; outside samples never added (spanning tunnels, and cavities) go half a grid step above
///   `level` (half a step, not just past it, so that a change one sample thick contours to two faces
///   clear of each other).
/// Preconditions: some sample > level, every border sample <= level. Throws std::invalid_argument
/// otherwise. Returns what changed (area_change as contour_isosurface(field, level, threads,
/// minimum_fraction) measures it); modifies `field`.
/// Both growths take samples from bucket queues: the solid by its value in steps of 1/256 of the grid
/// spacing, the outside by its squared lattice distance to the solid (exact below 65535 steps², capped
/// there); within a bucket the first offered first. Memory: one byte of state per sample, plus (while
/// the growths run) two bytes of distance per sample, plus the queues (4 bytes per queued sample).
/// `threads` (0: one per hardware thread) is used for the distance, and with two or more the two
/// growths run at once on two threads; the result does not depend on it.
HandleCut cut_handles(Grid3<double>& field, double level, double minimum_fraction = kContourMinimumFraction, int threads = 0);
HandleCut cut_handles(Grid3<float>& field, double level, double minimum_fraction = kContourMinimumFraction, int threads = 0);

/// One local change of a per-handle repair: a connected set of samples moved to the other side.
struct TopologyChange {
  bool filled = false;                // true: a tunnel spanned (outside samples made inside); false: a handle cut
  std::vector<std::int64_t> samples;  // grid indices, ascending
  std::vector<double> original_values;  // the field at `samples` before the change (for undo)
  int euler_change = 0;               // change of the solid's Euler characteristic (handles removed)
  /// Change of the contour's area (all components) that this change made, on the field as it was when
  /// it was applied (changes are applied in order): the changes' areas add up to the contour's change.
  double area_change = 0;
};

struct HandleRepair {
  std::vector<TopologyChange> changes;  // in the order applied
  std::int64_t samples_changed = 0;
  double area_change = 0;               // the sum of the changes' area_change
};

/// Removes the handles of the solid's main piece (the largest inside piece, as cut_handles grows it) by
/// small local changes, each a cut of a handle or a fill of a tunnel, chosen to change the least contour
/// area. Both growths of cut_handles are computed; the samples each leaves out (cut membranes of handles,
/// fill membranes of tunnels, whole detached pieces and cavities) are split into connected clusters on
/// the Freudenthal lattice. A cluster that touches the main piece and raises the Euler characteristic of
/// the solid (the full subcomplex on inside samples, counted exactly on the 14-neighbour lattice) removes
/// handles; pieces, cavities and membranes across tunnels of detached pieces are left alone.
/// - Each such membrane moves to the section of its handle or tunnel with the fewest samples within 4 Å
///   (a minimum vertex cut, by max-flow, between the far ends of its sides; for a cluster where several
///   membranes meet, the union of the cuts isolating each side), when that changes less |area|, removes
///   at least as many handles and stays apart from the other clusters of its side.
/// - A cut and a fill that touch may remove the same handle twice (after one, the other no longer raises
///   the Euler characteristic as much). Clusters of one side never touch, so the Euler change of any set
///   of clusters is its clusters' own plus these pairwise losses. The set chosen removes the handles left
///   (`handles_to_remove`, or as many as possible) at the least total |area change|: each cluster is worth
///   handles x price - |area|, a chosen pair loses its lost handles x price, the best set for a price is
///   a minimum cut (submodular), and the price is the smallest for which that set removes every handle
///   (binary search), so that no expensive change is bought for a count beyond the genus, which only
///   enclosed voids or split-off pieces can make up.
/// - Chosen clusters are applied cheapest first, each only if it still raises the Euler characteristic on
///   the field as it then is and does not split off a piece or close a pocket into a void (which raises
///   it too, but removes no handle; searched breadth first up to 500 Å³ of samples around the change),
///   until `handles_to_remove` are removed; the others complete the count if a chosen one did not.
/// A change that splits off a larger piece also raises the Euler characteristic: the caller must check
/// the genus of the result (repair_outer_genus does, and repeats) and fall back to cut_handles
/// (undo_handle_repair restores the field). Areas as contour_isosurface(field, level, threads,
/// minimum_fraction) measures them. Same preconditions and throws as cut_handles. Memory: as
/// cut_handles, plus the clusters and, per moved membrane, about 20 bytes per sample of a box around it
/// (boxes above 4M samples are not searched), for each of up to `threads` membranes searched at once.
/// Deterministic; independent of `threads`.
HandleRepair repair_handles(Grid3<double>& field, double level, double minimum_fraction = kContourMinimumFraction, int threads = 0,
                            int handles_to_remove = -1);
HandleRepair repair_handles(Grid3<float>& field, double level, double minimum_fraction = kContourMinimumFraction, int threads = 0,
                            int handles_to_remove = -1);

/// Restores the field values a repair changed.
void undo_handle_repair(Grid3<double>& field, const HandleRepair& repair);
void undo_handle_repair(Grid3<float>& field, const HandleRepair& repair);

}  // namespace spheremap

namespace spheremap {

/// What repair_outer_genus did.
struct GenusRepair {
  int outer_genus_before = 0;     // genus of the largest contour component before
  std::string method = "none";    // "none", "per-handle", or the fallback "fill" / "cut" (cut_handles)
  HandleRepair per_handle;        // the changes, when method == "per-handle"
  HandleCut global;               // when method is "fill" or "cut"
  std::int64_t samples_changed = 0;
  int rounds = 0;                 // rounds of repair_handles until the outer surface had genus 0 ("per-handle")
  /// mesh_components of the final contour, when the overload that returns that contour computed them on
  /// the way (a "per-handle" repair): a caller need not compute them again.
  std::optional<std::vector<MeshComponent>> final_components;
};

/// Makes the largest component of the contour {field = level} (the outer surface of a molecule) genus 0
/// with the smallest change we can find: repair_handles (asked for the outer genus), checked by
/// contouring, repeated on the changed field (asked for the genus left) while it still changes something
/// (at most 4 rounds); if the largest component still has handles, the field is restored and cut_handles
/// applied (always genus 0, one component). Other components (detached pieces, cavities) are left as they
/// are by the per-handle repair. Same preconditions and throws as cut_handles. `threads` is passed to
/// contour_isosurface and the growths; the result does not depend on it.
GenusRepair repair_outer_genus(Grid3<double>& field, double level, int threads = 0);
GenusRepair repair_outer_genus(Grid3<float>& field, double level, int threads = 0);

/// The same, for a caller that already knows the genus of the largest component of the field's contour
/// (`outer_genus_before` >= 0) and wants the contour of the field as repaired: `final_contour` receives
/// it (contour_isosurface(field, level, threads, minimum_fraction)), so that no contour is computed twice.
GenusRepair repair_outer_genus(Grid3<float>& field, double level, int outer_genus_before, int threads,
                               double minimum_fraction, Mesh& final_contour);

}  // namespace spheremap
