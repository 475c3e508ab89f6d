// valid_utf8: ill-formed UTF-8 replaced by U+FFFD, after the Unicode Standard's table of well-formed
// byte sequences (chapter 3, table 3-7).
#include "spheremap/text.hpp"

#include <cstdint>

namespace spheremap {
namespace {

constexpr std::string_view kReplacement = "\xEF\xBF\xBD";  // U+FFFD

// The length of the well-formed sequence at text[i], or 0 when text[i] starts an ill-formed one; then
// `maximal` is the length of its maximal ill-formed subpart (at least 1): the bytes to replace at once.
std::size_t sequence_at(std::string_view text, std::size_t i, std::size_t& maximal) {
  const auto byte = [&](std::size_t k) { return static_cast<std::uint8_t>(text[k]); };
  const std::uint8_t lead = byte(i);
  maximal = 1;
  if (lead < 0x80) return 1;
  std::size_t length = 0;
  std::uint8_t low = 0x80, high = 0xBF;  // the range of the second byte
  if (lead >= 0xC2 && lead <= 0xDF) {
    length = 2;
  } else if (lead >= 0xE0 && lead <= 0xEF) {
    length = 3;
    if (lead == 0xE0) low = 0xA0;   // no overlong forms
    if (lead == 0xED) high = 0x9F;  // no surrogates
  } else if (lead >= 0xF0 && lead <= 0xF4) {
    length = 4;
    if (lead == 0xF0) low = 0x90;   // no overlong forms
    if (lead == 0xF4) high = 0x8F;  // nothing above U+10FFFF
  } else {
    return 0;  // 0x80-0xC1, 0xF5-0xFF never start a sequence
  }
  for (std::size_t k = 1; k < length; ++k) {
    if (i + k >= text.size()) return 0;
    const std::uint8_t b = byte(i + k);
    const bool fits = k == 1 ? (b >= low && b <= high) : (b >= 0x80 && b <= 0xBF);
    if (!fits) return 0;
    maximal = k + 1;
  }
  maximal = length;
  return length;
}

}  // namespace

bool is_valid_utf8(std::string_view text) noexcept {
  std::size_t maximal = 0;
  for (std::size_t i = 0; i < text.size();) {
    const std::size_t length = sequence_at(text, i, maximal);
    if (length == 0) return false;
    i += length;
  }
  return true;
}

std::string valid_utf8(std::string_view text) {
  if (is_valid_utf8(text)) return std::string(text);
  std::string out;
  out.reserve(text.size() + 8);
  std::size_t maximal = 0;
  for (std::size_t i = 0; i < text.size();) {
    const std::size_t length = sequence_at(text, i, maximal);
    if (length == 0) {
      out += kReplacement;
      i += maximal;
    } else {
      out.append(text.substr(i, length));
      i += length;
    }
  }
  return out;
}

}  // namespace spheremap
