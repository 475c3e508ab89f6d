// AtomicFile and write_file_atomically: a temporary file beside the target, renamed over it when complete.
#include "spheremap/io/atomic_file.hpp"

#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <system_error>

#include <fmt/format.h>

#include "spheremap/error.hpp"

namespace spheremap {
namespace {

[[noreturn]] void fail(const std::filesystem::path& file, const std::string& problem, const std::string& fix) {
  throw InputError(fmt::format("{}: {}; {}", file.string(), problem, fix));
}

}  // namespace

AtomicFile::AtomicFile(std::filesystem::path path) : path_(std::move(path)), temporary_(path_) {
  temporary_ += fmt::format(".tmp-{}", static_cast<long>(::getpid()));
  stream_ = std::fopen(temporary_.c_str(), "wb");
  if (stream_ == nullptr) {
    fail(path_, fmt::format("cannot create '{}' ({})", temporary_.string(), std::strerror(errno)),
         "check that the folder exists and is writable");
  }
}

AtomicFile::~AtomicFile() {
  if (stream_ != nullptr) discard();
}

void AtomicFile::discard() noexcept {
  if (stream_ != nullptr) std::fclose(stream_);
  stream_ = nullptr;
  std::error_code ignored;
  std::filesystem::remove(temporary_, ignored);
}

void AtomicFile::discard_and_fail(const std::string& problem) {
  discard();
  fail(path_, problem, "check that the folder exists, is writable and the disk is not full");
}

void AtomicFile::append(std::string_view bytes) {
  if (stream_ == nullptr) throw std::logic_error("AtomicFile::append after commit");
  if (std::fwrite(bytes.data(), 1, bytes.size(), stream_) != bytes.size())
    discard_and_fail(fmt::format("cannot write the file ({})", std::strerror(errno)));
}

void AtomicFile::commit() {
  if (stream_ == nullptr) throw std::logic_error("AtomicFile::commit twice");
  const bool flushed = std::fflush(stream_) == 0;
  const int flush_errno = errno;
  const bool closed = std::fclose(stream_) == 0;
  const int close_errno = errno;
  stream_ = nullptr;
  if (!flushed || !closed)
    discard_and_fail(fmt::format("cannot write the file ({})", std::strerror(flushed ? close_errno : flush_errno)));
  std::error_code ec;
  std::filesystem::rename(temporary_, path_, ec);
  if (ec) discard_and_fail(fmt::format("cannot rename '{}' to it ({})", temporary_.string(), ec.message()));
}

void write_file_atomically(const std::filesystem::path& path, const std::string& text) {
  AtomicFile file(path);
  file.append(text);
  file.commit();
}

}  // namespace spheremap
