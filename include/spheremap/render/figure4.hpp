// The paper's Figure 4 as bar charts (stage: render), from the histograms of reproduction/figure4.hpp.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "spheremap/render/plot.hpp"
#include "spheremap/reproduction/figure4.hpp"

namespace spheremap {

/// Figure 4a as a chart: `histogram` from octant_histogram of the `surfaces` runs with `weights`.
/// Does not throw (but std::bad_alloc); drawing it throws as lay_out_bar_chart.
BarChart figure4a_chart(const Histogram& histogram, const std::string& weights, std::int64_t surfaces);

/// Figure 4b as a chart: `histogram` from triangle_area_histogram of the surface `name` (`triangles`
/// triangles), the typical one of `distinct_surfaces`. Does not throw (but std::bad_alloc).
BarChart figure4b_chart(const Histogram& histogram, const std::string& name, std::int64_t triangles,
                        std::size_t distinct_surfaces);

}  // namespace spheremap
