// The text tables of a structure's map (stage: pipeline): atoms.csv (what `atomid` indexes: the names the PLY
// files no longer carry, and the per-atom property values) and residues.csv (per residue: the area it owns
// on the surface and on the sphere, and the area-weighted mean of every property). RFC 4180, UTF-8.
#pragma once

#include <string>
#include <vector>

#include "spheremap/pipeline/map_job.hpp"

namespace spheremap {

/// atoms.csv: header `atomid,serial,model,chain,residue_number,insertion_code,residue_name,atom_name,element,
/// x,y,z,radius`, then one column per per-atom property (result.property_report.atom_properties) but
/// residue_number and chain_index (the columns residue_number and chain say it); one row per
/// atom of result.structure_atoms, row k for `atomid` k. Empty cells: no value. Never throws (but bad_alloc).
std::string atoms_csv(const MapJobResult& result);

/// Per residue of result.structure_atoms (file order): the area its vertices own, a third of each incident
/// triangle's, on the mapped surface (Å² for a structure) and on the unit sphere (steradians: the triangles'
/// solid angles), and the area-weighted mean of each property over its vertices (NaN values left out; a value
/// equal on all of them is the mean exactly).
struct ResidueAreas {
  std::vector<double> surface_area, sphere_area;  // per residue
  std::vector<std::vector<double>> means;         // [property][residue], NaN where the residue has no value
};

/// Precondition: result.prepared.mesh has `atomid` indexing result.structure_atoms (a structure's map).
/// Never throws (but bad_alloc).
ResidueAreas residue_areas(const MapJobResult& result);

/// residues.csv: `chain,residue_number,insertion_code,residue_name,surface_area,sphere_area`, then
/// `mean_<property>` per property but the categorical ones and residue_number, one row per residue (residues
/// with no vertex: area 0, means empty).
/// Never throws (but bad_alloc).
std::string residues_csv(const MapJobResult& result);

}  // namespace spheremap
