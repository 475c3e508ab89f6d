// index.html: structure, the embedded data read back, escaping of names, determinism, size, refusals.
#include "spheremap/render/viewer.hpp"

#include "../../src/render/viewer_payload.hpp"

#include <gtest/gtest.h>
#include <zlib.h>

#include <unistd.h>

#include <cstring>
#include <fstream>
#include <iostream>
#include <sstream>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "spheremap/error.hpp"
#include "viewer_test_map.hpp"

namespace spheremap {
namespace {

namespace fs = std::filesystem;
using testing_support::make_viewer_test_map;

std::size_t count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

std::string lower(std::string text) {
  for (char& c : text) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return text;
}

// The text of the element <script ... id="ID">...</script>.
std::string script_text(const std::string& page, const std::string& id) {
  const std::size_t open = page.find("id=\"" + id + "\">");
  if (open == std::string::npos) throw std::runtime_error("no element " + id);
  const std::size_t start = open + id.size() + 6;
  return page.substr(start, page.find("</script>", start) - start);
}

std::string base64_decode(const std::string& text) {
  static const std::string alphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  std::uint32_t bits = 0;
  int n = 0;
  for (const char c : text) {
    if (c == '=') break;
    bits = (bits << 6) | static_cast<std::uint32_t>(alphabet.find(c));
    if ((n += 6) >= 8) out.push_back(static_cast<char>((bits >> (n -= 8)) & 0xff));
  }
  return out;
}

std::string inflate(const std::string& deflated, std::size_t size) {
  std::string out(size, '\0');
  uLongf length = size;
  EXPECT_EQ(uncompress(reinterpret_cast<Bytef*>(out.data()), &length, reinterpret_cast<const Bytef*>(deflated.data()),
                       deflated.size()),
            Z_OK);
  out.resize(length);
  return out;
}

struct Embedded {
  nlohmann::json manifest;
  std::string blob;

  template <typename T>
  [[nodiscard]] std::vector<T> array(const std::string& name) const {
    const auto& a = manifest.at("arrays").at(name);
    std::vector<T> out(a.at("count").get<std::size_t>());
    std::memcpy(out.data(), blob.data() + a.at("offset").get<std::size_t>(), out.size() * sizeof(T));
    return out;  // the blob is little-endian, as this machine
  }
};

Embedded read_back(const std::string& page) {
  Embedded e;
  e.manifest = nlohmann::json::parse(script_text(page, "spheremap-manifest"));
  e.blob = inflate(base64_decode(script_text(page, "spheremap-data")), 64u << 20);
  return e;
}

TEST(Viewer, Base64EncodesEveryTailLength) {
  // RFC 4648's test vectors: no tail, one byte left over, two.
  const std::vector<std::pair<std::string, std::string>> vectors{{"", ""},
                                                                 {"f", "Zg=="},
                                                                 {"fo", "Zm8="},
                                                                 {"foo", "Zm9v"},
                                                                 {"foob", "Zm9vYg=="},
                                                                 {"fooba", "Zm9vYmE="},
                                                                 {"foobar", "Zm9vYmFy"}};
  for (const auto& [bytes, text] : vectors) EXPECT_EQ(detail::base64_encode(bytes), text) << bytes;
  EXPECT_EQ(detail::base64_encode(std::string("\xff\x00\xfe", 3)), "/wD+");
}

TEST(Viewer, PageHasItsPartsOnceAndNoPlaceholderLeft) {
  const std::string page = viewer_html(make_viewer_test_map(2, 20));
  EXPECT_EQ(page.rfind("<!DOCTYPE html>", 0), 0u);
  EXPECT_EQ(page.substr(page.size() - 8), "</html>\n");
  EXPECT_EQ(count(page, "<title>test map: bumpy sphere</title>"), 1u);
  EXPECT_EQ(count(page, "id=\"spheremap-manifest\""), 1u);
  EXPECT_EQ(count(page, "id=\"spheremap-data\""), 1u);
  EXPECT_EQ(count(lower(page), "<script"), 3u);  // manifest, data, the viewer's script
  EXPECT_EQ(count(lower(page), "</script"), 3u);
  EXPECT_EQ(count(page, "<!--"), 0u);
  EXPECT_EQ(count(page, "{{SPHEREMAP_"), 0u);
  EXPECT_EQ(count(page, "/*SPHEREMAP_SCRIPT*/"), 0u);
  EXPECT_NE(page.find("Three.js Authors"), std::string::npos);  // three.js, inlined with its licence notice
  // Nothing to fetch: no external script, style, image or link (three.js's namespace URIs name, not fetch).
  for (const char* fetching : {"src=", "href=", "url(", "@import", "fetch(\"http", "https://cdn"})
    EXPECT_EQ(page.find(fetching), std::string::npos) << fetching;
}

TEST(Viewer, EmbeddedDataReadsBackExactly) {
  const ViewerData data = make_viewer_test_map(2, 20);
  const Embedded e = read_back(viewer_html(data));
  const std::size_t n = data.surface_positions.size();
  EXPECT_EQ(e.manifest.at("format"), "spheremap-viewer");
  EXPECT_EQ(e.manifest.at("version"), 1);
  EXPECT_EQ(e.manifest.at("vertex_count"), n);
  EXPECT_EQ(e.manifest.at("triangle_count"), data.triangles.size());
  EXPECT_EQ(e.manifest.at("atom_count"), data.atoms.size());
  for (const auto& a : e.manifest.at("arrays")) EXPECT_EQ(a.at("offset").get<std::size_t>() % 4, 0u);

  const auto surface = e.array<float>("surface_positions");
  const auto sphere = e.array<float>("sphere_positions");
  ASSERT_EQ(surface.size(), 3 * n);
  for (std::size_t v = 0; v < n; ++v)
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(surface[3 * v + k], static_cast<float>(data.surface_positions[v][k]));
      EXPECT_EQ(sphere[3 * v + k], static_cast<float>(data.sphere_positions[v][k]));
    }
  const auto triangles = e.array<std::uint32_t>("triangles");
  ASSERT_EQ(triangles.size(), 3 * data.triangles.size());
  for (std::size_t t = 0; t < data.triangles.size(); ++t)
    for (int k = 0; k < 3; ++k) EXPECT_EQ(triangles[3 * t + k], static_cast<std::uint32_t>(data.triangles[t][k]));
  EXPECT_EQ(e.array<std::int32_t>("vertex_atoms"), data.vertex_atoms);

  const auto strings = e.manifest.at("strings").get<std::vector<std::string>>();
  const auto chains = e.array<std::uint32_t>("atom_chain");
  const auto names = e.array<std::uint32_t>("atom_name");
  const auto residues = e.array<std::uint32_t>("atom_residue_name");
  const auto numbers = e.array<std::int32_t>("atom_residue_number");
  for (std::size_t a = 0; a < data.atoms.size(); ++a) {
    EXPECT_EQ(strings.at(chains[a]), data.atoms[a].chain);
    EXPECT_EQ(strings.at(names[a]), data.atoms[a].atom_name);
    EXPECT_EQ(strings.at(residues[a]), data.atoms[a].residue_name);
    EXPECT_EQ(numbers[a], data.atoms[a].residue_number);
  }

  const auto& properties = e.manifest.at("properties");
  ASSERT_EQ(properties.size(), data.properties.size());
  for (std::size_t i = 0; i < properties.size(); ++i) {
    const ViewerProperty& p = data.properties[i];
    const auto& m = properties[i];
    EXPECT_EQ(m.at("name"), p.name);
    EXPECT_EQ(m.at("unit"), p.unit);
    EXPECT_EQ(m.at("scale"), std::string(to_string(p.scale)));
    EXPECT_EQ(m.at("range")[0].get<double>(), p.range.lo);
    EXPECT_EQ(m.at("range")[1].get<double>(), p.range.hi);
    EXPECT_EQ(m.at("categories").get<std::vector<std::string>>(), p.categories);
    const auto values = e.array<float>(m.at("values"));
    ASSERT_EQ(values.size(), n);
    for (std::size_t v = 0; v < n; ++v) {
      if (std::isnan(p.values[v]))
        EXPECT_TRUE(std::isnan(values[v]));
      else
        EXPECT_EQ(values[v], p.values[v]);
    }
    const auto colours = e.array<std::uint8_t>(m.at("colours"));
    const ColourTable& table = colour_table(p.scale);
    ASSERT_EQ(colours.size(), 768u);
    for (int k = 0; k < kColourTableSize; ++k)
      EXPECT_EQ((Rgb8{colours[3 * k], colours[3 * k + 1], colours[3 * k + 2]}), table[k]);
  }
}

TEST(Viewer, NamesFromFilesCannotBreakThePage) {
  ViewerData data = make_viewer_test_map(1, 4);
  data.title = "</script><script>alert(\"t\")</script> & 'x' <!-- \xff";
  data.atoms[0].chain = "</SCRIPT>";
  data.atoms[0].atom_name = "\"'<!--";
  data.atoms[1].residue_name = "G\xc3\x28Y";  // an invalid two-byte sequence
  data.properties[0].name = "a</script>b";
  data.properties[3].categories = {"\u2028", "B&amp;"};
  const std::string page = viewer_html(data);
  EXPECT_EQ(count(lower(page), "</script"), 3u);
  EXPECT_EQ(count(page, "<!--"), 0u);
  EXPECT_NE(page.find("<title>&lt;/script&gt;&lt;script&gt;alert(&quot;t&quot;)&lt;/script&gt; &amp; &#39;x&#39; "
                      "&lt;!-- \xef\xbf\xbd</title>"),
            std::string::npos);
  const Embedded e = read_back(page);
  EXPECT_EQ(e.manifest.at("title"), "</script><script>alert(\"t\")</script> & 'x' <!-- \xef\xbf\xbd");
  const auto strings = e.manifest.at("strings").get<std::vector<std::string>>();
  EXPECT_EQ(strings.at(e.array<std::uint32_t>("atom_chain")[0]), "</SCRIPT>");
  EXPECT_EQ(strings.at(e.array<std::uint32_t>("atom_name")[0]), "\"'<!--");
  EXPECT_EQ(strings.at(e.array<std::uint32_t>("atom_residue_name")[1]), "G\xef\xbf\xbd(Y");
  EXPECT_EQ(e.manifest.at("properties")[0].at("name"), "a</script>b");
  EXPECT_EQ(e.manifest.at("properties")[3].at("categories")[1], "B&amp;");
}

TEST(Viewer, SameDataSameBytes) {
  const ViewerData data = make_viewer_test_map(3, 40);
  const std::string first = viewer_html(data);
  EXPECT_EQ(viewer_html(data), first);
  EXPECT_EQ(viewer_html(make_viewer_test_map(3, 40)), first);
  ViewerData other = data;
  other.properties[1].values[7] += 1;
  EXPECT_NE(viewer_html(other), first);
}

TEST(Viewer, FortyThousandVerticesWithFivePropertiesFitInFiveMegabytes) {
  const ViewerData data = make_viewer_test_map(6, 800);  // 40,962 vertices, 81,920 triangles, 4,000 atoms
  ASSERT_EQ(data.surface_positions.size(), 40962u);
  ASSERT_EQ(data.properties.size(), 5u);
  const std::string page = viewer_html(data);
  std::cout << "index.html for 40,962 vertices, 81,920 triangles, 4,000 atoms, 5 properties: " << page.size()
            << " bytes\n";
  RecordProperty("bytes", std::to_string(page.size()));
  EXPECT_LE(page.size(), 5'000'000u);
}

TEST(Viewer, WritesTheFileAtomically) {
  const fs::path dir = fs::temp_directory_path() / ("spheremap_viewer_test_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const ViewerData data = make_viewer_test_map(1, 4);
  write_viewer_html(dir / "index.html", data);
  std::ifstream in(dir / "index.html", std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  EXPECT_EQ(text.str(), viewer_html(data));
  EXPECT_EQ(std::distance(fs::directory_iterator(dir), fs::directory_iterator()), 1);  // no temporary left
  EXPECT_THROW(write_viewer_html(dir / "missing" / "index.html", data), InputError);
  fs::remove_all(dir);
}

TEST(Viewer, RefusesInconsistentData) {
  const ViewerData good = make_viewer_test_map(1, 4);
  const auto refused = [](const ViewerData& data, const std::string& words) {
    try {
      (void)viewer_html(data);
      ADD_FAILURE() << "accepted data with " << words;
    } catch (const std::invalid_argument& e) {
      EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
    }
  };
  ViewerData d = good;
  d.sphere_positions.pop_back();
  refused(d, "sphere vertices");
  d = good;
  d.triangles[3][1] = static_cast<std::int32_t>(d.surface_positions.size());
  refused(d, "triangle 3");
  d = good;
  d.triangles.clear();
  refused(d, "no triangles");
  d = good;
  d.surface_positions[2][1] = std::numeric_limits<double>::quiet_NaN();
  refused(d, "surface position 2");
  d = good;
  d.vertex_atoms[5] = static_cast<std::int32_t>(d.atoms.size());
  refused(d, "vertex 5");
  d = good;
  d.vertex_atoms.pop_back();
  refused(d, "vertex atoms");
  d = good;
  d.properties[1].values.pop_back();
  refused(d, "\"electrostatics\"");
  d = good;
  d.properties[0].range = {3, 3};
  refused(d, "\"height\" has the range");
  d = good;
  d.vertex_atoms.clear();  // no atoms at all is allowed
  d.atoms.clear();
  d.properties.clear();
  EXPECT_NO_THROW((void)viewer_html(d));
}

}  // namespace
}  // namespace spheremap
