// Van der Waals radii of atoms by element (stage: molecule).
#pragma once

#include <filesystem>
#include <map>
#include <optional>
#include <string>

namespace spheremap {

/// The radius (Å) read_structure gives an element that neither the Bondi table nor a radius table lists.
inline constexpr double kUnknownElementRadius = 1.8;

/// Bondi (1964) van der Waals radius of an element symbol (any case), if tabulated. Never throws.
std::optional<double> bondi_radius(const std::string& element);

/// Reads a radius table: one "ELEMENT RADIUS" pair per line, '#' starts a comment.
/// Throws InputError naming the file and line on a malformed line or a radius outside (0, 10] Å.
std::map<std::string, double> load_radius_table(const std::filesystem::path& path);

}  // namespace spheremap
