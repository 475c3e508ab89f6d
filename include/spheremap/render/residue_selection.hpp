// Residues named on the command line (`--outline A:45-60,B:12`, `locate --residue A:45`) (stage: render).
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "spheremap/render/globe.hpp"

namespace spheremap {

/// One item of a selection: residues first..last of a chain (by number, then insertion code).
struct ResidueRange {
  std::string chain;
  std::int32_t first = 0;
  std::string first_insertion;
  std::int32_t last = 0;
  std::string last_insertion;
};

/// Comma-separated items CHAIN:NUMBER[INSERTION] or CHAIN:FIRST[INSERTION]-LAST[INSERTION]; numbers may be
/// negative ("A:-3-5" is -3 to 5). E.g. "A:45-60,B:12,H:52A".
/// Throws InputError quoting the item that does not parse, or a range whose end comes before its start.
std::vector<ResidueRange> parse_residue_selection(std::string_view text);

/// Whether `residue` lies in `range`. Never throws.
bool in_range(const ResidueLabel& residue, const ResidueRange& range);

/// The residues of `globe` in any of `ranges`, as indices into globe.residues (sorted).
/// Throws InputError if the globe has no residues (a mesh file) or an item names none of its residues
/// (naming the item and the chains there are), so that a typo never outlines nothing silently.
std::vector<std::int32_t> select_residues(const Globe& globe, const std::vector<ResidueRange>& ranges,
                                          std::string_view option);

}  // namespace spheremap
