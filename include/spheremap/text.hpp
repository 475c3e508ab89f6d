// Text that comes from input files (atom, residue and chain names, file names, messages quoting a line)
// on its way into an output (JSON, CSV, HTML, the terminal): always valid UTF-8.
#pragma once

#include <string>
#include <string_view>

namespace spheremap {

/// True when `text` is well-formed UTF-8 (no overlong forms, no surrogates, nothing above U+10FFFF).
/// Does not throw.
bool is_valid_utf8(std::string_view text) noexcept;

/// `text` with every ill-formed UTF-8 sequence replaced by U+FFFD, one per maximal ill-formed subpart
/// (Unicode's recommended practice, as browsers decode). Valid text comes back unchanged, so applying it
/// twice changes nothing. The one function every output path uses for text from input files.
/// Does not throw (but std::bad_alloc).
std::string valid_utf8(std::string_view text);

}  // namespace spheremap
