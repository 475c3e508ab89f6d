// The viewer's data as the page reads it: a JSON manifest and one binary blob (private to render/).
#pragma once

#include <string>

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

/// zlib stream (RFC 1950, what DecompressionStream("deflate") reads) of `bytes`, at level 1 (Z_BEST_SPEED): on
/// 5hr7's viewer data a third of the default level's time for 4% more bytes.
/// Throws std::runtime_error if zlib fails.
std::string deflate_zlib(const std::string& bytes);

/// Standard base64 (RFC 4648, with padding, no line breaks).
std::string base64_encode(const std::string& bytes);

/// `text` with invalid UTF-8 sequences replaced by U+FFFD.
std::string valid_utf8(const std::string& text);

}  // namespace spheremap::detail
