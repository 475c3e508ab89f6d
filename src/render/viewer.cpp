// index.html: the viewer's page with the data embedded (see viewer.hpp).
#include "spheremap/render/viewer.hpp"

#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "markup.hpp"
#include "spheremap/io/atomic_file.hpp"
#include "viewer_page.hpp"
#include "viewer_payload.hpp"

namespace spheremap {
namespace {

[[noreturn]] void refuse(const std::string& problem) { throw std::invalid_argument("viewer data: " + problem); }

void check_positions(const std::vector<Vec3>& positions, const char* what) {
  for (std::size_t v = 0; v < positions.size(); ++v)
    for (const double c : positions[v])
      if (!std::isfinite(c)) refuse(fmt::format("{} position {} is not finite", what, v));
}

void check_properties(const ViewerData& data) {
  for (const ViewerProperty& p : data.properties) {
    if (p.values.size() != data.surface_positions.size())
      refuse(fmt::format("property \"{}\" has {} values for {} vertices", p.name, p.values.size(),
                         data.surface_positions.size()));
    if (p.scale != ScaleKind::categorical &&
        !(std::isfinite(p.range.lo) && std::isfinite(p.range.hi) && p.range.hi > p.range.lo))
      refuse(fmt::format("property \"{}\" has the range [{}, {}]; it needs finite lo < hi", p.name, p.range.lo,
                         p.range.hi));
  }
}

void check(const ViewerData& data) {
  const std::size_t n = data.surface_positions.size();
  if (n < 3) refuse(fmt::format("{} surface vertices; at least 3 are needed", n));
  if (data.sphere_positions.size() != n)
    refuse(fmt::format("{} sphere vertices for {} surface vertices", data.sphere_positions.size(), n));
  check_positions(data.surface_positions, "surface");
  check_positions(data.sphere_positions, "sphere");
  if (data.triangles.empty()) refuse("no triangles");
  for (std::size_t t = 0; t < data.triangles.size(); ++t)
    for (const std::int32_t v : data.triangles[t])
      if (v < 0 || static_cast<std::size_t>(v) >= n) refuse(fmt::format("triangle {} has vertex {} of {}", t, v, n));
  if (!data.vertex_atoms.empty() && data.vertex_atoms.size() != n)
    refuse(fmt::format("{} vertex atoms for {} vertices", data.vertex_atoms.size(), n));
  for (std::size_t v = 0; v < data.vertex_atoms.size(); ++v) {
    const std::int32_t a = data.vertex_atoms[v];
    if (a < -1 || (a >= 0 && static_cast<std::size_t>(a) >= data.atoms.size()))
      refuse(fmt::format("vertex {} names atom {} of {}", v, a, data.atoms.size()));
  }
  check_properties(data);
}

// JSON inside <script>: "<" could start "</script>" or "<!--", which end or change the element whatever the
// JSON means; as \u escapes they are the same JSON. ">" and "&" likewise, for HTML-aware readers. These
// characters occur only inside JSON strings, where \u escapes are valid.
std::string escape_json_for_script(const std::string& json) {
  std::string out;
  out.reserve(json.size());
  for (const char c : json) {
    switch (c) {
      case '<': out += "\\u003c"; break;
      case '>': out += "\\u003e"; break;
      case '&': out += "\\u0026"; break;
      default: out += c;
    }
  }
  return out;
}

std::string data_elements(const ViewerData& data) {
  const detail::ViewerPayload payload = detail::pack_viewer_payload(data);
  // Base64 has no "<", so the blob needs no further escaping.
  return "<script type=\"application/json\" id=\"spheremap-manifest\">" +
         escape_json_for_script(payload.manifest_json) +
         "</script>\n<script type=\"application/octet-stream\" id=\"spheremap-data\">" +
         detail::base64_encode(detail::deflate_zlib(payload.blob)) + "</script>";
}

// The template with its two placeholders filled. Both are located in the template before anything is
// inserted, so no inserted text can be taken for a placeholder.
std::string fill_template(std::string_view page, const std::string& title, const std::string& data) {
  const std::size_t t = page.find(detail::kViewerTitlePlaceholder);
  const std::size_t d = page.find(detail::kViewerDataPlaceholder);
  if (t == std::string_view::npos || d == std::string_view::npos || d < t)
    throw std::logic_error("the viewer's page template lacks its placeholders");
  std::string out;
  out.reserve(page.size() + title.size() + data.size());
  out += page.substr(0, t);
  out += title;
  out += page.substr(t + detail::kViewerTitlePlaceholder.size(), d - t - detail::kViewerTitlePlaceholder.size());
  out += data;
  out += page.substr(d + detail::kViewerDataPlaceholder.size());
  return out;
}

}  // namespace

std::string viewer_html(const ViewerData& data) {
  check(data);
  const std::string title = render_detail::escape_markup(detail::valid_utf8(data.title));
  return fill_template(detail::viewer_page_template(), title, data_elements(data));
}

void write_viewer_html(const std::filesystem::path& path, const ViewerData& data) {
  write_file_atomically(path, viewer_html(data));
}

}  // namespace spheremap
