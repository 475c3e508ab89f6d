// Reading and writing mesh files (stage: io).
#pragma once

#include <cstdio>
#include <filesystem>
#include <string>
#include <string_view>

#include "spheremap/mesh.hpp"

namespace spheremap {

/// Reads an OBJ, OFF, PLY (ASCII, binary little- or big-endian) or STL (ASCII or binary) file,
/// chosen by extension (case-insensitive; `.ply`, `.obj`, `.off`, `.stl`).
/// Faces keep all their corners (triangulation happens in prepare_mesh). OBJ `v/vt/vn` and negative
/// (relative) indices are understood; texture and normal data are ignored. STL has no shared vertices:
/// each facet brings three new positions, to be welded by prepare_mesh.
/// Throws InputError naming the file and the problem if the file is missing, unreadable, truncated,
/// of an unknown extension, has an index out of range, a non-finite coordinate, or no faces.
PolygonSoup read_polygon_soup(const std::filesystem::path& path);

struct PlyWriteOptions {
  bool ascii = false;  // ASCII writes every double with %.17g (round-trips exactly)
};

/// Writes `mesh` as PLY: `x y z` as double, then every real attribute as a `double` property and
/// every integer attribute as an `int` property (in name order), then the faces as
/// `list uchar int vertex_indices`. Binary little-endian unless options.ascii.
/// The file is written to a temporary name beside `path` and renamed over it only when complete,
/// so a reader never sees a partial file. Throws InputError if the file cannot be written.
void write_ply(const std::filesystem::path& path, const Mesh& mesh, const PlyWriteOptions& options = {});

/// Writes `text` to `path` atomically (temporary file in the same folder, then rename).
/// Throws InputError if it cannot.
void write_file_atomically(const std::filesystem::path& path, const std::string& text);

/// A file written in pieces under a temporary name beside `path` (`<path>.tmp-<pid>`, the same folder, so
/// that the rename is atomic) and renamed over `path` by commit(): a reader never sees a partial file,
/// and an AtomicFile destroyed before commit() (an exception on the way) removes what it wrote. For
/// outputs too large to hold whole in memory (a 0.25 Å surface of GroEL is a 1.8 GB PLY).
/// The constructor, append() and commit() throw InputError naming the file if it cannot be written.
class AtomicFile {
 public:
  explicit AtomicFile(std::filesystem::path path);
  AtomicFile(const AtomicFile&) = delete;
  AtomicFile& operator=(const AtomicFile&) = delete;
  ~AtomicFile();
  void append(std::string_view bytes);
  void commit();

 private:
  void discard() noexcept;  // closes and removes the temporary file
  [[noreturn]] void discard_and_fail(const std::string& problem);
  std::filesystem::path path_, temporary_;
  std::FILE* stream_ = nullptr;
};

}  // namespace spheremap
