// The viewer's page as built from viewer/ (private to render/): HTML, CSS and the bundled script, with the
// placeholders that viewer_html fills. Defined in a source file generated at build time (cmake/viewer.cmake).
#pragma once

#include <string_view>

namespace spheremap::detail {

inline constexpr std::string_view kViewerTitlePlaceholder = "{{SPHEREMAP_TITLE}}";
inline constexpr std::string_view kViewerDataPlaceholder = "{{SPHEREMAP_DATA}}";

/// The page; each placeholder occurs exactly once (the build checks it).
std::string_view viewer_page_template();

}  // namespace spheremap::detail
