#include "spheremap/molecule/radii.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>

#include <fmt/format.h>

#include "spheremap/error.hpp"

namespace spheremap {

std::optional<double> bondi_radius(const std::string& element) {
  // A. Bondi, "van der Waals Volumes and Radii", J. Phys. Chem. 68, 441 (1964), Table I.
  static const std::map<std::string, double> kBondi = {
      {"H", 1.20},  {"HE", 1.40}, {"C", 1.70},  {"N", 1.55},  {"O", 1.52},  {"F", 1.47},  {"NE", 1.54}, {"SI", 2.10},
      {"P", 1.80},  {"S", 1.80},  {"CL", 1.75}, {"AR", 1.88}, {"AS", 1.85}, {"SE", 1.90}, {"BR", 1.85}, {"KR", 2.02},
      {"TE", 2.06}, {"I", 1.98},  {"XE", 2.16}, {"LI", 1.82}, {"NA", 2.27}, {"K", 2.75},  {"MG", 1.73}, {"NI", 1.63},
      {"CU", 1.40}, {"ZN", 1.39}, {"GA", 1.87}, {"PD", 1.63}, {"AG", 1.72}, {"CD", 1.58}, {"IN", 1.93}, {"SN", 2.17},
      {"PT", 1.72}, {"AU", 1.66}, {"HG", 1.55}, {"TL", 1.96}, {"PB", 2.02}, {"U", 1.86},  {"D", 1.20}};
  std::string key = element;
  std::transform(key.begin(), key.end(), key.begin(), [](unsigned char c) { return std::toupper(c); });
  const auto it = kBondi.find(key);
  if (it == kBondi.end()) return std::nullopt;
  return it->second;
}

std::map<std::string, double> load_radius_table(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in)
    throw InputError(fmt::format("{}: cannot open the radius table; check the path given to --radii", path.string()));
  std::map<std::string, double> table;
  std::string line;
  int line_number = 0;
  while (std::getline(in, line)) {
    ++line_number;
    if (const auto hash = line.find('#'); hash != std::string::npos) line.erase(hash);
    std::istringstream fields(line);
    std::string element, radius_text, extra;
    if (!(fields >> element)) continue;
    double radius = 0;
    const bool parsed =
        static_cast<bool>(fields >> radius_text) && !(fields >> extra) &&
        std::from_chars(radius_text.data(), radius_text.data() + radius_text.size(), radius).ec == std::errc{};
    if (!parsed || !(radius > 0 && radius <= 10))
      throw InputError(fmt::format("{}:{}: expected 'ELEMENT RADIUS' with a radius in (0, 10] Å, got '{}'",
                                   path.string(), line_number, line));
    std::transform(element.begin(), element.end(), element.begin(), [](unsigned char c) { return std::toupper(c); });
    table[element] = radius;
  }
  if (table.empty())
    throw InputError(fmt::format("{}: the radius table has no entries ('ELEMENT RADIUS' per line)", path.string()));
  return table;
}

}  // namespace spheremap
