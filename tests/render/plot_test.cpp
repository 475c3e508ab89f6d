// Bar charts: layout, SVG text, raster, PNG round trip through libpng.
#include "spheremap/render/plot.hpp"

#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "../test_support.hpp"
#include "spheremap/error.hpp"

namespace spheremap {
namespace {

namespace fs = std::filesystem;

BarChart sample_chart() {
  BarChart chart;
  chart.title = "Figure 4a: octant areas, uniform weights";
  chart.subtitle = "3 surfaces × 8 octants; 25.0° <&> \"x\"";
  chart.x_label = "% area of octant";
  chart.y_label = "Frequency";
  chart.categories = {"6.5", "9.5", "12.5", "15.5", "18.5"};
  chart.values = {2, 5, 13, 3, 0};
  return chart;
}

std::size_t count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

TEST(Plot, LayoutHasRoundTicksAndProportionalBars) {
  const BarChartLayout l = lay_out_bar_chart(sample_chart());
  EXPECT_DOUBLE_EQ(l.y_max, 15);  // largest 13, step 5 (the first of 1, 2, 5 x 10^k >= 13/5)
  ASSERT_EQ(l.y_ticks.size(), 4u);
  EXPECT_EQ(l.y_tick_labels.front(), "0");
  EXPECT_EQ(l.y_tick_labels.back(), "15");
  ASSERT_EQ(l.bars.size(), 5u);
  const int height = l.plot_bottom - l.plot_top;
  EXPECT_EQ(l.bars[2].y1 - l.bars[2].y0, static_cast<int>(std::lround(13.0 / 15 * height)));
  EXPECT_EQ(l.bars[4].y0, l.bars[4].y1);  // zero: empty bar
  for (std::size_t i = 1; i < l.bars.size(); ++i) EXPECT_GT(l.bars[i].x0, l.bars[i - 1].x1 - 1);
  EXPECT_EQ(l.label_every, 1);
  // Integer counts never get fractional ticks.
  BarChart small = sample_chart();
  small.values = {1, 0, 1, 0, 1};
  const BarChartLayout s = lay_out_bar_chart(small);
  EXPECT_DOUBLE_EQ(s.y_max, 1);
  EXPECT_EQ(s.y_tick_labels.back(), "1");
  // Fractions do.
  small.values = {0.25, 0, 0.5, 0, 0.1};
  EXPECT_EQ(lay_out_bar_chart(small).y_tick_labels[1], "0.1");
}

TEST(Plot, CrowdedLabelsAreThinned) {
  BarChart chart = sample_chart();
  chart.categories.clear();
  chart.values.clear();
  for (int i = 0; i < 60; ++i) {
    chart.categories.push_back(std::to_string(1000 + i));
    chart.values.push_back(i % 7);
  }
  const BarChartLayout l = lay_out_bar_chart(chart, {480, 300});
  EXPECT_GT(l.label_every, 1);
}

TEST(Plot, BadChartsAreRefused) {
  BarChart chart = sample_chart();
  EXPECT_THROW(lay_out_bar_chart(chart, {100, 100}), std::invalid_argument);
  chart.values.pop_back();
  EXPECT_THROW(lay_out_bar_chart(chart), std::invalid_argument);
  chart = sample_chart();
  chart.values[0] = -1;
  EXPECT_THROW(bar_chart_svg(chart), std::invalid_argument);
  chart.values[0] = std::nan("");
  EXPECT_THROW(render_bar_chart(chart), std::invalid_argument);
  EXPECT_THROW(lay_out_bar_chart(BarChart{}), std::invalid_argument);
}

TEST(Plot, SvgIsTextWithOneRectPerBar) {
  const std::string svg = bar_chart_svg(sample_chart());
  EXPECT_EQ(svg.rfind("<svg", 0), 0u);
  EXPECT_EQ(svg.substr(svg.size() - 7), "</svg>\n");
  EXPECT_EQ(count(svg, "<rect class=\"bar\""), 5u);
  EXPECT_EQ(count(svg, "<rect"), count(svg, "</rect>") + 1);  // the background rect is self-closing
  EXPECT_EQ(count(svg, "<text"), count(svg, "</text>"));
  EXPECT_NE(svg.find(">12.5</text>"), std::string::npos);
  EXPECT_NE(svg.find(">Frequency</text>"), std::string::npos);
  EXPECT_NE(svg.find("&lt;&amp;&gt; &quot;x&quot;"), std::string::npos);  // escaped
  EXPECT_EQ(svg.find("<&>"), std::string::npos);
  EXPECT_NE(svg.find("25.0°"), std::string::npos);  // UTF-8 kept
  EXPECT_EQ(svg, bar_chart_svg(sample_chart()));
}

TEST(Plot, RasterHasBarsAxesAndText) {
  const BarChart chart = sample_chart();
  const RgbImage image = render_bar_chart(chart);
  const BarChartLayout l = lay_out_bar_chart(chart);
  ASSERT_EQ(image.width, 960);
  ASSERT_EQ(image.height, 600);
  ASSERT_EQ(image.pixels.size(), 960u * 600u * 3u);
  EXPECT_EQ(image.at(0, 0), kPlotBackground);
  const auto& tall = l.bars[2];
  EXPECT_EQ(image.at((tall.x0 + tall.x1) / 2, (tall.y0 + tall.y1) / 2), kPlotBarFill);
  EXPECT_EQ(image.at(l.plot_left - 1, (l.plot_top + l.plot_bottom) / 2), kPlotInk);  // y axis
  // Some ink in the title band and under the axis (labels), none in the right margin.
  auto ink_in = [&](int x0, int y0, int x1, int y1) {
    int n = 0;
    for (int y = y0; y < y1; ++y)
      for (int x = x0; x < x1; ++x) n += image.at(x, y) == kPlotInk;
    return n;
  };
  EXPECT_GT(ink_in(0, 0, image.width, l.plot_top - 4), 100);
  EXPECT_GT(ink_in(l.plot_left, l.plot_bottom + 2, l.plot_right, image.height), 100);
  EXPECT_EQ(ink_in(image.width - 8, 0, image.width, image.height), 0);
  EXPECT_EQ(bitmap_text_width("12.5", 2), (4 * 6 - 1) * 2);
  EXPECT_EQ(bitmap_text_width("25°", 1), 3 * 6 - 1);  // one glyph per character, not per byte
  EXPECT_EQ(bitmap_text_width("", 2), 0);
}

class PlotFiles : public testing_support::FolderTest {};

TEST_F(PlotFiles, PngRoundTripsThroughLibpng) {
  RgbImage image;
  image.width = 7;
  image.height = 5;
  image.pixels.assign(7 * 5 * 3, 255);
  const auto i = (2 * 7 + 3) * 3;  // pixel (3, 2)
  image.pixels[i] = 10;
  image.pixels[i + 1] = 200;
  image.pixels[i + 2] = 30;
  const fs::path path = folder_ / "small.png";
  write_png(path, image);
  const std::string png = testing_support::slurp(path);
  ASSERT_GT(png.size(), 33u);
  EXPECT_EQ(png.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
  EXPECT_EQ(png.substr(12, 4), "IHDR");
  EXPECT_EQ(png.substr(16, 8), std::string("\0\0\0\x07\0\0\0\x05", 8));  // width, height big-endian
  const RgbImage back = read_png(path);
  EXPECT_EQ(back.width, 7);
  EXPECT_EQ(back.height, 5);
  EXPECT_EQ(back.pixels, image.pixels);
  EXPECT_EQ((back.at(3, 2)), (std::array<std::uint8_t, 3>{10, 200, 30}));
  EXPECT_EQ(png, encode_png(image));  // deterministic
  // Nothing left behind but the file.
  int files = 0;
  for ([[maybe_unused]] const auto& entry : fs::directory_iterator(folder_)) ++files;
  EXPECT_EQ(files, 1);
}

TEST_F(PlotFiles, ChartPngReadsBackAsRendered) {
  const RgbImage image = render_bar_chart(sample_chart(), {640, 400});
  write_png(folder_ / "chart.png", image);
  const RgbImage back = read_png(folder_ / "chart.png");
  EXPECT_EQ(back.width, 640);
  EXPECT_EQ(back.height, 400);
  EXPECT_EQ(back.pixels, image.pixels);
}

TEST_F(PlotFiles, BadImagesAndFilesAreRefused) {
  RgbImage image;
  image.width = 2;
  image.height = 2;
  image.pixels.assign(5, 0);
  EXPECT_THROW(encode_png(image), std::invalid_argument);
  EXPECT_THROW(read_png(folder_ / "missing.png"), InputError);
  std::ofstream(folder_ / "not.png") << "hello";
  EXPECT_THROW(read_png(folder_ / "not.png"), InputError);
  image.pixels.assign(12, 0);
  EXPECT_THROW(write_png(folder_ / "no-such-folder" / "x.png", image), InputError);
}

}  // namespace
}  // namespace spheremap
