// Bar charts as SVG and as rasters, and PNG files through libpng's simplified API.
#include "spheremap/render/plot.hpp"

#include <png.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>

#include <fmt/format.h>

#include "markup.hpp"
#include "spheremap/error.hpp"
#include "spheremap/io/atomic_file.hpp"

namespace spheremap {
namespace {

// ---------------------------------------------------------------------------------------------------
// The bitmap font: 5 columns x 9 rows per glyph; rows 0-6 stand on the baseline (capitals and digits
// use all seven), rows 7-8 are descenders. '#' is ink. Rows not given are empty.
struct Glyph {
  char32_t code;
  const char* rows[9];
};

// clang-format off
constexpr Glyph kGlyphs[] = {
  {U' ', {".....", ".....", ".....", ".....", ".....", ".....", "....."}},
  {U'!', {"..#..", "..#..", "..#..", "..#..", "..#..", ".....", "..#.."}},
  {U'"', {".#.#.", ".#.#.", ".#.#.", ".....", ".....", ".....", "....."}},
  {U'#', {".#.#.", ".#.#.", "#####", ".#.#.", "#####", ".#.#.", ".#.#."}},
  {U'$', {"..#..", ".####", "#.#..", ".###.", "..#.#", "####.", "..#.."}},
  {U'%', {"##...", "##..#", "...#.", "..#..", ".#...", "#..##", "...##"}},
  {U'&', {".##..", "#..#.", "#.#..", ".#...", "#.#.#", "#..#.", ".##.#"}},
  {U'\'', {"..#..", "..#..", ".#...", ".....", ".....", ".....", "....."}},
  {U'(', {"...#.", "..#..", ".#...", ".#...", ".#...", "..#..", "...#."}},
  {U')', {".#...", "..#..", "...#.", "...#.", "...#.", "..#..", ".#..."}},
  {U'*', {".....", "..#..", "#.#.#", ".###.", "#.#.#", "..#..", "....."}},
  {U'+', {".....", "..#..", "..#..", "#####", "..#..", "..#..", "....."}},
  {U',', {".....", ".....", ".....", ".....", ".....", ".##..", "..#..", ".#..."}},
  {U'-', {".....", ".....", ".....", "#####", ".....", ".....", "....."}},
  {U'.', {".....", ".....", ".....", ".....", ".....", ".##..", ".##.."}},
  {U'/', {".....", "....#", "...#.", "..#..", ".#...", "#....", "....."}},
  {U'0', {".###.", "#...#", "#..##", "#.#.#", "##..#", "#...#", ".###."}},
  {U'1', {"..#..", ".##..", "..#..", "..#..", "..#..", "..#..", ".###."}},
  {U'2', {".###.", "#...#", "....#", "...#.", "..#..", ".#...", "#####"}},
  {U'3', {"#####", "...#.", "..#..", "...#.", "....#", "#...#", ".###."}},
  {U'4', {"...#.", "..##.", ".#.#.", "#..#.", "#####", "...#.", "...#."}},
  {U'5', {"#####", "#....", "####.", "....#", "....#", "#...#", ".###."}},
  {U'6', {"..##.", ".#...", "#....", "####.", "#...#", "#...#", ".###."}},
  {U'7', {"#####", "....#", "...#.", "..#..", ".#...", ".#...", ".#..."}},
  {U'8', {".###.", "#...#", "#...#", ".###.", "#...#", "#...#", ".###."}},
  {U'9', {".###.", "#...#", "#...#", ".####", "....#", "...#.", ".##.."}},
  {U':', {".....", ".##..", ".##..", ".....", ".##..", ".##..", "....."}},
  {U';', {".....", ".##..", ".##..", ".....", ".##..", "..#..", ".#..."}},
  {U'<', {"...#.", "..#..", ".#...", "#....", ".#...", "..#..", "...#."}},
  {U'=', {".....", ".....", "#####", ".....", "#####", ".....", "....."}},
  {U'>', {".#...", "..#..", "...#.", "....#", "...#.", "..#..", ".#..."}},
  {U'?', {".###.", "#...#", "....#", "...#.", "..#..", ".....", "..#.."}},
  {U'@', {".###.", "#...#", "....#", ".##.#", "#.#.#", "#.#.#", ".###."}},
  {U'A', {".###.", "#...#", "#...#", "#####", "#...#", "#...#", "#...#"}},
  {U'B', {"####.", "#...#", "#...#", "####.", "#...#", "#...#", "####."}},
  {U'C', {".###.", "#...#", "#....", "#....", "#....", "#...#", ".###."}},
  {U'D', {"###..", "#..#.", "#...#", "#...#", "#...#", "#..#.", "###.."}},
  {U'E', {"#####", "#....", "#....", "####.", "#....", "#....", "#####"}},
  {U'F', {"#####", "#....", "#....", "####.", "#....", "#....", "#...."}},
  {U'G', {".###.", "#...#", "#....", "#.###", "#...#", "#...#", ".####"}},
  {U'H', {"#...#", "#...#", "#...#", "#####", "#...#", "#...#", "#...#"}},
  {U'I', {".###.", "..#..", "..#..", "..#..", "..#..", "..#..", ".###."}},
  {U'J', {"..###", "...#.", "...#.", "...#.", "...#.", "#..#.", ".##.."}},
  {U'K', {"#...#", "#..#.", "#.#..", "##...", "#.#..", "#..#.", "#...#"}},
  {U'L', {"#....", "#....", "#....", "#....", "#....", "#....", "#####"}},
  {U'M', {"#...#", "##.##", "#.#.#", "#.#.#", "#...#", "#...#", "#...#"}},
  {U'N', {"#...#", "#...#", "##..#", "#.#.#", "#..##", "#...#", "#...#"}},
  {U'O', {".###.", "#...#", "#...#", "#...#", "#...#", "#...#", ".###."}},
  {U'P', {"####.", "#...#", "#...#", "####.", "#....", "#....", "#...."}},
  {U'Q', {".###.", "#...#", "#...#", "#...#", "#.#.#", "#..#.", ".##.#"}},
  {U'R', {"####.", "#...#", "#...#", "####.", "#.#..", "#..#.", "#...#"}},
  {U'S', {".####", "#....", "#....", ".###.", "....#", "....#", "####."}},
  {U'T', {"#####", "..#..", "..#..", "..#..", "..#..", "..#..", "..#.."}},
  {U'U', {"#...#", "#...#", "#...#", "#...#", "#...#", "#...#", ".###."}},
  {U'V', {"#...#", "#...#", "#...#", "#...#", "#...#", ".#.#.", "..#.."}},
  {U'W', {"#...#", "#...#", "#...#", "#.#.#", "#.#.#", "#.#.#", ".#.#."}},
  {U'X', {"#...#", "#...#", ".#.#.", "..#..", ".#.#.", "#...#", "#...#"}},
  {U'Y', {"#...#", "#...#", ".#.#.", "..#..", "..#..", "..#..", "..#.."}},
  {U'Z', {"#####", "....#", "...#.", "..#..", ".#...", "#....", "#####"}},
  {U'[', {".###.", ".#...", ".#...", ".#...", ".#...", ".#...", ".###."}},
  {U'\\', {".....", "#....", ".#...", "..#..", "...#.", "....#", "....."}},
  {U']', {".###.", "...#.", "...#.", "...#.", "...#.", "...#.", ".###."}},
  {U'^', {"..#..", ".#.#.", "#...#", ".....", ".....", ".....", "....."}},
  {U'_', {".....", ".....", ".....", ".....", ".....", ".....", ".....", "#####"}},
  {U'`', {".#...", "..#..", "...#.", ".....", ".....", ".....", "....."}},
  {U'a', {".....", ".....", ".###.", "....#", ".####", "#...#", ".####"}},
  {U'b', {"#....", "#....", "####.", "#...#", "#...#", "#...#", "####."}},
  {U'c', {".....", ".....", ".###.", "#....", "#....", "#...#", ".###."}},
  {U'd', {"....#", "....#", ".####", "#...#", "#...#", "#...#", ".####"}},
  {U'e', {".....", ".....", ".###.", "#...#", "#####", "#....", ".###."}},
  {U'f', {"..##.", ".#..#", ".#...", "###..", ".#...", ".#...", ".#..."}},
  {U'g', {".....", ".....", ".####", "#...#", "#...#", "#...#", ".####", "....#", ".###."}},
  {U'h', {"#....", "#....", "#.##.", "##..#", "#...#", "#...#", "#...#"}},
  {U'i', {"..#..", ".....", ".##..", "..#..", "..#..", "..#..", ".###."}},
  {U'j', {"...#.", ".....", "..##.", "...#.", "...#.", "...#.", "...#.", "#..#.", ".##.."}},
  {U'k', {"#....", "#....", "#..#.", "#.#..", "##...", "#.#..", "#..#."}},
  {U'l', {".##..", "..#..", "..#..", "..#..", "..#..", "..#..", ".###."}},
  {U'm', {".....", ".....", "##.#.", "#.#.#", "#.#.#", "#.#.#", "#.#.#"}},
  {U'n', {".....", ".....", "#.##.", "##..#", "#...#", "#...#", "#...#"}},
  {U'o', {".....", ".....", ".###.", "#...#", "#...#", "#...#", ".###."}},
  {U'p', {".....", ".....", "####.", "#...#", "#...#", "#...#", "####.", "#....", "#...."}},
  {U'q', {".....", ".....", ".####", "#...#", "#...#", "#...#", ".####", "....#", "....#"}},
  {U'r', {".....", ".....", "#.##.", "##..#", "#....", "#....", "#...."}},
  {U's', {".....", ".....", ".####", "#....", ".###.", "....#", "####."}},
  {U't', {".#...", ".#...", "###..", ".#...", ".#...", ".#..#", "..##."}},
  {U'u', {".....", ".....", "#...#", "#...#", "#...#", "#..##", ".##.#"}},
  {U'v', {".....", ".....", "#...#", "#...#", "#...#", ".#.#.", "..#.."}},
  {U'w', {".....", ".....", "#...#", "#...#", "#.#.#", "#.#.#", ".#.#."}},
  {U'x', {".....", ".....", "#...#", ".#.#.", "..#..", ".#.#.", "#...#"}},
  {U'y', {".....", ".....", "#...#", "#...#", "#...#", "#...#", ".####", "....#", ".###."}},
  {U'z', {".....", ".....", "#####", "...#.", "..#..", ".#...", "#####"}},
  {U'{', {"...#.", "..#..", "..#..", ".#...", "..#..", "..#..", "...#."}},
  {U'|', {"..#..", "..#..", "..#..", "..#..", "..#..", "..#..", "..#.."}},
  {U'}', {".#...", "..#..", "..#..", "...#.", "..#..", "..#..", ".#..."}},
  {U'~', {".....", ".....", ".#...", "#.#.#", "...#.", ".....", "....."}},
  {U'\u00B0', {".##..", "#..#.", "#..#.", ".##..", ".....", ".....", "....."}},  // °
  {U'\u00B7', {".....", ".....", ".....", "..#..", ".....", ".....", "....."}},  // ·
  {U'\u00C5', {"..#..", ".#.#.", "..#..", ".###.", "#...#", "#####", "#...#"}},  // Å
  {U'\u00D7', {".....", "#...#", ".#.#.", "..#..", ".#.#.", "#...#", "....."}},  // ×
  {U'\u2013', {".....", ".....", ".....", "#####", ".....", ".....", "....."}},  // –
  {U'\u2265', {".#...", "..#..", "...#.", "..#..", ".#...", ".....", "#####"}},  // ≥
};
// clang-format on

constexpr int kGlyphWidth = 5;
constexpr int kGlyphRows = 9;     // including descenders
constexpr int kGlyphAdvance = 6;  // one column of spacing

const Glyph& glyph_for(char32_t code) {
  for (const auto& g : kGlyphs)
    if (g.code == code) return g;
  for (const auto& g : kGlyphs)
    if (g.code == U'?') return g;
  throw std::logic_error("bitmap font: no '?' glyph");
}

// UTF-8 to code points; a malformed byte becomes U+FFFD (drawn as '?').
std::u32string decode_utf8(const std::string& text) {
  std::u32string out;
  for (std::size_t i = 0; i < text.size();) {
    const auto byte = static_cast<unsigned char>(text[i]);
    int extra = byte < 0x80 ? 0 : (byte >> 5) == 0x6 ? 1 : (byte >> 4) == 0xE ? 2 : (byte >> 3) == 0x1E ? 3 : -1;
    if (extra < 0 || i + static_cast<std::size_t>(extra) >= text.size()) {
      out.push_back(U'\uFFFD');
      ++i;
      continue;
    }
    char32_t code = extra == 0 ? byte : byte & (0x3F >> extra);
    bool valid = true;
    for (int k = 1; k <= extra; ++k) {
      const auto next = static_cast<unsigned char>(text[i + static_cast<std::size_t>(k)]);
      if ((next & 0xC0) != 0x80) valid = false;
      code = (code << 6) | (next & 0x3F);
    }
    if (!valid) {
      out.push_back(U'\uFFFD');
      ++i;
      continue;
    }
    out.push_back(code);
    i += static_cast<std::size_t>(extra) + 1;
  }
  return out;
}

using Color = std::array<std::uint8_t, 3>;
constexpr Color kGrid{221, 221, 221};
constexpr Color kBarEdge{47, 75, 102};

void fill_rect(RgbImage& image, int x0, int y0, int x1, int y1, const Color& color) {
  x0 = std::max(x0, 0);
  y0 = std::max(y0, 0);
  x1 = std::min(x1, image.width);
  y1 = std::min(y1, image.height);
  for (int y = y0; y < y1; ++y)
    for (int x = x0; x < x1; ++x) {
      const auto i =
          (static_cast<std::size_t>(y) * static_cast<std::size_t>(image.width) + static_cast<std::size_t>(x)) * 3;
      image.pixels[i] = color[0];
      image.pixels[i + 1] = color[1];
      image.pixels[i + 2] = color[2];
    }
}

// Horizontal text; (x, top) is the top-left corner of the first glyph's cell.
void draw_text(RgbImage& image, int x, int top, const std::string& text, int scale, const Color& color) {
  int pen = x;
  for (const char32_t code : decode_utf8(text)) {
    const Glyph& g = glyph_for(code);
    for (int row = 0; row < kGlyphRows; ++row) {
      if (g.rows[row] == nullptr) continue;
      for (int col = 0; col < kGlyphWidth; ++col)
        if (g.rows[row][col] == '#')
          fill_rect(image, pen + col * scale, top + row * scale, pen + (col + 1) * scale, top + (row + 1) * scale,
                    color);
    }
    pen += kGlyphAdvance * scale;
  }
}

// Text turned a quarter turn counter-clockwise (read bottom to top); (left, bottom) is where the first
// glyph's cell starts: its top row lies along column `left`, its first column ends at row `bottom`.
void draw_text_up(RgbImage& image, int left, int bottom, const std::string& text, int scale, const Color& color) {
  int pen = 0;
  for (const char32_t code : decode_utf8(text)) {
    const Glyph& g = glyph_for(code);
    for (int row = 0; row < kGlyphRows; ++row) {
      if (g.rows[row] == nullptr) continue;
      for (int col = 0; col < kGlyphWidth; ++col)
        if (g.rows[row][col] == '#')
          fill_rect(image, left + row * scale, bottom - (pen + col + 1) * scale, left + (row + 1) * scale,
                    bottom - (pen + col) * scale, color);
    }
    pen += kGlyphAdvance;
  }
}

// Layout constants (pixels).
constexpr int kTextScale = 2;
constexpr int kLineHeight = (kGlyphRows + 2) * kTextScale;  // 22
constexpr int kCapHeight = 7 * kTextScale;
constexpr int kMargin = 14;
constexpr int kTickLength = 6;

// 1, 2 or 5 times a power of ten, at least `at_least`.
double nice_step(double at_least) {
  const double power = std::pow(10.0, std::floor(std::log10(at_least)));
  for (const double m : {1.0, 2.0, 5.0, 10.0})
    if (m * power >= at_least * (1 - 1e-12)) return m * power;
  return 10 * power;
}

std::string tick_label(double value, double step) {
  const int decimals = step >= 1 ? 0 : static_cast<int>(std::ceil(-std::log10(step) - 1e-9));
  return fmt::format("{:.{}f}", value, decimals);
}

std::string hex(const Color& c) { return fmt::format("#{:02x}{:02x}{:02x}", c[0], c[1], c[2]); }

}  // namespace

int bitmap_text_width(const std::string& text, int scale) {
  const auto n = static_cast<int>(decode_utf8(text).size());
  return n == 0 ? 0 : (n * kGlyphAdvance - 1) * scale;
}

BarChartLayout lay_out_bar_chart(const BarChart& chart, const PlotSize& size) {
  if (chart.values.empty()) throw std::invalid_argument("bar chart: no bars");
  if (chart.values.size() != chart.categories.size())
    throw std::invalid_argument(
        fmt::format("bar chart: {} values but {} category labels", chart.values.size(), chart.categories.size()));
  if (size.width < 240 || size.height < 180 || size.width > 8000 || size.height > 8000)
    throw std::invalid_argument(
        fmt::format("bar chart: canvas {} x {} outside 240 x 180 to 8000 x 8000", size.width, size.height));
  double largest = 0;
  bool whole = true;
  for (const double v : chart.values) {
    if (!std::isfinite(v) || v < 0)
      throw std::invalid_argument(fmt::format("bar chart: bar value {} is not finite and >= 0", v));
    largest = std::max(largest, v);
    whole = whole && v == std::floor(v);
  }

  BarChartLayout layout;
  // The y scale: about five steps of 1, 2 or 5 x 10^k.
  double step = largest > 0 ? nice_step(largest / 5) : 1;
  if (whole) step = std::max(step, 1.0);
  const double top_value = largest > 0 ? std::ceil(largest / step - 1e-9) * step : step;
  layout.y_max = top_value;
  const int tick_count = static_cast<int>(std::lround(top_value / step));
  int widest_tick = 0;
  for (int k = 0; k <= tick_count; ++k) {
    layout.y_ticks.push_back(k * step);
    layout.y_tick_labels.push_back(tick_label(k * step, step));
    widest_tick = std::max(widest_tick, bitmap_text_width(layout.y_tick_labels.back(), kTextScale));
  }

  const int title_lines = (chart.title.empty() ? 0 : 1) + (chart.subtitle.empty() ? 0 : 1);
  layout.plot_top = kMargin + title_lines * kLineHeight + (title_lines > 0 ? kLineHeight / 2 : 0);
  layout.plot_left = kMargin + (chart.y_label.empty() ? 0 : kLineHeight + 4) + widest_tick + kTickLength + 6;
  layout.plot_right = size.width - kMargin - 10;
  layout.plot_bottom =
      size.height - kMargin - (chart.x_label.empty() ? 0 : kLineHeight + 4) - kLineHeight - kTickLength - 4;
  if (layout.plot_right - layout.plot_left < 40 || layout.plot_bottom - layout.plot_top < 40)
    throw std::invalid_argument("bar chart: canvas too small for the text");

  const int plot_height = layout.plot_bottom - layout.plot_top;
  for (const double tick : layout.y_ticks)
    layout.y_tick_rows.push_back(layout.plot_bottom - static_cast<int>(std::lround(tick / top_value * plot_height)));

  const auto n = static_cast<int>(chart.values.size());
  const double slot = static_cast<double>(layout.plot_right - layout.plot_left) / n;
  const double gap = std::max(1.0, std::floor(slot * 0.15));
  for (int i = 0; i < n; ++i) {
    BarChartLayout::Bar bar{};
    bar.x0 = layout.plot_left + static_cast<int>(std::lround(i * slot + gap / 2));
    bar.x1 = std::max(bar.x0 + 1, layout.plot_left + static_cast<int>(std::lround((i + 1) * slot - gap / 2)));
    bar.y1 = layout.plot_bottom;
    bar.y0 = layout.plot_bottom -
             static_cast<int>(std::lround(chart.values[static_cast<std::size_t>(i)] / top_value * plot_height));
    layout.bars.push_back(bar);
  }
  int widest_label = 0;
  for (const auto& c : chart.categories) widest_label = std::max(widest_label, bitmap_text_width(c, kTextScale));
  while (layout.label_every < n && layout.label_every * slot < widest_label + 3 * kTextScale) ++layout.label_every;
  return layout;
}

std::string bar_chart_svg(const BarChart& chart, const PlotSize& size) {
  const BarChartLayout l = lay_out_bar_chart(chart, size);
  const int font = kCapHeight + kCapHeight / 3;  // roughly the bitmap font's size
  std::string svg = fmt::format(
      "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"{0}\" height=\"{1}\" viewBox=\"0 0 {0} {1}\" "
      "font-family=\"DejaVu Sans, Helvetica, Arial, sans-serif\" font-size=\"{2}\">\n",
      size.width, size.height, font);
  svg += fmt::format("<rect x=\"0\" y=\"0\" width=\"{}\" height=\"{}\" fill=\"{}\"/>\n", size.width, size.height,
                     hex(kPlotBackground));
  int line_top = kMargin;
  for (const std::string* line : {&chart.title, &chart.subtitle}) {
    if (line->empty()) continue;
    svg += fmt::format("<text class=\"title\" x=\"{}\" y=\"{}\" text-anchor=\"middle\">{}</text>\n", size.width / 2,
                       line_top + kCapHeight, render_detail::escape_markup(*line));
    line_top += kLineHeight;
  }
  for (std::size_t k = 0; k < l.y_ticks.size(); ++k) {
    const int row = l.y_tick_rows[k];
    if (k > 0)
      svg += fmt::format("<line x1=\"{}\" y1=\"{}\" x2=\"{}\" y2=\"{}\" stroke=\"{}\"/>\n", l.plot_left, row,
                         l.plot_right, row, hex(kGrid));
    svg += fmt::format("<line x1=\"{}\" y1=\"{}\" x2=\"{}\" y2=\"{}\" stroke=\"{}\"/>\n", l.plot_left - kTickLength,
                       row, l.plot_left, row, hex(kPlotInk));
    svg += fmt::format("<text x=\"{}\" y=\"{}\" text-anchor=\"end\">{}</text>\n", l.plot_left - kTickLength - 4,
                       row + kCapHeight / 2, render_detail::escape_markup(l.y_tick_labels[k]));
  }
  for (std::size_t i = 0; i < l.bars.size(); ++i) {
    const auto& b = l.bars[i];
    if (b.y1 > b.y0)
      svg += fmt::format(
          "<rect class=\"bar\" x=\"{}\" y=\"{}\" width=\"{}\" height=\"{}\" fill=\"{}\" stroke=\"{}\">"
          "<title>{}: {}</title></rect>\n",
          b.x0, b.y0, b.x1 - b.x0, b.y1 - b.y0, hex(kPlotBarFill), hex(kBarEdge),
          render_detail::escape_markup(chart.categories[i]), chart.values[i]);
    else
      svg += fmt::format(
          "<rect class=\"bar\" x=\"{}\" y=\"{}\" width=\"{}\" height=\"0\" fill=\"{}\"><title>{}: {}</title></rect>\n",
          b.x0, b.y0, b.x1 - b.x0, hex(kPlotBarFill), render_detail::escape_markup(chart.categories[i]),
          chart.values[i]);
    const int centre = (b.x0 + b.x1) / 2;
    svg += fmt::format("<line x1=\"{0}\" y1=\"{1}\" x2=\"{0}\" y2=\"{2}\" stroke=\"{3}\"/>\n", centre, l.plot_bottom,
                       l.plot_bottom + kTickLength / (i % static_cast<std::size_t>(l.label_every) == 0 ? 1 : 2),
                       hex(kPlotInk));
    if (i % static_cast<std::size_t>(l.label_every) == 0)
      svg +=
          fmt::format("<text x=\"{}\" y=\"{}\" text-anchor=\"middle\">{}</text>\n", centre,
                      l.plot_bottom + kTickLength + 4 + kCapHeight, render_detail::escape_markup(chart.categories[i]));
  }
  svg += fmt::format(
      "<line x1=\"{0}\" y1=\"{1}\" x2=\"{0}\" y2=\"{2}\" stroke=\"{4}\"/>\n"
      "<line x1=\"{0}\" y1=\"{2}\" x2=\"{3}\" y2=\"{2}\" stroke=\"{4}\"/>\n",
      l.plot_left, l.plot_top, l.plot_bottom, l.plot_right, hex(kPlotInk));
  if (!chart.x_label.empty())
    svg += fmt::format("<text class=\"x-label\" x=\"{}\" y=\"{}\" text-anchor=\"middle\">{}</text>\n",
                       (l.plot_left + l.plot_right) / 2, size.height - kMargin - kLineHeight + kCapHeight,
                       render_detail::escape_markup(chart.x_label));
  if (!chart.y_label.empty()) {
    const int x = kMargin + kCapHeight, y = (l.plot_top + l.plot_bottom) / 2;
    svg += fmt::format(
        "<text class=\"y-label\" x=\"{0}\" y=\"{1}\" text-anchor=\"middle\" transform=\"rotate(-90 {0} "
        "{1})\">{2}</text>\n",
        x, y, render_detail::escape_markup(chart.y_label));
  }
  svg += "</svg>\n";
  return svg;
}

RgbImage render_bar_chart(const BarChart& chart, const PlotSize& size) {
  const BarChartLayout l = lay_out_bar_chart(chart, size);
  RgbImage image;
  image.width = size.width;
  image.height = size.height;
  image.pixels.resize(static_cast<std::size_t>(size.width) * static_cast<std::size_t>(size.height) * 3);
  fill_rect(image, 0, 0, size.width, size.height, kPlotBackground);

  int line_top = kMargin;
  for (const std::string* line : {&chart.title, &chart.subtitle}) {
    if (line->empty()) continue;
    draw_text(image, (size.width - bitmap_text_width(*line, kTextScale)) / 2, line_top, *line, kTextScale, kPlotInk);
    line_top += kLineHeight;
  }
  for (std::size_t k = 0; k < l.y_ticks.size(); ++k) {
    const int row = l.y_tick_rows[k];
    if (k > 0) fill_rect(image, l.plot_left, row, l.plot_right, row + 1, kGrid);
    fill_rect(image, l.plot_left - kTickLength, row, l.plot_left, row + 1, kPlotInk);
    const int w = bitmap_text_width(l.y_tick_labels[k], kTextScale);
    draw_text(image, l.plot_left - kTickLength - 4 - w, row - kCapHeight / 2, l.y_tick_labels[k], kTextScale, kPlotInk);
  }
  for (std::size_t i = 0; i < l.bars.size(); ++i) {
    const auto& b = l.bars[i];
    if (b.y1 > b.y0) {
      fill_rect(image, b.x0, b.y0, b.x1, b.y1, kBarEdge);
      fill_rect(image, b.x0 + 1, b.y0 + 1, b.x1 - 1, b.y1, kPlotBarFill);
    }
    const bool labelled = i % static_cast<std::size_t>(l.label_every) == 0;
    const int centre = (b.x0 + b.x1) / 2;
    fill_rect(image, centre, l.plot_bottom, centre + 1, l.plot_bottom + (labelled ? kTickLength : kTickLength / 2),
              kPlotInk);
    if (labelled) {
      const int w = bitmap_text_width(chart.categories[i], kTextScale);
      draw_text(image, centre - w / 2, l.plot_bottom + kTickLength + 4, chart.categories[i], kTextScale, kPlotInk);
    }
  }
  fill_rect(image, l.plot_left - 1, l.plot_top, l.plot_left, l.plot_bottom + 1, kPlotInk);      // y axis
  fill_rect(image, l.plot_left - 1, l.plot_bottom, l.plot_right, l.plot_bottom + 1, kPlotInk);  // x axis
  if (!chart.x_label.empty()) {
    const int w = bitmap_text_width(chart.x_label, kTextScale);
    draw_text(image, (l.plot_left + l.plot_right - w) / 2, size.height - kMargin - kLineHeight, chart.x_label,
              kTextScale, kPlotInk);
  }
  if (!chart.y_label.empty()) {
    const int w = bitmap_text_width(chart.y_label, kTextScale);
    draw_text_up(image, kMargin, (l.plot_top + l.plot_bottom + w) / 2, chart.y_label, kTextScale, kPlotInk);
  }
  return image;
}

std::string encode_png(const RgbImage& image) {
  if (image.width <= 0 || image.height <= 0)
    throw std::invalid_argument(fmt::format("encode_png: image size {} x {}", image.width, image.height));
  if (image.pixels.size() != static_cast<std::size_t>(image.width) * static_cast<std::size_t>(image.height) * 3)
    throw std::invalid_argument(
        fmt::format("encode_png: {} bytes for a {} x {} RGB image", image.pixels.size(), image.width, image.height));
  png_image png;
  std::memset(&png, 0, sizeof png);
  png.version = PNG_IMAGE_VERSION;
  png.width = static_cast<png_uint_32>(image.width);
  png.height = static_cast<png_uint_32>(image.height);
  png.format = PNG_FORMAT_RGB;
  png_alloc_size_t bytes = 0;
  // First call: the size needed; second: the bytes.
  if (!png_image_write_to_memory(&png, nullptr, &bytes, 0, image.pixels.data(), 0, nullptr))
    throw std::runtime_error(fmt::format("libpng: {}", png.message));
  std::string out(bytes, '\0');
  if (!png_image_write_to_memory(&png, out.data(), &bytes, 0, image.pixels.data(), 0, nullptr))
    throw std::runtime_error(fmt::format("libpng: {}", png.message));
  out.resize(bytes);
  png_image_free(&png);
  return out;
}

void write_png(const std::filesystem::path& path, const RgbImage& image) {
  write_file_atomically(path, encode_png(image));
}

RgbImage read_png(const std::filesystem::path& path) {
  png_image png;
  std::memset(&png, 0, sizeof png);
  png.version = PNG_IMAGE_VERSION;
  if (!png_image_begin_read_from_file(&png, path.c_str()))
    throw InputError(fmt::format("{}: cannot read as PNG ({}); check that the file exists and is a PNG image",
                                 path.string(), png.message));
  png.format = PNG_FORMAT_RGB;
  RgbImage image;
  image.width = static_cast<int>(png.width);
  image.height = static_cast<int>(png.height);
  image.pixels.resize(PNG_IMAGE_SIZE(png));
  png_color white{255, 255, 255};
  if (!png_image_finish_read(&png, &white, image.pixels.data(), 0, nullptr)) {
    const std::string message = png.message;
    png_image_free(&png);
    throw InputError(fmt::format("{}: damaged PNG ({}); write it again", path.string(), message));
  }
  return image;
}

}  // namespace spheremap
