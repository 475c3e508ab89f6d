// Drawing surfaces, text, colour bars and legends for the pictures (see canvas.hpp).
#include "canvas.hpp"

#include <cairo-ft.h>
#include <cairo-pdf.h>
#include <cairo-svg.h>
#include <fontconfig/fontconfig.h>
#include <ft2build.h>
#include <png.h>
#include FT_FREETYPE_H

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <map>
#include <memory>
#include <mutex>
#include <regex>
#include <set>
#include <stdexcept>

#include <fmt/format.h>

#include "spheremap/error.hpp"
#include "viewer_payload.hpp"

namespace spheremap::render_detail {
namespace {

constexpr const char* kFontFamily = "DejaVu Sans";

cairo_status_t append_to_string(void* closure, const unsigned char* data, unsigned int length) {
  static_cast<std::string*>(closure)->append(reinterpret_cast<const char*>(data), length);
  return CAIRO_STATUS_SUCCESS;
}

// The font file fontconfig gives for DejaVu Sans, refused if it is another family (fontconfig substitutes
// silently, and another font would change every picture).
std::string font_file(bool bold) {
  FcInit();
  FcPattern* pattern = FcPatternCreate();
  FcPatternAddString(pattern, FC_FAMILY, reinterpret_cast<const FcChar8*>(kFontFamily));
  FcPatternAddInteger(pattern, FC_WEIGHT, bold ? FC_WEIGHT_BOLD : FC_WEIGHT_REGULAR);
  FcPatternAddInteger(pattern, FC_SLANT, FC_SLANT_ROMAN);
  FcConfigSubstitute(nullptr, pattern, FcMatchPattern);
  FcDefaultSubstitute(pattern);
  FcResult result = FcResultNoMatch;
  FcPattern* match = FcFontMatch(nullptr, pattern, &result);
  FcPatternDestroy(pattern);
  std::string family, file;
  FcChar8* value = nullptr;
  if (match != nullptr && FcPatternGetString(match, FC_FAMILY, 0, &value) == FcResultMatch)
    family = reinterpret_cast<const char*>(value);
  if (match != nullptr && FcPatternGetString(match, FC_FILE, 0, &value) == FcResultMatch)
    file = reinterpret_cast<const char*>(value);
  if (match != nullptr) FcPatternDestroy(match);
  if (family != kFontFamily || file.empty())
    throw Error(ExitCode::kUsage, fmt::format("pictures need the font {}, and fontconfig found {} instead; install "
                                              "it (Debian: apt-get install fonts-dejavu-core) or use --no-pictures",
                                              kFontFamily, family.empty() ? "no font" : family));
  return file;
}

// The two faces, loaded once for the process (cairo locks a FreeType face while it uses it).
cairo_font_face_t* font_face(bool bold) {
  static std::mutex mutex;
  static FT_Library library = nullptr;
  static std::array<cairo_font_face_t*, 2> faces{nullptr, nullptr};
  const std::lock_guard lock(mutex);
  cairo_font_face_t*& face = faces[bold ? 1 : 0];
  if (face != nullptr) return face;
  const std::string file = font_file(bold);
  if (library == nullptr && FT_Init_FreeType(&library) != 0) throw std::runtime_error("FreeType cannot start");
  FT_Face ft_face = nullptr;
  if (FT_New_Face(library, file.c_str(), 0, &ft_face) != 0)
    throw Error(ExitCode::kUsage, fmt::format("{}: cannot read the font file; reinstall fonts-dejavu-core", file));
  face = cairo_ft_font_face_create_for_ft_face(ft_face, 0);
  return face;
}

void set_deterministic_font_options(cairo_t* cr) {
  cairo_font_options_t* options = cairo_font_options_create();
  cairo_font_options_set_antialias(options, CAIRO_ANTIALIAS_GRAY);
  cairo_font_options_set_hint_style(options, CAIRO_HINT_STYLE_NONE);
  cairo_font_options_set_hint_metrics(options, CAIRO_HINT_METRICS_OFF);
  cairo_font_options_set_subpixel_order(options, CAIRO_SUBPIXEL_ORDER_DEFAULT);
  cairo_set_font_options(cr, options);
  cairo_font_options_destroy(options);
}

// cairo numbers SVG images and surfaces by process-wide counters: renumbered in order of first appearance,
// the same picture gives the same bytes however many were drawn before it.
std::string renumber_svg_ids(const std::string& svg) {
  // Only ids and references to them: `id="`, `#` never occur in base64 image data.
  static const std::regex id(R"((id="|#)(surface|image|pattern|source)(\d+))");
  std::map<std::string, int> numbers;
  std::string out;
  out.reserve(svg.size());
  auto last = svg.cbegin();
  for (std::sregex_iterator it(svg.begin(), svg.end(), id), end; it != end; ++it) {
    const std::smatch& m = *it;
    out.append(last, m[0].first);
    const auto [found, inserted] = numbers.try_emplace(m[2].str() + m[3].str(), static_cast<int>(numbers.size()) + 1);
    out += m[1].str() + m[2].str() + "-" + std::to_string(found->second);
    last = m[0].second;
  }
  out.append(last, svg.cend());
  return out;
}

void append_png_bytes(png_structp png, png_bytep data, png_size_t length) {
  static_cast<std::string*>(png_get_io_ptr(png))->append(reinterpret_cast<const char*>(data), length);
}

// 8-bit RGB PNG of an opaque ARGB32 surface. libpng writes the signature, the header and the chunks (with
// their CRCs); the image data is compressed in one piece by libdeflate (several times faster than zlib for
// fewer bytes), its rows unfiltered: maps and shaded spheres have long runs of one colour, which deflate's
// matches take whole, and on them the "sub" filter gave more bytes, not fewer.
// No time stamp or text chunk: the same pixels give the same bytes.
std::string png_of(cairo_surface_t* surface, int width, int height) {
  cairo_surface_flush(surface);
  const unsigned char* data = cairo_image_surface_get_data(surface);
  const int stride = cairo_image_surface_get_stride(surface);
  // The filtered image data: each row a filter-type byte (0, none) then its RGB bytes. Not zero-filled first: every
  // byte is written below (and one more at the end, see there).
  const std::size_t row_size = 1 + static_cast<std::size_t>(width) * 3;
  const std::size_t size = row_size * static_cast<std::size_t>(height);
  const std::unique_ptr<std::uint8_t[]> filtered(new std::uint8_t[size + 1]);
  for (int y = 0; y < height; ++y) {
    const auto* row = reinterpret_cast<const std::uint32_t*>(data + static_cast<std::ptrdiff_t>(y) * stride);
    std::uint8_t* out_row = filtered.get() + row_size * static_cast<std::size_t>(y);
    out_row[0] = 0;
    for (int x = 0; x < width; ++x) {
      // The picture is painted white first, so every pixel is opaque. Its bytes R, G, B and a zero, stored as
      // one word: the zero is overwritten by the next pixel, or by the next row's filter byte (also a zero), or
      // falls into the spare byte after the last row.
      const std::uint32_t rgb0 = __builtin_bswap32(row[x]) >> 8;
      std::memcpy(out_row + 1 + 3 * static_cast<std::size_t>(x), &rgb0, 4);
    }
  }
  static_assert(std::endian::native == std::endian::little, "the word of a pixel's bytes is stored little-endian");
  const std::string idat =
      detail::deflate_zlib(std::string_view(reinterpret_cast<const char*>(filtered.get()), size), 1);
  std::string out;
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, nullptr, nullptr, nullptr);
  png_infop info = png != nullptr ? png_create_info_struct(png) : nullptr;
  if (png == nullptr || info == nullptr) {
    png_destroy_write_struct(&png, nullptr);
    throw std::runtime_error("libpng cannot start");
  }
  if (setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    throw std::runtime_error("libpng failed to encode a picture");
  }
  png_set_write_fn(png, &out, append_png_bytes, nullptr);
  png_set_IHDR(png, info, static_cast<png_uint_32>(width), static_cast<png_uint_32>(height), 8, PNG_COLOR_TYPE_RGB,
               PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_DEFAULT, PNG_FILTER_TYPE_DEFAULT);
  png_write_info(png, info);
  // A chunk holds at most 2^31 - 1 bytes; pictures of the usual sizes need one IDAT.
  constexpr std::size_t kMaxChunk = 0x7fffffff;
  for (std::size_t at = 0; at < idat.size(); at += kMaxChunk)
    png_write_chunk(png, reinterpret_cast<png_const_bytep>("IDAT"), reinterpret_cast<png_const_bytep>(idat.data()) + at,
                    std::min(kMaxChunk, idat.size() - at));
  // png_write_end would refuse: libpng wrote no IDAT itself.
  png_write_chunk(png, reinterpret_cast<png_const_bytep>("IEND"), nullptr, 0);
  png_destroy_write_struct(&png, &info);
  return out;
}

}  // namespace

Canvas::Canvas(ImageFormat format, int width, int height) : format_(format), width_(width), height_(height) {
  switch (format) {
    case ImageFormat::png: surface_ = cairo_image_surface_create(CAIRO_FORMAT_ARGB32, width, height); break;
    case ImageFormat::svg:
      surface_ = cairo_svg_surface_create_for_stream(append_to_string, &bytes_, width, height);
      cairo_svg_surface_restrict_to_version(surface_, CAIRO_SVG_VERSION_1_1);
      break;
    case ImageFormat::pdf:
      surface_ = cairo_pdf_surface_create_for_stream(append_to_string, &bytes_, width, height);
      // No creation date: the same picture gives the same bytes.
      cairo_pdf_surface_set_metadata(surface_, CAIRO_PDF_METADATA_CREATE_DATE, "");
      break;
  }
  if (cairo_surface_status(surface_) != CAIRO_STATUS_SUCCESS) {
    cairo_surface_destroy(surface_);
    throw std::runtime_error(fmt::format("cairo cannot make a {} x {} {} surface", width, height, to_string(format)));
  }
  cr_ = cairo_create(surface_);
  set_deterministic_font_options(cr_);
  cairo_set_source_rgb(cr_, 1, 1, 1);
  cairo_paint(cr_);
}

Canvas::~Canvas() {
  if (cr_ != nullptr) cairo_destroy(cr_);
  if (surface_ != nullptr) cairo_surface_destroy(surface_);
}

std::string Canvas::finish() {
  if (cairo_status(cr_) != CAIRO_STATUS_SUCCESS)
    throw std::runtime_error(std::string("cairo: ") + cairo_status_to_string(cairo_status(cr_)));
  cairo_destroy(cr_);
  cr_ = nullptr;
  if (format_ == ImageFormat::png) return png_of(surface_, width_, height_);
  cairo_surface_finish(surface_);
  if (cairo_surface_status(surface_) != CAIRO_STATUS_SUCCESS)
    throw std::runtime_error(std::string("cairo: ") + cairo_status_to_string(cairo_surface_status(surface_)));
  return format_ == ImageFormat::svg ? renumber_svg_ids(bytes_) : bytes_;
}

cairo_surface_t* image_surface(std::vector<std::uint32_t>& pixels, int width, int height) {
  return cairo_image_surface_create_for_data(reinterpret_cast<unsigned char*>(pixels.data()), CAIRO_FORMAT_ARGB32,
                                             width, height, width * 4);
}

void set_font(cairo_t* cr, double size, bool bold) {
  cairo_set_font_face(cr, font_face(bold));
  cairo_set_font_size(cr, size);
}

double text_width(cairo_t* cr, std::string_view text) {
  const std::string s(text);
  cairo_text_extents_t extents;
  cairo_text_extents(cr, s.c_str(), &extents);
  return extents.x_advance;
}

void draw_text(cairo_t* cr, double x, double y, std::string_view text, Align align, Rgb8 ink, double halo) {
  const std::string s(text);
  const double width = text_width(cr, s);
  const double left = align == Align::left ? x : align == Align::centre ? x - width / 2 : x - width;
  cairo_new_path(cr);
  cairo_move_to(cr, left, y);
  if (halo > 0) {
    cairo_text_path(cr, s.c_str());
    cairo_set_source_rgba(cr, 1, 1, 1, 0.85);
    cairo_set_line_width(cr, halo);
    cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
    cairo_stroke(cr);
    cairo_move_to(cr, left, y);
  }
  cairo_set_source_rgb(cr, ink.r / 255.0, ink.g / 255.0, ink.b / 255.0);
  cairo_show_text(cr, s.c_str());
  cairo_new_path(cr);
}

}  // namespace spheremap::render_detail
