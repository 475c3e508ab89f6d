// Figure 4 of Rahi & Sharp: the histograms of octant areas and of triangle areas, and which surface is typical.
#include "spheremap/reproduction/figure4.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>

#include <fmt/format.h>

#include "spheremap/error.hpp"
#include "spheremap/geometry/vec.hpp"
#include "spheremap/io/mesh_io.hpp"

namespace spheremap {

namespace fs = std::filesystem;

Histogram octant_histogram(const std::vector<ReportSummary>& reports) {
  // Bin k is [3k - 1, 3k + 2), centred on 3k + 0.5: ..., [5, 8) centred on 6.5, [11, 14) on 12.5, ...
  auto bin_of = [](double a) { return static_cast<int>(std::floor((a + 1) / 3)); };
  int first = bin_of(6.5), last = bin_of(33.5);
  for (const auto& r : reports)
    for (const double a : r.distortion.octant_area_percent) {
      first = std::min(first, std::max(0, bin_of(a)));
      last = std::max(last, bin_of(a));
    }
  Histogram h;
  for (int k = first; k <= last + 1; ++k) h.edges.push_back(3.0 * k - 1);
  h.counts.assign(static_cast<std::size_t>(last - first + 1), 0);
  for (int k = first; k <= last; ++k) h.labels.push_back(fmt::format("{:.1f}", 3.0 * k + 0.5));
  for (const auto& r : reports)
    for (const double a : r.distortion.octant_area_percent)
      ++h.counts[static_cast<std::size_t>(std::max(0, bin_of(a)) - first)];
  return h;
}

Histogram triangle_area_histogram(const std::vector<double>& triangle_areas) {
  double total = 0;
  for (const double a : triangle_areas) total += a;
  if (triangle_areas.empty() || !(total > 0) || !std::isfinite(total))
    throw std::invalid_argument("triangle_area_histogram: no triangles, or no positive finite total area");
  const double mean = total / static_cast<double>(triangle_areas.size());
  constexpr double kWidth = 10, kOverflow = 300;
  double largest = 0;
  std::vector<double> percent;
  percent.reserve(triangle_areas.size());
  for (const double a : triangle_areas) {
    percent.push_back(100 * a / mean);
    largest = std::max(largest, percent.back());
  }
  const bool overflow = largest >= kOverflow;
  const double top = overflow ? kOverflow : std::max(230.0, kWidth * (std::floor(largest / kWidth) + 1));
  const auto regular = static_cast<int>(std::lround(top / kWidth));
  Histogram h;
  for (int k = 0; k <= regular; ++k) h.edges.push_back(kWidth * k);
  for (int k = 1; k <= regular; ++k) h.labels.push_back(fmt::format("{:.0f}", kWidth * k));
  if (overflow) {
    h.edges.push_back(std::numeric_limits<double>::infinity());
    h.labels.push_back(fmt::format("≥{:.0f}", kOverflow));
  }
  h.counts.assign(h.labels.size(), 0);
  for (const double p : percent) {
    const auto bin = std::min(static_cast<std::size_t>(std::max(0.0, std::floor(p / kWidth))), h.counts.size() - 1);
    ++h.counts[bin];
  }
  return h;
}

std::vector<double> triangle_areas_of_file(const fs::path& mesh_file) {
  const PolygonSoup soup = read_polygon_soup(mesh_file);
  std::vector<double> areas;
  areas.reserve(soup.faces.size());
  for (const auto& f : soup.faces) {
    if (f.size() != 3)
      throw InputError(fmt::format("{}: a face has {} corners; expected the triangles of a spheremap output",
                                   mesh_file.string(), f.size()));
    areas.push_back(triangle_area(soup.positions[static_cast<std::size_t>(f[0])],
                                  soup.positions[static_cast<std::size_t>(f[1])],
                                  soup.positions[static_cast<std::size_t>(f[2])]));
  }
  return areas;
}

std::size_t typical_surface(const std::vector<ReportSummary>& reports) {
  if (reports.empty()) throw std::invalid_argument("typical_surface: no records");
  std::map<std::string, std::size_t> first_of_input;
  for (std::size_t i = 0; i < reports.size(); ++i) first_of_input.emplace(reports[i].input, i);
  std::vector<std::size_t> surfaces;
  for (const auto& [input, index] : first_of_input) surfaces.push_back(index);
  std::sort(surfaces.begin(), surfaces.end(), [&](std::size_t a, std::size_t b) {
    if (reports[a].triangles != reports[b].triangles) return reports[a].triangles < reports[b].triangles;
    return reports[a].input < reports[b].input;
  });
  return surfaces[(surfaces.size() - 1) / 2];
}

}  // namespace spheremap
