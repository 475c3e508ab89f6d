// The viewer's data as the page reads it: a JSON manifest and one binary blob (private to render/).
#pragma once

#include <string>
#include <string_view>

#include "spheremap/render/viewer.hpp"

namespace spheremap::detail {

/// The manifest names every array of the blob (byte offset, element type and count, all 4-byte aligned,
/// little-endian) and carries the texts: title, a string table (atom names index into it) and the
/// properties' names, units, scales, ranges and categories. Texts are valid UTF-8 (invalid bytes replaced).
struct ViewerPayload {
  std::string manifest_json;  // compact JSON, not yet escaped for a <script> element
  std::string blob;           // raw bytes, not yet compressed
};

/// Packs `data`. Precondition: validated (viewer.cpp checks it first). Deterministic.
ViewerPayload pack_viewer_payload(const ViewerData& data);

/// zlib stream (RFC 1950: what DecompressionStream("deflate") reads, and a PNG's IDAT data) of `bytes`,
/// compressed by libdeflate at `level` (1..12; 1, the fastest, is what the viewer and the pictures use:
/// on 5hr7 it is about 3 times faster than zlib's level 1 and gives fewer bytes). Deterministic.
/// Throws std::invalid_argument for a level outside 1..12, std::runtime_error if libdeflate fails.
std::string deflate_zlib(std::string_view bytes, int level = 1);

/// Standard base64 (RFC 4648, with padding, no line breaks).
std::string base64_encode(const std::string& bytes);

/// `text` with invalid UTF-8 sequences replaced by U+FFFD.
std::string valid_utf8(const std::string& text);

}  // namespace spheremap::detail
