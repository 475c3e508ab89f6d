// Private to src/molecule: a structure file's text, read whole (and, for .gz, inflated with every check
// zlib offers), with the signs of a truncated file noted as warnings.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace spheremap::molecule_detail {

/// What the readers parse: the file's bytes (inflated for .gz), and warnings about its integrity.
struct StructureText {
  std::string bytes;
  std::vector<std::string> warnings;
};

/// Reads `path` whole; a name ending in .gz (any case) must be a complete gzip file (one or more members,
/// each ending with its CRC-32 and length, both checked). Then the warnings of truncation_warnings.
/// Throws InputError naming the file when it is missing, a folder, unreadable, empty, not gzip although
/// named .gz, a gzip stream that ends early or is corrupt (CRC), or one that inflates past a limit (1 GiB, or
/// 100 times its compressed size beyond 64 MiB: a gzip bomb), checked as it inflates.
StructureText read_structure_text(const std::filesystem::path& path);

/// Signs that a text structure file was cut short: its last line has no line break, or (PDB and PQR) its
/// last ATOM/HETATM record is shorter than the file's other atom records. Each sign is one warning that
/// quotes the line. Does not throw (but std::bad_alloc).
std::vector<std::string> truncation_warnings(const std::string& text);

/// `text` quoted for a message: at most 80 bytes, control bytes as '?', valid UTF-8.
std::string quoted_line(const std::string& text);

}  // namespace spheremap::molecule_detail
