// Private to the library: the bytes of an open file, for the structure and mesh readers.
#pragma once

#include <cstddef>
#include <cstdio>
#include <string>

namespace spheremap::detail {

/// Everything left in `stream`. Reads in chunks rather than trusting the size (special files report 0): the first
/// chunk is `size_hint` and a byte more (`size_hint` 0: a megabyte), so a small file costs no megabyte of buffer.
/// Stops at the end of the file or at a read error; the caller checks std::ferror. Throws std::bad_alloc only.
inline std::string read_all(std::FILE* stream, std::size_t size_hint) {
  constexpr std::size_t kChunk = std::size_t{1} << 20;
  std::string bytes;
  std::size_t request = size_hint == 0 ? kChunk : size_hint + 1;
  std::size_t used = 0;
  for (;;) {
    bytes.resize(used + request);
    const std::size_t got = std::fread(bytes.data() + used, 1, request, stream);
    used += got;
    if (got < request) break;
    request = kChunk;
  }
  bytes.resize(used);
  return bytes;
}

}  // namespace spheremap::detail
