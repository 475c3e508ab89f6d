// The three hydrophobicity tables, transcribed from their papers (references in residue_scales.hpp and
// docs/properties.md).
#include "spheremap/properties/residue_scales.hpp"

#include <algorithm>
#include <array>
#include <utility>

namespace spheremap {
namespace {

struct Entry {
  std::string_view residue;
  double kyte_doolittle, wimley_white, eisenberg;
};

constexpr std::array<Entry, 22> kTable{{
    {"ALA", 1.8, 0.17, 0.62},
    {"ARG", -4.5, 0.81, -2.53},
    {"ASN", -3.5, 0.42, -0.78},
    {"ASP", -3.5, 1.23, -0.90},
    {"CYS", 2.5, -0.24, 0.29},
    {"GLN", -3.5, 0.58, -0.85},
    {"GLU", -3.5, 2.02, -0.74},
    {"GLY", -0.4, 0.01, 0.48},
    {"HIS", -3.2, 0.17, -0.40},
    {"ILE", 4.5, -0.31, 1.38},
    {"LEU", 3.8, -0.56, 1.06},
    {"LYS", -3.9, 0.99, -1.50},
    {"MET", 1.9, -0.23, 0.64},
    {"PHE", 2.8, -1.13, 1.19},
    {"PRO", -1.6, 0.45, 0.12},
    {"SER", -0.8, 0.13, -0.18},
    {"THR", -0.7, 0.14, -0.05},
    {"TRP", -0.9, -1.85, 0.81},
    {"TYR", -1.3, -0.94, 0.26},
    {"VAL", 4.2, 0.07, 1.08},
    // Neutral aspartate and glutamate: their own Wimley-White values; the other scales as ASP and GLU.
    {"ASH", -3.5, -0.07, -0.90},
    {"GLH", -3.5, -0.01, -0.74},
}};

constexpr std::array<std::pair<std::string_view, std::string_view>, 11> kVariants{{
    {"HID", "HIS"},
    {"HIE", "HIS"},
    {"HIP", "HIS"},
    {"HSD", "HIS"},
    {"HSE", "HIS"},
    {"HSP", "HIS"},
    {"CYX", "CYS"},
    {"CYM", "CYS"},
    {"ASH", "ASP"},
    {"GLH", "GLU"},
    {"LYN", "LYS"},
}};

double value_of(const Entry& e, ResidueScale scale) {
  switch (scale) {
    case ResidueScale::kKyteDoolittle: return e.kyte_doolittle;
    case ResidueScale::kWimleyWhite: return e.wimley_white;
    case ResidueScale::kEisenberg: return e.eisenberg;
  }
  return e.kyte_doolittle;
}

const Entry* find(std::string_view residue) {
  for (const Entry& e : kTable)
    if (e.residue == residue) return &e;
  return nullptr;
}

}  // namespace

std::string_view standard_amino_acid(std::string_view residue_name) {
  for (const auto& [variant, standard] : kVariants)
    if (variant == residue_name) return standard;
  return residue_name;
}

std::optional<double> residue_scale_value(ResidueScale scale, std::string_view residue_name) {
  const Entry* entry = scale == ResidueScale::kWimleyWhite ? find(residue_name) : nullptr;
  if (entry == nullptr) entry = find(standard_amino_acid(residue_name));
  if (entry == nullptr) return std::nullopt;
  return value_of(*entry, scale);
}

std::pair<double, double> residue_scale_bounds(ResidueScale scale) {
  double lo = value_of(kTable.front(), scale), hi = lo;
  for (const Entry& e : kTable) lo = std::min(lo, value_of(e, scale)), hi = std::max(hi, value_of(e, scale));
  return {lo, hi};
}

}  // namespace spheremap
