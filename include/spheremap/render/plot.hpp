// Simple plots for reports (stage: render): a bar chart (e.g. a histogram) drawn as SVG text and as an
// RGB raster with a built-in 5x7 bitmap font, and PNG files through libpng. No plotting library.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

namespace spheremap {

/// One series of bars, drawn left to right in the order given (a histogram: one bar per bin).
/// Text is UTF-8. The raster font has printable ASCII plus ° × · – ≥ Å; any other character is drawn
/// as '?' in the PNG (the SVG keeps it).
struct BarChart {
  std::string title;                    // first line above the plot
  std::string subtitle;                 // optional second line
  std::string x_label, y_label;         // axis titles (the y title is drawn vertically)
  std::vector<std::string> categories;  // the label under each bar (labels that would overlap are thinned)
  std::vector<double> values;           // bar heights: finite, >= 0, one per category
};

struct PlotSize {
  int width = 960;  // pixels (SVG user units)
  int height = 600;
};

/// An 8-bit RGB raster, row-major from the top-left corner, 3 bytes per pixel.
struct RgbImage {
  int width = 0;
  int height = 0;
  std::vector<std::uint8_t> pixels;  // width * height * 3

  /// The pixel at column x, row y. Precondition: 0 <= x < width, 0 <= y < height.
  [[nodiscard]] std::array<std::uint8_t, 3> at(int x, int y) const {
    const auto i = (static_cast<std::size_t>(y) * static_cast<std::size_t>(width) + static_cast<std::size_t>(x)) * 3;
    return {pixels[i], pixels[i + 1], pixels[i + 2]};
  }
};

/// Colours of the charts, exposed for tests (sRGB).
inline constexpr std::array<std::uint8_t, 3> kPlotBackground{255, 255, 255};
inline constexpr std::array<std::uint8_t, 3> kPlotBarFill{78, 121, 167};
inline constexpr std::array<std::uint8_t, 3> kPlotInk{0, 0, 0};

/// Where the chart's pieces go; both renderers use it, so the SVG and the PNG are the same picture.
/// All coordinates in pixels from the top-left corner; rectangles are [x0, x1) x [y0, y1).
struct BarChartLayout {
  int plot_left = 0, plot_top = 0, plot_right = 0, plot_bottom = 0;  // the axes' box
  struct Bar {
    int x0, y0, x1, y1;
  };
  std::vector<Bar> bars;         // one per category (an empty bar has y0 == y1)
  std::vector<double> y_ticks;   // values of the horizontal grid lines, from 0 up to the axis maximum
  std::vector<int> y_tick_rows;  // their rows
  std::vector<std::string> y_tick_labels;
  double y_max = 1;     // value at the top of the axes
  int label_every = 1;  // category labels drawn under bars 0, k, 2k, ...
};

/// The layout of `chart` on a canvas of `size`. The y axis runs from 0 to a round number (1, 2 or 5
/// times a power of ten steps, at least 1 when every value is a whole number) at or above the largest value.
/// Throws std::invalid_argument if there are no bars, if categories and values differ in size, if a
/// value is negative or not finite, or if the canvas is smaller than 240 x 180 or larger than 8000 x 8000.
BarChartLayout lay_out_bar_chart(const BarChart& chart, const PlotSize& size = {});

/// The chart as a standalone SVG document (starts with "<svg"); each bar is a <rect class="bar">, all
/// text is <text> (XML-escaped). Deterministic: same chart, same bytes. Throws as lay_out_bar_chart.
std::string bar_chart_svg(const BarChart& chart, const PlotSize& size = {});

/// The chart as a raster (white background, grid, bars, axes, text in the built-in bitmap font).
/// Deterministic. Throws as lay_out_bar_chart.
RgbImage render_bar_chart(const BarChart& chart, const PlotSize& size = {});

/// PNG file contents (8-bit RGB, written by libpng's simplified API; no time stamp, so the same image
/// gives the same bytes with the same libpng and zlib). Throws std::invalid_argument if the image's
/// pixel count does not match its size or a side is not positive, std::runtime_error if libpng fails.
std::string encode_png(const RgbImage& image);

/// Writes `image` as PNG to `path` atomically (temporary file beside it, then rename).
/// Throws as encode_png, and InputError if the file cannot be written.
void write_png(const std::filesystem::path& path, const RgbImage& image);

/// Reads any PNG libpng reads, converted to 8-bit RGB (alpha composited on white).
/// Throws InputError naming the file if it is missing or not a readable PNG.
RgbImage read_png(const std::filesystem::path& path);

/// Width in pixels of `text` in the bitmap font at `scale` (each glyph 5 x 7 pixels plus one pixel of
/// spacing, times scale). Counts UTF-8 characters, not bytes.
int bitmap_text_width(const std::string& text, int scale);

}  // namespace spheremap
