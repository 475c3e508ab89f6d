// Colour bars and legends of the pictures (see canvas.hpp).
#include <algorithm>
#include <cmath>
#include <set>

#include <fmt/format.h>

#include "canvas.hpp"

namespace spheremap::render_detail {
namespace {

void set_colour(cairo_t* cr, const Rgb8& c) { cairo_set_source_rgb(cr, c.r / 255.0, c.g / 255.0, c.b / 255.0); }

constexpr Rgb8 kInk{0, 0, 0};
constexpr Rgb8 kFrame{60, 60, 60};

// The 256 entries left to right, as a pattern of one pixel per entry scaled to the bar (nearest: bins stay
// sharp, as the pictures colour them).
void fill_bar(cairo_t* cr, const ColourTable& table, double x, double y, double width, double height) {
  std::vector<std::uint32_t> pixels;
  for (const Rgb8& c : table) pixels.push_back(opaque(c));
  cairo_surface_t* strip = image_surface(pixels, kColourTableSize, 1);
  cairo_save(cr);
  cairo_rectangle(cr, x, y, width, height);
  cairo_clip(cr);
  cairo_translate(cr, x, y);
  cairo_scale(cr, width / kColourTableSize, height);
  cairo_set_source_surface(cr, strip, 0, 0);
  cairo_pattern_set_filter(cairo_get_source(cr), CAIRO_FILTER_NEAREST);
  cairo_paint(cr);
  cairo_restore(cr);
  cairo_surface_destroy(strip);
}

// A triangle beyond the bar's end in the end colour: values past the range saturate there.
void draw_extension(cairo_t* cr, double tip_x, double base_x, double y, double height, const Rgb8& colour) {
  cairo_new_path(cr);
  cairo_move_to(cr, base_x, y);
  cairo_line_to(cr, tip_x, y + height / 2);
  cairo_line_to(cr, base_x, y + height);
  cairo_close_path(cr);
  set_colour(cr, colour);
  cairo_fill_preserve(cr);
  set_colour(cr, kFrame);
  cairo_set_line_width(cr, 1);
  cairo_stroke(cr);
}

void draw_missing_swatch(cairo_t* cr, double x, double y, double size, double font_size) {
  cairo_rectangle(cr, x, y, size, size);
  set_colour(cr, kMissingValueColour);
  cairo_fill_preserve(cr);
  set_colour(cr, kFrame);
  cairo_set_line_width(cr, 1);
  cairo_stroke(cr);
  set_font(cr, font_size);
  draw_text(cr, x + size * 1.3, y + size * 0.85, "no value", Align::left, kInk);
}

void draw_colour_bar(cairo_t* cr, const ColourKey& key, double x, double y, double width, double height, double fs) {
  const double bar_width = std::min(width * 0.62, 34 * fs), bar_height = fs * 1.1;
  const double left = x + (width - bar_width) / 2, top = y + (height - 4.2 * fs) / 2 + 1.5 * fs;
  set_font(cr, fs * 1.05, true);
  draw_text(cr, left + bar_width / 2, top - 0.45 * fs, key.title, Align::centre, kInk);
  const ColourTable& table = colour_table(key.scale);
  fill_bar(cr, table, left, top, bar_width, bar_height);
  if (key.below_range) draw_extension(cr, left - bar_height * 0.9, left, top, bar_height, table.front());
  if (key.above_range)
    draw_extension(cr, left + bar_width + bar_height * 0.9, left + bar_width, top, bar_height, table.back());
  cairo_rectangle(cr, left, top, bar_width, bar_height);
  set_colour(cr, kFrame);
  cairo_set_line_width(cr, 1);
  cairo_stroke(cr);
  const double lo = key.range.lo, hi = key.range.hi;
  if (hi > lo && std::isfinite(lo) && std::isfinite(hi)) {
    const std::vector<double> ticks = nice_ticks(lo, hi, 6);
    const double step = ticks.size() > 1 ? ticks[1] - ticks[0] : hi - lo;
    set_font(cr, fs);
    for (const double t : ticks) {
      const double tx = left + (t - lo) / (hi - lo) * bar_width;
      cairo_move_to(cr, tx, top + bar_height);
      cairo_line_to(cr, tx, top + bar_height + 0.35 * fs);
      set_colour(cr, kFrame);
      cairo_stroke(cr);
      draw_text(cr, tx, top + bar_height + 1.45 * fs, tick_label(t, step), Align::centre, kInk);
    }
  }
  if (key.missing) draw_missing_swatch(cr, left + bar_width + 2.5 * bar_height, top, bar_height, fs);
}

// Swatches with their class names, in rows centred in the box.
void draw_legend(cairo_t* cr, const ColourKey& key, double x, double y, double width, double height, double fs) {
  struct Item {
    Rgb8 colour;
    std::string label;
  };
  std::vector<Item> items;
  for (const int k : key.classes)
    items.push_back({colour_of(ScaleKind::categorical, key.range, k),
                     k < static_cast<int>(key.categories.size()) ? key.categories[k] : std::to_string(k)});
  if (key.missing) items.push_back({kMissingValueColour, "no value"});
  set_font(cr, fs);
  const double swatch = fs * 1.1, gap = fs * 1.4;
  std::vector<std::vector<std::size_t>> rows{{}};
  std::vector<double> row_widths{0};
  const double title_width = (set_font(cr, fs * 1.05, true), text_width(cr, key.title + "  "));
  set_font(cr, fs);
  const double available = width - title_width;
  for (std::size_t i = 0; i < items.size(); ++i) {
    const double w = swatch * 1.35 + text_width(cr, items[i].label) + gap;
    if (!rows.back().empty() && row_widths.back() + w > available) rows.emplace_back(), row_widths.push_back(0);
    rows.back().push_back(i);
    row_widths.back() += w;
  }
  const double line = fs * 1.8;
  double top = y + (height - line * static_cast<double>(rows.size())) / 2;
  const double widest = *std::max_element(row_widths.begin(), row_widths.end());
  const double left = x + (width - widest - title_width) / 2;
  set_font(cr, fs * 1.05, true);
  draw_text(cr, left, top + swatch * 0.9, key.title, Align::left, kInk);
  set_font(cr, fs);
  for (std::size_t r = 0; r < rows.size(); ++r, top += line) {
    double cursor = left + title_width;
    for (const std::size_t i : rows[r]) {
      cairo_rectangle(cr, cursor, top, swatch, swatch);
      set_colour(cr, items[i].colour);
      cairo_fill_preserve(cr);
      set_colour(cr, kFrame);
      cairo_set_line_width(cr, 1);
      cairo_stroke(cr);
      draw_text(cr, cursor + swatch * 1.35, top + swatch * 0.88, items[i].label, Align::left, kInk);
      cursor += swatch * 1.35 + text_width(cr, items[i].label) + gap;
    }
  }
}

}  // namespace

ColourKey colour_key(const SurfaceProperty& property, const ValueRange& range) {
  ColourKey key;
  key.title = property.info.unit.empty() ? property.info.name : property.info.name + " (" + property.info.unit + ")";
  key.scale = property.info.scale;
  key.range = range;
  key.categories = property.info.categories;
  std::set<int> classes;
  for (const double v : property.values) {
    if (std::isnan(v)) {
      key.missing = true;
    } else if (key.scale == ScaleKind::categorical) {
      const int k = colour_index(ScaleKind::categorical, range, v);
      if (k < 0)
        key.missing = true;
      else
        classes.insert(k);
    } else {
      key.below_range = key.below_range || v < range.lo;
      key.above_range = key.above_range || v > range.hi;
    }
  }
  key.classes.assign(classes.begin(), classes.end());
  return key;
}

void draw_colour_key(cairo_t* cr, const ColourKey& key, double x, double y, double width, double height,
                     double font_size) {
  if (key.scale == ScaleKind::categorical)
    draw_legend(cr, key, x, y, width, height, font_size);
  else
    draw_colour_bar(cr, key, x, y, width, height, font_size);
}

std::vector<double> nice_ticks(double lo, double hi, int count) {
  const double rough = (hi - lo) / std::max(1, count - 1);
  const double power = std::pow(10.0, std::floor(std::log10(rough)));
  double step = power;
  for (const double m : {1.0, 2.0, 5.0, 10.0})
    if (m * power >= rough) {
      step = m * power;
      break;
    }
  std::vector<double> ticks;
  const double tolerance = step * 1e-9;
  for (double k = std::ceil((lo - tolerance) / step); k * step <= hi + tolerance; k += 1)
    ticks.push_back(std::abs(k) < 0.5 ? 0.0 : k * step);
  return ticks;
}

std::string tick_label(double value, double step) {
  const int decimals = std::clamp(static_cast<int>(std::ceil(-std::log10(step) - 1e-9)), 0, 8);
  if (std::abs(value) >= 1e6 || (value != 0 && std::abs(value) < 1e-4)) return fmt::format("{:.2g}", value);
  std::string text = fmt::format("{:.{}f}", value, decimals);
  if (text.starts_with("-")) text = "\u2212" + text.substr(1);  // a true minus sign
  return text;
}

}  // namespace spheremap::render_detail
