// The data of the paper's Figure 4 (stage: reproduction): the histogram of octant areas (4a) and of the
// triangle areas of a typical surface (4b). Drawn by render/figure4.hpp.
#pragma once

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "spheremap/pipeline/report.hpp"

namespace spheremap {

/// A histogram with its bins as chart categories.
struct Histogram {
  std::vector<double> edges;         // bins [edges[i], edges[i+1]); the last one may be +inf (overflow)
  std::vector<std::int64_t> counts;  // one per bin
  std::vector<std::string> labels;   // one per bin, as drawn under the bar
};

/// Figure 4a: octant areas (%) of every report in `reports` (8 each), in bins 3% wide centred on
/// 12.5 ± 3k like the paper's (labelled by their centres: ..., 6.5, 9.5, 12.5, ...), from the bin of
/// the smallest value (at least [-1, 2)) to that of the largest, and at least 5-8 to 32-35 % as in the
/// paper. Does not throw (but std::bad_alloc).
Histogram octant_histogram(const std::vector<ReportSummary>& reports);

/// Figure 4b: each triangle's area as % of the surface's mean triangle area, in bins 10% wide labelled by
/// their upper edge as in the paper (the bar "10" holds [0, 10) %), up to 230% or beyond to the largest
/// value, with one overflow bar "≥300" when a value reaches 300%.
/// Precondition: areas non-empty with a positive finite sum; throws std::invalid_argument otherwise.
Histogram triangle_area_histogram(const std::vector<double>& triangle_areas);

/// The areas of the triangles of a mesh file (polygons must be triangles). Throws InputError as
/// read_polygon_soup does, or if a face is not a triangle.
std::vector<double> triangle_areas_of_file(const std::filesystem::path& mesh_file);

/// The surface Figure 4b shows: among the distinct inputs (the first report of each, in the order
/// given), the one with the median triangle count (ties by input name; with an even count the lower of
/// the two middle ones). Returns the index of its report. Throws std::invalid_argument if `reports` is
/// empty.
std::size_t typical_surface(const std::vector<ReportSummary>& reports);

}  // namespace spheremap
