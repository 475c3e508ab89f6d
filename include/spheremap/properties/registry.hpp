// The property registry (stage: properties): every surface property spheremap computes, by name, with its
// unit and colour scale, and the one function that computes them for a mapped surface. Every output (PLY,
// glTF, atoms.csv, residues.csv, report.json, pictures, viewer) shows what compute_properties returns, in
// the registry's order.
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "spheremap/mesh.hpp"
#include "spheremap/molecule/structure.hpp"
#include "spheremap/properties/electrostatics.hpp"
#include "spheremap/properties/property.hpp"
#include "spheremap/properties/values_file.hpp"
#include "spheremap/timing.hpp"

namespace spheremap {

/// The names of the built-in properties (PLY property `vertex_<name>`, glTF attribute `_<NAME>`).
namespace property_names {
inline constexpr const char* kElectrostatics = "electrostatics";
inline constexpr const char* kHydrophobicity = "hydrophobicity";
inline constexpr const char* kWimleyWhite = "wimley_white";
inline constexpr const char* kEisenberg = "eisenberg";
inline constexpr const char* kSequencePosition = "sequence_position";
inline constexpr const char* kResidueNumber = "residue_number";
inline constexpr const char* kChainIndex = "chain_index";
inline constexpr const char* kBFactor = "b_factor";
inline constexpr const char* kCharge = "charge";
inline constexpr const char* kShapeIndex = "shape_index";
inline constexpr const char* kCurvedness = "curvedness";
inline constexpr const char* kAreaDistortion = "area_distortion";
inline constexpr const char* kOctant = "octant";
}  // namespace property_names

/// What a property is computed from.
enum class PropertyBasis {
  kStructure,  // the atoms of a structure file (a mesh file has none)
  kSurface,    // the mapped surface's shape
  kMap,        // the sphere map
};

struct PropertyDefinition {
  PropertyInfo info;
  PropertyBasis basis = PropertyBasis::kStructure;
  /// Per atom (hydrophobicity, B-factor, ...: each vertex takes its atom's value, and atoms.csv lists it), or
  /// per vertex (electrostatics, shape, map).
  bool per_atom = false;
  std::string description;  // one sentence: definition, unit, source (docs/properties.md has the details)
};

/// The built-in properties in their order (the order of every output). Never throws.
const std::vector<PropertyDefinition>& property_registry();

/// The built-in property of that name, or null (a --values column is not built in: its PropertyInfo is in the
/// SurfaceProperty, and report.json's `properties` block has its unit and scale). Never throws.
const PropertyDefinition* find_property_definition(std::string_view name);
/// find_property_definition(name)->info, or null. Never throws.
const PropertyInfo* find_property(std::string_view name);

struct PropertyOptions {
  /// --properties: the properties to compute, by name (built-in names and --values columns); unset: all that
  /// apply to the input.
  std::optional<std::vector<std::string>> only;
  /// The map job's default charges: a PQR input's own, else the formal table (no external program).
  ElectrostaticsOptions electrostatics = [] {
    ElectrostaticsOptions e;
    e.charges = ChargeChoice::kInputOrFormal;
    return e;
  }();
  std::vector<std::filesystem::path> values_files;  // --values, each a table of value columns
  ProgressCallback progress;                        // hears what pdb2pqr and APBS do; may be null
};

/// What the properties of one surface are computed from.
struct PropertyInputs {
  const Mesh* surface = nullptr;              // the mapped mesh; `atomid` (index into atoms) from a structure
  const std::vector<Atom>* atoms = nullptr;   // the structure's atoms; null for a mesh file
  std::filesystem::path structure_file;       // the structure file (a PQR gives its own charges)
  const std::vector<Vec3>* sphere = nullptr;  // the map (unit vectors); null: map properties are left out
};

/// How the electrostatic potential was computed (report.json's `properties.electrostatics`).
struct ElectrostaticsDetails {
  ElectrostaticsMethod method = ElectrostaticsMethod::kCoulomb;
  std::string charges;  // the charges' source ("formal", "pdb2pqr (AMBER)", "PQR file.pqr"); empty for a map
  std::optional<ForceField> force_field;  // pdb2pqr's (pdb2pqr charges and APBS)
  double temperature = 0, offset = 0;
  std::string dielectric;               // "4r" or a constant ("80"); APBS: "pdie 2, sdie 78.54"
  std::filesystem::path potential_map;  // --potential-map
  std::optional<double> net_charge;     // e, of the charges summed
  std::int64_t atoms_charged = 0, atoms_unmatched = 0, added_atoms = 0, added_hydrogens = 0;
};

/// Residues that no hydrophobicity table knows (MSE, NTE, nucleotides, ligands): their vertices get NaN.
struct UnknownResidues {
  std::int64_t residues = 0;       // residues (of the structure) whose name no table knows
  std::vector<std::string> names;  // their distinct names, sorted
};

/// A per-atom property's values for atoms.csv.
struct AtomProperty {
  std::string name;
  std::vector<double> values;  // per atom of the structure
};

/// What the report says about the properties of one surface, beyond their values.
struct PropertyReport {
  std::vector<AtomProperty> atom_properties;  // the per-atom properties, in the order of the properties
  std::optional<ElectrostaticsDetails> electrostatics;
  UnknownResidues unknown_residues;
  std::vector<AtomValues> values;  // per --values column: rows, unmatched rows, atoms without a value
  std::vector<std::string> warnings;
  std::vector<StageTime> timings;  // seconds per property (shape_index and curvedness together, as "shape")
};

/// The properties of one surface: values per vertex, registry order, then the --values columns in file order.
struct PropertySet {
  std::vector<SurfaceProperty> properties;
  PropertyReport report;
};

/// The properties that apply to `inputs` and that options.only selects: structure properties when atoms are
/// given, surface properties always, map properties when the sphere is given. NaN where a vertex has no value.
/// Preconditions: inputs.surface set; inputs.sphere (if set) of one point per vertex; with atoms, `atomid` on
/// every vertex indexes them. Throws InputError for a name in options.only that is neither built in nor a
/// --values column, a values column named like a built-in property, and as read_values_file, match_values and
/// surface_electrostatics do; std::invalid_argument when a precondition fails.
PropertySet compute_properties(const PropertyInputs& inputs, const PropertyOptions& options);

/// Adds the map properties (area_distortion, octant) selected by options.only to a set computed without the
/// sphere, in registry order, as if compute_properties had been given the sphere. Throws as compute_properties.
void add_map_properties(PropertySet& set, const Mesh& surface, const std::vector<Vec3>& sphere,
                        const PropertyOptions& options);

/// The property the vertex colours (PLY red green blue, glTF COLOR_0) show: `requested` if not empty, else
/// electrostatics when it was computed, else hydrophobicity, else octant, else the first property; null when
/// there is none. Throws InputError when `requested` names no property of the list (naming those there are).
const SurfaceProperty* colour_property(const std::vector<SurfaceProperty>& properties, const std::string& requested);

/// The colour range of a property on its surface: its default range, else the range of its values
/// (data_range). Never throws.
ValueRange colour_range(const SurfaceProperty& property);

}  // namespace spheremap
