// read_structure_text: a structure file read whole and checked for truncation; .gz inflated by zlib,
// whose gzip wrapper verifies each member's CRC-32 and length.
#include "structure_text.hpp"
#include "../util/read_all.hpp"

#include <zlib.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <memory>
#include <system_error>

#include <fmt/format.h>

#include "spheremap/error.hpp"
#include "spheremap/text.hpp"

namespace spheremap::molecule_detail {
namespace {

// A .gz is refused as soon as what it inflates to passes either limit (docs/robustness.md), so that a
// gzip bomb (a small file of ~1000:1 that inflates to gigabytes) costs at most this much memory. Structure
// files compress 4-10:1; the largest entries of the PDB are a few hundred MB uncompressed.
constexpr std::size_t kMaxInflated = std::size_t{1} << 30;        // 1 GiB
constexpr std::size_t kRatioCheckedFrom = std::size_t{64} << 20;  // 64 MiB
constexpr std::size_t kMaxRatio = 100;

bool has_gz_name(const std::filesystem::path& path) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext == ".gz";
}

std::string read_bytes(const std::filesystem::path& path) {
  const auto close_file = [](std::FILE* stream) { std::fclose(stream); };
  std::unique_ptr<std::FILE, decltype(close_file)> stream(std::fopen(path.c_str(), "rb"), close_file);
  if (!stream)
    throw InputError(
        fmt::format("{}: cannot open the file ({}); check that it is readable", path.string(), std::strerror(errno)));
  std::error_code ec;
  const auto size_hint = std::filesystem::file_size(path, ec);
  std::string bytes = detail::read_all(stream.get(), ec ? 0 : static_cast<std::size_t>(size_hint));
  if (std::ferror(stream.get()))
    throw InputError(
        fmt::format("{}: cannot read the file ({}); check the disk and the file", path.string(), std::strerror(errno)));
  return bytes;
}

[[noreturn]] void gzip_fail(const std::filesystem::path& path, const std::string& problem) {
  throw InputError(
      fmt::format("{}: {}; download or compress the file again (gzip -t checks a .gz file)", path.string(), problem));
}

// Throws InputError once `inflated` bytes (from `consumed` compressed ones) pass a limit of kMaxInflated.
void check_inflated_size(const std::filesystem::path& path, std::size_t inflated, std::size_t consumed) {
  const bool too_large = inflated > kMaxInflated;
  const bool too_compressed = inflated > kRatioCheckedFrom && inflated / std::max<std::size_t>(consumed, 1) > kMaxRatio;
  if (!too_large && !too_compressed) return;
  const std::string problem =
      too_large ? fmt::format("it inflates to more than {} MiB (the limit for a .gz file)", kMaxInflated >> 20)
                : fmt::format(
                      "it inflates to more than {} times its compressed size ({} MiB from {} bytes so far; the "
                      "limit for a .gz file beyond {} MiB is {}:1, and structure files compress about 4-10:1)",
                      kMaxRatio, inflated >> 20, consumed, kRatioCheckedFrom >> 20, kMaxRatio);
  throw InputError(
      fmt::format("{}: {}, so inflating it stopped there (a gzip bomb?); if it really is a structure, "
                  "decompress it (gunzip -k) and map the uncompressed file, which has no such limit",
                  path.string(), problem));
}

// Inflates every gzip member of `compressed`. Bytes after the last member that do not start another
// member are left out with a warning (gzip itself ignores such trailing garbage with a warning).
std::string inflate_gzip(const std::filesystem::path& path, const std::string& compressed,
                         std::vector<std::string>& warnings) {
  if (compressed.size() < 2 || static_cast<unsigned char>(compressed[0]) != 0x1F ||
      static_cast<unsigned char>(compressed[1]) != 0x8B)
    throw InputError(
        fmt::format("{}: the name ends in .gz but the file is not gzip-compressed (it does not start "
                    "with gzip's bytes 1F 8B); rename it without .gz if it is plain text, or compress "
                    "it with gzip",
                    path.string()));
  z_stream z{};
  if (inflateInit2(&z, 16 + MAX_WBITS) != Z_OK) throw std::runtime_error("zlib: inflateInit2 failed");
  const std::unique_ptr<z_stream, int (*)(z_stream*)> guard(&z, inflateEnd);
  std::string out;
  std::size_t offset = 0;
  constexpr std::size_t kChunk = std::size_t{64} << 10;  // the string grows geometrically; this is per call
  for (;;) {
    z.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(compressed.data() + offset));
    z.avail_in = static_cast<uInt>(std::min<std::size_t>(compressed.size() - offset, 1u << 30));
    int status = Z_OK;
    while (status == Z_OK) {
      const std::size_t used = out.size();
      check_inflated_size(path, used, offset);
      out.resize(used + kChunk);
      z.next_out = reinterpret_cast<Bytef*>(out.data() + used);
      z.avail_out = static_cast<uInt>(kChunk);
      const uInt before_in = z.avail_in;
      status = inflate(&z, Z_NO_FLUSH);
      out.resize(used + (kChunk - z.avail_out));
      offset += before_in - z.avail_in;
      if (status == Z_BUF_ERROR && offset >= compressed.size()) break;
      if (status == Z_BUF_ERROR) status = Z_OK;                                    // output was full; go on
      if (status == Z_OK && z.avail_in == 0 && offset < compressed.size()) break;  // refill the input
    }
    if (status == Z_OK && offset < compressed.size()) continue;
    if (status == Z_STREAM_END) {
      if (offset == compressed.size()) return out;
      const bool next_member = compressed.size() - offset >= 2 &&
                               static_cast<unsigned char>(compressed[offset]) == 0x1F &&
                               static_cast<unsigned char>(compressed[offset + 1]) == 0x8B;
      if (!next_member) {
        warnings.push_back(
            fmt::format("{} byte(s) after the end of the gzip data were ignored", compressed.size() - offset));
        return out;
      }
      inflateReset(&z);
      continue;
    }
    if (status == Z_DATA_ERROR)
      gzip_fail(path, fmt::format("the gzip data is corrupt ({})", z.msg != nullptr ? z.msg : "bad data"));
    if (status == Z_MEM_ERROR) throw std::bad_alloc();
    gzip_fail(path, fmt::format("the gzip stream ends early, without its CRC and length (the file is truncated: "
                                "{} bytes inflated so far)",
                                out.size()));
  }
}

bool is_atom_record(std::string_view line) { return line.rfind("ATOM", 0) == 0 || line.rfind("HETATM", 0) == 0; }

std::string_view without_cr(std::string_view line) {
  if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
  return line;
}

}  // namespace

std::string quoted_line(const std::string& text) {
  std::string shown = text.substr(0, 80);
  for (char& c : shown)
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7F) c = '?';
  return fmt::format("'{}{}'", valid_utf8(shown), text.size() > 80 ? "..." : "");
}

std::vector<std::string> truncation_warnings(const std::string& text) {
  std::vector<std::string> warnings;
  if (text.empty()) return warnings;
  const std::string_view all(text);
  const std::size_t body_end = all.back() == '\n' ? all.size() - 1 : all.size();
  const std::size_t last_start = all.rfind('\n', body_end == 0 ? 0 : body_end - 1);
  const std::size_t start = last_start == std::string_view::npos || last_start >= body_end ? 0 : last_start + 1;
  const std::string_view last = without_cr(all.substr(start, body_end - start));
  if (all.back() != '\n')
    warnings.push_back(
        fmt::format("the file does not end with a line break, so its last line may be cut short "
                    "(a truncated file?): {}",
                    quoted_line(std::string(last))));
  if (!is_atom_record(last)) return warnings;
  // A cut record is shorter than every other atom record of the file (files that mix record lengths,
  // e.g. waters without an element column, keep their shortest records' length).
  std::size_t records = 0, shortest = std::string_view::npos;
  for (std::size_t at = 0; at < start;) {
    std::size_t end = all.find('\n', at);
    if (end == std::string_view::npos || end > start) end = start;
    const std::string_view line = without_cr(all.substr(at, end - at));
    if (is_atom_record(line)) ++records, shortest = std::min(shortest, line.size());
    at = end + 1;
  }
  if (records > 0 && last.size() < shortest)
    warnings.push_back(
        fmt::format("the last atom record is shorter than the file's {} other ones ({} characters "
                    "instead of at least {}), so it may be cut short (a truncated file?): {}",
                    records, last.size(), shortest, quoted_line(std::string(last))));
  return warnings;
}

StructureText read_structure_text(const std::filesystem::path& path) {
  std::error_code ec;
  const auto status = std::filesystem::status(path, ec);
  if (!std::filesystem::exists(status))
    throw InputError(fmt::format("{}: no such file; check the path", path.string()));
  if (std::filesystem::is_directory(status))
    throw InputError(
        fmt::format("{}: this is a folder, not a structure file; give the path of a file (spheremap "
                    "batch maps every file of a folder)",
                    path.string()));
  StructureText text;
  text.bytes = read_bytes(path);
  if (text.bytes.empty()) throw InputError(fmt::format("{}: the file is empty", path.string()));
  if (has_gz_name(path)) {
    text.bytes = inflate_gzip(path, text.bytes, text.warnings);
    if (text.bytes.empty()) throw InputError(fmt::format("{}: the file is empty (inflated)", path.string()));
  }
  for (auto& warning : truncation_warnings(text.bytes)) text.warnings.push_back(std::move(warning));
  return text;
}

}  // namespace spheremap::molecule_detail
