// The file formats of spheremap's pictures (stage: render).
#pragma once

#include <optional>
#include <string_view>

namespace spheremap {

enum class ImageFormat {
  png,  // 8-bit RGB raster
  svg,  // vector figure: text, graticule and colour bar as paths, the map itself as an embedded image
  pdf,  // the same as SVG, for print
};

/// "png", "svg" or "pdf" (also the file extension, without the dot). Never throws.
std::string_view to_string(ImageFormat format);

/// The format named `name` (as to_string writes it), or none. Never throws.
std::optional<ImageFormat> parse_image_format(std::string_view name);

}  // namespace spheremap
