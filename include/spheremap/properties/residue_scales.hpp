// Per-residue hydrophobicity scales (stage: properties): published tables of the twenty amino acids.
#pragma once

#include <optional>
#include <string_view>

namespace spheremap {

enum class ResidueScale {
  /// Kyte & Doolittle (1982) hydropathy index, J. Mol. Biol. 157:105-132: -4.5 (Arg) to 4.5 (Ile),
  /// dimensionless; higher is more hydrophobic. Proline -1.6.
  kKyteDoolittle,
  /// Wimley & White (1996) whole-residue interface scale ΔG(water -> POPC interface), kcal/mol, Nat. Struct.
  /// Biol. 3:842-848, with Asp, Glu, Lys, Arg charged and His neutral (ASH, GLH: the neutral forms); lower
  /// is more hydrophobic (Trp -1.85, Glu 2.02), as published.
  kWimleyWhite,
  /// Eisenberg, Schwarz, Komaromy & Wall (1984) normalized consensus scale, J. Mol. Biol. 179:125-142,
  /// dimensionless; higher is more hydrophobic (Arg -2.53, Ile 1.38).
  kEisenberg,
};

/// The standard amino acid a residue name stands for: force-field protonation variants (HID, HIE, HIP,
/// HSD, HSE, HSP -> HIS; CYX, CYM -> CYS; ASH -> ASP; GLH -> GLU; LYN -> LYS) and the name itself otherwise
/// (upper case expected). Never throws.
std::string_view standard_amino_acid(std::string_view residue_name);

/// The scale's value for a residue name (via standard_amino_acid; ASH and GLH keep their own Wimley-White
/// values), or nothing for a residue the scale does not know (modified residues such as MSE, terminal
/// patches such as NTE, nucleotides, ligands, water). Never throws.
std::optional<double> residue_scale_value(ResidueScale scale, std::string_view residue_name);

/// The smallest and largest value of the scale (the default colour range). Never throws.
std::pair<double, double> residue_scale_bounds(ResidueScale scale);

}  // namespace spheremap
