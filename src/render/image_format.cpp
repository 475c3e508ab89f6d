#include "spheremap/render/image_format.hpp"

namespace spheremap {

std::string_view to_string(ImageFormat format) {
  switch (format) {
    case ImageFormat::png: return "png";
    case ImageFormat::svg: return "svg";
    case ImageFormat::pdf: return "pdf";
  }
  return "png";
}

std::optional<ImageFormat> parse_image_format(std::string_view name) {
  if (name == "png") return ImageFormat::png;
  if (name == "svg") return ImageFormat::svg;
  if (name == "pdf") return ImageFormat::pdf;
  return std::nullopt;
}

}  // namespace spheremap
