// Files that appear whole or not at all (stage: io): every output of spheremap is written this way,
// so that an interrupted run never leaves a partial file for a reader (or a resumed batch) to trust.
#pragma once

#include <cstdio>
#include <filesystem>
#include <string>
#include <string_view>

namespace spheremap {

/// Writes `text` to `path` atomically (temporary file in the same folder, then rename).
/// Precondition: the folder of `path` exists. Throws InputError naming the file if it cannot be written.
void write_file_atomically(const std::filesystem::path& path, const std::string& text);

/// A file written in pieces under a temporary name beside `path` (`<path>.tmp-<pid>`, the same folder, so
/// that the rename is atomic) and renamed over `path` by commit(): a reader never sees a partial file,
/// and an AtomicFile destroyed before commit() (an exception on the way) removes what it wrote. For
/// outputs too large to hold whole in memory.
/// The constructor, append() and commit() throw InputError naming the file if it cannot be written;
/// append() or commit() after commit() throw std::logic_error.
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
