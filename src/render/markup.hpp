// Private to src/render: text put inside SVG and HTML markup.
#pragma once

#include <string>

namespace spheremap::render_detail {

/// `text` with the five characters markup gives a meaning to (& < > " ') as references: safe in element
/// text and in quoted attribute values of SVG (XML) and HTML alike. Throws nothing beyond std::bad_alloc.
inline std::string escape_markup(const std::string& text) {
  std::string out;
  out.reserve(text.size());
  for (const char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&#39;"; break;
      default: out += c;
    }
  }
  return out;
}

}  // namespace spheremap::render_detail
