// Private to src/render: a cairo drawing surface for one picture in any ImageFormat, with the text, colour
// bar and legend every picture shares. Text is DejaVu Sans, found through fontconfig and refused if it is
// not that font, with hinting off: the same picture gives the same bytes on every machine with the font.
#pragma once

#include <cairo.h>

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "spheremap/properties/property.hpp"
#include "spheremap/render/colour_scale.hpp"
#include "spheremap/render/image_format.hpp"

namespace spheremap::render_detail {

/// One picture being drawn. The constructor paints it white. Throws std::runtime_error if cairo cannot
/// make the surface, and spheremap::Error (exit 1) if the font DejaVu Sans is not installed.
class Canvas {
 public:
  Canvas(ImageFormat format, int width, int height);
  Canvas(const Canvas&) = delete;
  Canvas& operator=(const Canvas&) = delete;
  ~Canvas();

  [[nodiscard]] cairo_t* cr() const { return cr_; }
  [[nodiscard]] int width() const { return width_; }
  [[nodiscard]] int height() const { return height_; }

  /// Ends the drawing and returns the file's bytes. Call once. Throws std::runtime_error if cairo failed.
  std::string finish();

 private:
  ImageFormat format_;
  int width_, height_;
  std::string bytes_;
  cairo_surface_t* surface_ = nullptr;
  cairo_t* cr_ = nullptr;
};

/// An image in cairo's ARGB32 layout (premultiplied alpha, native-endian 32-bit words), for pictures drawn
/// pixel by pixel. The surface returned refers to `pixels`, which must outlive it.
cairo_surface_t* image_surface(std::vector<std::uint32_t>& pixels, int width, int height);

/// ARGB32 word of an opaque colour.
inline std::uint32_t opaque(const Rgb8& c) {
  return 0xff000000u | (static_cast<std::uint32_t>(c.r) << 16) | (static_cast<std::uint32_t>(c.g) << 8) | c.b;
}

enum class Align { left, centre, right };

/// Selects DejaVu Sans (bold or not) at `size` pixels.
void set_font(cairo_t* cr, double size, bool bold = false);

/// The advance width of `text` (UTF-8) in the current font.
double text_width(cairo_t* cr, std::string_view text);

/// Draws `text` with its baseline at y, aligned on x, in `ink`; with halo > 0 a white outline of that width
/// first, so that it reads over a picture.
void draw_text(cairo_t* cr, double x, double y, std::string_view text, Align align, Rgb8 ink = {0, 0, 0},
               double halo = 0);

/// What a colour bar or a legend shows.
struct ColourKey {
  std::string title;  // e.g. "electrostatics (kT/e)"
  ScaleKind scale = ScaleKind::sequential;
  ValueRange range;
  std::vector<std::string> categories;            // categorical: the name of each class shown
  std::vector<int> classes;                       // categorical: the classes present, in order
  bool below_range = false, above_range = false;  // some values saturate at either end
  bool missing = false;                           // some vertices have no value (grey)
};

/// The key of `property` with colour range `range`, from the values it has.
ColourKey colour_key(const SurfaceProperty& property, const ValueRange& range);

/// Draws the key (a horizontal colour bar with ticks, or a legend of swatches) centred in the box
/// [x, x + width] x [y, y + height], text at `font_size`.
void draw_colour_key(cairo_t* cr, const ColourKey& key, double x, double y, double width, double height,
                     double font_size);

/// Values 1, 2 or 5 times a power of ten apart, covering [lo, hi] with about `count` ticks inside it, and
/// their labels (as many decimals as the step needs). Precondition: hi > lo, both finite.
std::vector<double> nice_ticks(double lo, double hi, int count);
std::string tick_label(double value, double step);

}  // namespace spheremap::render_detail
