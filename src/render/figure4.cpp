// Figure 4 of Rahi & Sharp as bar charts.
#include "spheremap/render/figure4.hpp"

#include <fmt/format.h>

#include "spheremap/reproduction/table1.hpp"

namespace spheremap {
namespace {

BarChart histogram_chart(const Histogram& histogram) {
  BarChart chart;
  chart.y_label = "Frequency";
  chart.categories = histogram.labels;
  for (const auto c : histogram.counts) chart.values.push_back(static_cast<double>(c));
  return chart;
}

}  // namespace

BarChart figure4a_chart(const Histogram& histogram, const std::string& weights, std::int64_t surfaces) {
  BarChart chart = histogram_chart(histogram);
  chart.title = fmt::format("Figure 4a: octant areas, {} weights", weights);
  chart.subtitle =
      fmt::format("{} surfaces × 8 octants; bins 3% wide, labelled by their centre", with_thousands(surfaces));
  chart.x_label = "% area of octant";
  return chart;
}

BarChart figure4b_chart(const Histogram& histogram, const std::string& name, std::int64_t triangles,
                        std::size_t distinct_surfaces) {
  BarChart chart = histogram_chart(histogram);
  chart.title = fmt::format("Figure 4b: triangle areas of {} ({} triangles)", name, with_thousands(triangles));
  chart.subtitle =
      fmt::format("median triangle count of {} surfaces; bar 10 = [0, 10)% of the mean", distinct_surfaces);
  chart.x_label = "Area as % of mean";
  return chart;
}

}  // namespace spheremap
