// Parsing and matching residue selections (see residue_selection.hpp).
#include "spheremap/render/residue_selection.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <set>
#include <tuple>

#include <fmt/format.h>

#include "spheremap/error.hpp"

namespace spheremap {
namespace {

// NUMBER[INSERTION] at the start of `text` (a sign allowed); moves `text` past it. False if no number.
bool take_residue(std::string_view& text, std::int32_t& number, std::string& insertion) {
  const char* begin = text.data();
  const char* end = text.data() + text.size();
  const auto [ptr, error] = std::from_chars(begin, end, number);
  if (error != std::errc() || ptr == begin) return false;
  text.remove_prefix(static_cast<std::size_t>(ptr - begin));
  insertion.clear();
  if (!text.empty() && std::isalpha(static_cast<unsigned char>(text.front()))) {
    insertion = std::string(1, text.front());
    text.remove_prefix(1);
  }
  return true;
}

ResidueRange parse_item(std::string_view item, std::string_view whole) {
  const auto fail = [&](const std::string& why) -> ResidueRange {
    throw InputError(
        fmt::format("residue selection '{}': item '{}' {}; write CHAIN:NUMBER or CHAIN:FIRST-LAST, "
                    "items separated by commas (e.g. A:45-60,B:12)",
                    whole, item, why));
  };
  const auto colon = item.find(':');
  if (colon == std::string_view::npos || colon == 0) return fail("has no chain before ':'");
  ResidueRange range;
  range.chain = std::string(item.substr(0, colon));
  std::string_view rest = item.substr(colon + 1);
  if (!take_residue(rest, range.first, range.first_insertion)) return fail("has no residue number");
  range.last = range.first;
  range.last_insertion = range.first_insertion;
  if (!rest.empty()) {
    if (rest.front() != '-') return fail("has unexpected text after the number");
    rest.remove_prefix(1);
    if (!take_residue(rest, range.last, range.last_insertion) || !rest.empty())
      return fail("has no residue number after '-'");
  }
  if (std::tie(range.last, range.last_insertion) < std::tie(range.first, range.first_insertion))
    return fail("ends before it starts");
  return range;
}

}  // namespace

std::vector<ResidueRange> parse_residue_selection(std::string_view text) {
  std::vector<ResidueRange> ranges;
  std::size_t start = 0;
  while (start <= text.size()) {
    const auto comma = std::min(text.find(',', start), text.size());
    const std::string_view item = text.substr(start, comma - start);
    if (item.empty())
      throw InputError(
          fmt::format("residue selection '{}': an empty item (two commas, or a comma "
                      "at an end); write e.g. A:45-60,B:12",
                      text));
    ranges.push_back(parse_item(item, text));
    start = comma + 1;
  }
  return ranges;
}

bool in_range(const ResidueLabel& r, const ResidueRange& range) {
  return r.chain == range.chain &&
         std::tie(range.first, range.first_insertion) <= std::tie(r.number, r.insertion_code) &&
         std::tie(r.number, r.insertion_code) <= std::tie(range.last, range.last_insertion);
}

std::vector<std::int32_t> select_residues(const Globe& globe, const std::vector<ResidueRange>& ranges,
                                          std::string_view option) {
  if (globe.residues.empty())
    throw InputError(fmt::format("{}: this map has no residues ({})", option, no_residues_text(globe)));
  std::set<std::string> chains;
  for (const auto& r : globe.residues) chains.insert(r.chain);
  std::vector<std::int32_t> selected;
  for (const ResidueRange& range : ranges) {
    bool any = false;
    for (std::size_t r = 0; r < globe.residues.size(); ++r)
      if (in_range(globe.residues[r], range)) selected.push_back(static_cast<std::int32_t>(r)), any = true;
    if (!any) {
      const bool single = range.first == range.last && range.first_insertion == range.last_insertion;
      const std::string item = single ? fmt::format("{}:{}{}", range.chain, range.first, range.first_insertion)
                                      : fmt::format("{}:{}{}-{}{}", range.chain, range.first, range.first_insertion,
                                                    range.last, range.last_insertion);
      throw InputError(
          fmt::format("{}: no residue {} is on the mapped surface (chains there: {}); buried residues "
                      "have no place on the map",
                      option, item, fmt::join(chains, ", ")));
    }
  }
  std::sort(selected.begin(), selected.end());
  selected.erase(std::unique(selected.begin(), selected.end()), selected.end());
  return selected;
}

}  // namespace spheremap
