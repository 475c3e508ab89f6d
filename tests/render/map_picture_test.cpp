// Projections (round trip, PROJ as the oracle), the point location on the globe, map figures (bands of a
// property equal to z, the pixel under a vertex, size, determinism), the TSV grid and hemisphere figures.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <numbers>
#include <random>
#include <set>
#include <sstream>
#include <string>

#include "../test_support.hpp"
#include "spheremap/error.hpp"
#include "spheremap/render/colour_scale.hpp"
#include "spheremap/render/hemispheres.hpp"
#include "spheremap/render/map_picture.hpp"
#include "spheremap/render/plot.hpp"
#include "spheremap/render/viewer_data.hpp"
#include "spheremap/shapes/shapes.hpp"
#include "spheremap/topology/connectivity.hpp"

namespace spheremap {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr std::array<Projection, 3> kProjections{Projection::mollweide, Projection::equirectangular,
                                                 Projection::sinusoidal};

Vec3 unit(const Vec3& v) {
  const double n = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  return {v[0] / n, v[1] / n, v[2] / n};
}

TEST(Projection, ForwardThenInverseReturnsThePoint) {
  for (const Projection projection : kProjections)
    for (int lat = -89; lat <= 89; lat += 7)
      for (int lon = -179; lon <= 179; lon += 11) {
        const GeoPoint p{lat * kDegree, lon * kDegree};
        const auto back = unproject(projection, project(projection, p));
        ASSERT_TRUE(back) << to_string(projection) << " " << lat << " " << lon;
        EXPECT_NEAR(back->latitude, p.latitude, 1e-9) << to_string(projection) << " " << lat << " " << lon;
        EXPECT_NEAR(back->longitude, p.longitude, 1e-9) << to_string(projection) << " " << lat << " " << lon;
      }
}

TEST(Projection, PointsOutsideTheMapHaveNoGlobePoint) {
  EXPECT_FALSE(unproject(Projection::mollweide, {2.8, 1.3}));          // beyond the ellipse's corner
  EXPECT_FALSE(unproject(Projection::sinusoidal, {3.0, 1.2}));         // beyond the sinusoid
  EXPECT_FALSE(unproject(Projection::equirectangular, {3.2, 0}));      // beyond ±180°
  EXPECT_TRUE(unproject(Projection::mollweide, {0, std::sqrt(2.0)}));  // the north pole
  const auto edge = unproject(Projection::mollweide, {2 * std::sqrt(2.0), 0});
  ASSERT_TRUE(edge);
  EXPECT_NEAR(edge->longitude, kPi, 1e-12);
}

TEST(Projection, NamesRoundTrip) {
  for (const Projection projection : kProjections) EXPECT_EQ(parse_projection(to_string(projection)), projection);
  EXPECT_EQ(parse_projection("flamsteed"), Projection::sinusoidal);
  EXPECT_FALSE(parse_projection("mercator"));
}

// PROJ's `proj` program on the unit sphere: "lon lat" in degrees in, "x y" out.
std::vector<PlanePoint> proj_oracle(const std::string& definition, const std::vector<GeoPoint>& points) {
  const std::filesystem::path input =
      std::filesystem::temp_directory_path() / ("spheremap-proj-" + std::to_string(::getpid()) + ".txt");
  std::string text;
  for (const GeoPoint& p : points)
    text += fmt::format("{:.12f} {:.12f}\n", p.longitude / kDegree, p.latitude / kDegree);
  testing_support::write_text(input, text);
  const std::string command = "proj " + definition + " -f %.12f " + input.string();
  std::FILE* pipe = ::popen(command.c_str(), "r");
  std::vector<PlanePoint> out;
  if (pipe == nullptr) return out;
  double x = 0, y = 0;
  while (std::fscanf(pipe, "%lf %lf", &x, &y) == 2) out.push_back({x, y});
  ::pclose(pipe);
  std::filesystem::remove(input);
  return out;
}

TEST(Projection, AgreesWithProj) {
  std::vector<GeoPoint> points;
  for (int lat = -90; lat <= 90; lat += 15)
    for (int lon = -180; lon <= 180; lon += 45) points.push_back({lat * kDegree, lon * kDegree});
  points.push_back({89.999 * kDegree, 12.3 * kDegree});
  points.push_back({-37.7 * kDegree, -101.1 * kDegree});
  const std::array<std::string, 3> definitions{"+proj=moll +R=1", "+proj=eqc +R=1", "+proj=sinu +R=1"};
  for (std::size_t k = 0; k < kProjections.size(); ++k) {
    const auto expected = proj_oracle(definitions[k], points);
    ASSERT_EQ(expected.size(), points.size()) << "`proj` (PROJ, Debian proj-bin) must be installed: "
                                              << "scripts/install-deps.sh installs it";
    for (std::size_t i = 0; i < points.size(); ++i) {
      const PlanePoint got = project(kProjections[k], points[i]);
      // At the poles PROJ's Mollweide stops its iteration early (x ~ 1e-5 where the pole's x is 0): y only.
      const bool pole = std::abs(points[i].latitude) == kPi / 2;
      if (!(pole && kProjections[k] == Projection::mollweide))
        EXPECT_NEAR(got.x, expected[i].x, 1e-9) << definitions[k] << " point " << i;
      EXPECT_NEAR(got.y, expected[i].y, 1e-9) << definitions[k] << " point " << i;
    }
  }
}

TEST(SphereLocator, FindsTheTriangleUnderRandomPointsPolesAndTheSeam) {
  const Mesh sphere = make_icosphere(4);
  const SphereLocator locator = make_sphere_locator(sphere.positions, sphere.triangles);
  std::mt19937 random(7);
  std::normal_distribution<double> normal;
  std::vector<Vec3> points{{0, 0, 1}, {0, 0, -1}, {1, 0, 0}, {1, -1e-17, 0}, {1, 1e-17, 0.3}, {0.5, -1e-300, -0.5}};
  for (int k = 0; k < 20000; ++k) points.push_back({normal(random), normal(random), normal(random)});
  for (const Vec3& point : points) {
    const Vec3 p = unit(point);
    const SphereHit hit = locate_on_sphere(locator, point);
    ASSERT_GE(hit.triangle, 0);
    // The weights put the point on the triangle's plane along the ray from the centre.
    Vec3 q{0, 0, 0};
    for (int c = 0; c < 3; ++c) {
      EXPECT_GE(hit.weights[c], 0);
      for (int i = 0; i < 3; ++i) q[i] += hit.weights[c] * locator.vertices[locator.triangles[hit.triangle][c]][i];
    }
    const Vec3 qu = unit(q);
    EXPECT_NEAR(qu[0], p[0], 1e-9);
    EXPECT_NEAR(qu[1], p[1], 1e-9);
    EXPECT_NEAR(qu[2], p[2], 1e-9);
  }
}

TEST(SphereLocator, AHintChangesNothingOnAOneToOneMap) {
  // Random points, the mesh's corners and edge midpoints (which several triangles contain: the hint must not
  // win over the first of them), each hinted with every triangle that holds one of its candidates' corners,
  // and the last 200 random points with every triangle (walks that end far from the point).
  const Mesh sphere = make_icosphere(3);
  const SphereLocator locator = make_sphere_locator(sphere.positions, sphere.triangles);
  std::mt19937 random(11);
  std::normal_distribution<double> normal;
  std::vector<Vec3> points(sphere.positions.begin(), sphere.positions.end());
  for (const Triangle& t : sphere.triangles)
    for (int k = 0; k < 3; ++k) {
      const Vec3& a = sphere.positions[t[k]];
      const Vec3& b = sphere.positions[t[(k + 1) % 3]];
      points.push_back({a[0] + b[0], a[1] + b[1], a[2] + b[2]});
    }
  for (int k = 0; k < 2000; ++k) points.push_back({normal(random), normal(random), normal(random)});
  int hinted = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Vec3& point = points[i];
    const bool every_hint = i + 200 >= points.size();
    const Vec3 p = unit(point);
    const double theta = std::acos(std::clamp(p[2], -1.0, 1.0)), phi = std::atan2(p[1], p[0]);
    const SphereHit expected = locate_on_sphere(locator, point, theta, phi);
    ASSERT_GE(expected.triangle, 0);
    const Triangle& under = locator.triangles[expected.triangle];
    for (std::int32_t hint = 0; hint < static_cast<std::int32_t>(locator.triangles.size()); ++hint) {
      const Triangle& t = locator.triangles[hint];
      if (!every_hint && std::find_first_of(t.begin(), t.end(), under.begin(), under.end()) == t.end()) continue;
      const SphereHit hit = locate_on_sphere(locator, point, theta, phi, hint);
      ASSERT_EQ(hit.triangle, expected.triangle) << "hint " << hint;
      for (int c = 0; c < 3; ++c) EXPECT_EQ(hit.weights[c], expected.weights[c]);
      ++hinted;
    }
  }
  EXPECT_GT(hinted, 20000);
}

TEST(SphereLocator, KeepsTheHalfEdgeAcrossEachEdge) {
  const Mesh sphere = make_icosphere(2);
  SphereLocator locator = make_sphere_locator(sphere.positions, sphere.triangles);
  EXPECT_EQ(locator.opposite, opposite_half_edges(sphere.positions.size(), sphere.triangles));
  ASSERT_EQ(locator.opposite.size(), 3 * sphere.triangles.size());
  for (const std::int32_t g : locator.opposite) EXPECT_GE(g, 0);
  // A hole: the triangles around a removed one have no neighbour there.
  Mesh open = sphere;
  open.triangles.pop_back();
  locator = make_sphere_locator(open.positions, open.triangles);
  EXPECT_EQ(std::count(locator.opposite.begin(), locator.opposite.end(), -1), 3);
}

TEST(SphereLocator, RefusesAnIndexOutOfRange) {
  EXPECT_THROW(make_sphere_locator({{1, 0, 0}}, {{0, 1, 2}}), std::invalid_argument);
}

// An icosphere with properties: z of the globe point (sequential) and the octant.
Globe test_globe(int levels) {
  const Mesh sphere = make_icosphere(levels);
  std::vector<Vec3> unit_sphere;
  for (const Vec3& p : sphere.positions) unit_sphere.push_back(unit(p));
  SurfaceProperty z{{"z", "", ScaleKind::sequential, ValueRange{-1, 1}, {}}, "test", {}};
  for (const Vec3& p : unit_sphere) z.values.push_back(p[2]);
  std::vector<SurfaceProperty> properties = properties_from_attributes(sphere, unit_sphere);
  properties.push_back(z);
  return make_globe(sphere, unit_sphere, properties, "icosphere");
}

TEST(MapSamples, APropertyEqualToZGivesHorizontalBandsOnEveryProjection) {
  const Globe globe = test_globe(5);
  const SphereLocator locator = make_sphere_locator(globe.sphere, globe.triangles);
  const SurfaceProperty& z = *find_globe_property(globe, "z");
  for (const Projection projection : kProjections) {
    const int width = 400, height = 200;
    const MapSamples samples = sample_map(locator, projection, width, height, 2);
    int on_map = 0;
    for (int row = 0; row < height; ++row) {
      // Every pixel of a row: the value is sin(latitude of the row), up to the flat triangles' error.
      for (int column = 0; column < width; ++column) {
        const std::size_t i = static_cast<std::size_t>(row) * width + column;
        if (samples.triangle[i] < 0) continue;
        ++on_map;
        const double latitude = (1 - (row + 0.5) / height * 2) * projection_half_extent(projection).y;
        const double expected = projection == Projection::mollweide
                                    ? std::sin(unproject(projection, {0, latitude})->latitude)
                                    : std::sin(latitude);
        EXPECT_NEAR(value_at(globe, z, samples.triangle[i], samples.weights[i]), expected, 2e-3)
            << to_string(projection) << " row " << row << " column " << column;
      }
    }
    // No gaps: every pixel centre inside the projection's outline has a triangle.
    int inside = 0;
    const PlanePoint half = projection_half_extent(projection);
    for (int row = 0; row < height; ++row)
      for (int column = 0; column < width; ++column)
        inside +=
            unproject(projection, {((column + 0.5) / width * 2 - 1) * half.x, (1 - (row + 0.5) / height * 2) * half.y})
                .has_value();
    EXPECT_EQ(on_map, inside) << to_string(projection);
    EXPECT_GT(on_map, width * height / 2) << to_string(projection);
  }
}

TEST(MapSamples, DoNotDependOnTheThreadCount) {
  const Globe globe = test_globe(3);
  const SphereLocator locator = make_sphere_locator(globe.sphere, globe.triangles);
  const MapSamples one = sample_map(locator, Projection::mollweide, 300, 150, 1);
  const MapSamples two = sample_map(locator, Projection::mollweide, 300, 150, 2);
  EXPECT_EQ(one.triangle, two.triangle);
  EXPECT_EQ(one.weights, two.weights);
}

MapFigureOptions small_figure(Projection projection, ImageFormat format = ImageFormat::png) {
  MapFigureOptions options;
  options.width = 800;
  options.height = 460;
  options.format = format;
  (void)projection;
  return options;
}

class MapFigureFiles : public testing_support::FolderTest {};

TEST_F(MapFigureFiles, ThePixelUnderAVertexHasItsColourAndTheImageHasTheRequestedSize) {
  const Globe globe = test_globe(4);
  const SphereLocator locator = make_sphere_locator(globe.sphere, globe.triangles);
  const SurfaceProperty& z = *find_globe_property(globe, "z");
  for (const Projection projection : kProjections) {
    const MapFigureOptions options = small_figure(projection);
    const auto size = map_image_size(options);
    const auto origin = map_image_origin(options);
    const MapSamples samples = sample_map(locator, projection, size[0], size[1]);
    const std::filesystem::path path = folder_ / "z.png";
    testing_support::write_text(path, map_figure(globe, z, samples, options));
    const RgbImage image = read_png(path);
    ASSERT_EQ(image.width, options.width);
    ASSERT_EQ(image.height, options.height);
    const PlanePoint half = projection_half_extent(projection);
    int checked = 0;
    for (std::size_t v = 0; v < globe.sphere.size(); v += 37) {
      const GeoPoint g = geo_point_of(globe.sphere[v]);
      // Away from the graticule lines (every 30°) and the map's edge, which are drawn over the colours.
      const auto near_line = [](double degrees) { return std::abs(std::remainder(degrees, 30.0)) < 4; };
      if (near_line(g.latitude / kDegree) || near_line(g.longitude / kDegree) || std::abs(g.latitude) > 75 * kDegree ||
          std::abs(g.longitude) > 160 * kDegree)
        continue;
      const PlanePoint p = project(projection, g);
      const int column = static_cast<int>(std::floor((p.x / half.x + 1) / 2 * size[0]));
      const int row = static_cast<int>(std::floor((1 - p.y / half.y) / 2 * size[1]));
      const std::size_t pixel = (static_cast<std::size_t>(origin[1] + row) * image.width + origin[0] + column) * 3;
      const Rgb8 expected = colour_of(ScaleKind::sequential, {-1, 1}, z.values[v]);
      // The pixel centre is within half a pixel of the vertex: its value differs by the slope times that.
      EXPECT_NEAR(image.pixels[pixel], expected.r, 6) << to_string(projection) << " vertex " << v;
      EXPECT_NEAR(image.pixels[pixel + 1], expected.g, 6) << to_string(projection) << " vertex " << v;
      EXPECT_NEAR(image.pixels[pixel + 2], expected.b, 6) << to_string(projection) << " vertex " << v;
      ++checked;
    }
    EXPECT_GT(checked, 20);
  }
}

TEST_F(MapFigureFiles, AreNotBlankAndTheSameInputGivesTheSameBytes) {
  const Globe globe = test_globe(3);
  const SphereLocator locator = make_sphere_locator(globe.sphere, globe.triangles);
  for (const ImageFormat format : {ImageFormat::png, ImageFormat::svg, ImageFormat::pdf}) {
    MapFigureOptions options = small_figure(Projection::mollweide, format);
    const auto size = map_image_size(options);
    const MapSamples samples = sample_map(locator, Projection::mollweide, size[0], size[1], 1);
    const MapSamples samples2 = sample_map(locator, Projection::mollweide, size[0], size[1], 2);
    const SurfaceProperty& octant = *find_globe_property(globe, "octant");
    const std::string first = map_figure(globe, octant, samples, options);
    EXPECT_EQ(first, map_figure(globe, octant, samples2, options)) << to_string(format);
    EXPECT_GT(first.size(), 1000u);
    if (format == ImageFormat::svg) EXPECT_NE(first.find("<svg"), std::string::npos);
    if (format == ImageFormat::pdf) EXPECT_EQ(first.substr(0, 5), "%PDF-");
  }
  MapFigureOptions options = small_figure(Projection::mollweide);
  const auto size = map_image_size(options);
  const MapSamples samples = sample_map(locator, Projection::mollweide, size[0], size[1]);
  testing_support::write_text(folder_ / "octant.png",
                              map_figure(globe, *find_globe_property(globe, "octant"), samples, options));
  const RgbImage image = read_png(folder_ / "octant.png");
  std::set<std::array<std::uint8_t, 3>> colours;
  for (std::size_t i = 0; i < image.pixels.size(); i += 3)
    colours.insert({image.pixels[i], image.pixels[i + 1], image.pixels[i + 2]});
  EXPECT_GT(colours.size(), 50u);  // eight octant colours, text, lines and their antialiasing
  for (int k = 0; k < 8; ++k) {
    const Rgb8 c = colour_of(ScaleKind::categorical, {0, 255}, k);
    EXPECT_TRUE(colours.count({c.r, c.g, c.b})) << "octant " << k;
  }
}

TEST(MapFigure, RefusesASizeOutOfBounds) {
  MapFigureOptions options;
  options.width = 100;
  options.height = 50;
  EXPECT_THROW(map_image_size(options), InputError);
}

TEST(MapGrid, ListsCellsWithLatitudeLongitudeValueAndResidues) {
  const Globe globe = test_globe(3);
  const SphereLocator locator = make_sphere_locator(globe.sphere, globe.triangles);
  const std::string tsv =
      map_grid_tsv(globe, *find_globe_property(globe, "z"), locator, Projection::equirectangular, 36, 18);
  std::istringstream in(tsv);
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "row\tcolumn\tlatitude\tlongitude\tvalue\tresidues");
  int lines = 0;
  while (std::getline(in, line)) {
    double row = 0, column = 0, latitude = 0, longitude = 0, value = 0;
    ASSERT_EQ(std::sscanf(line.c_str(), "%lf\t%lf\t%lf\t%lf\t%lf", &row, &column, &latitude, &longitude, &value), 5)
        << line;
    EXPECT_NEAR(latitude, 90 - (row + 0.5) * 10, 1e-9);
    EXPECT_NEAR(longitude, -180 + (column + 0.5) * 10, 1e-9);
    EXPECT_NEAR(value, std::sin(latitude * kDegree), 0.06) << line;  // the mean over the 10° cell
    ++lines;
  }
  EXPECT_EQ(lines, 36 * 18);
}

TEST(MapGrid, SeveralPropertiesAtOnceGiveEachOnesGrid) {
  const Globe globe = test_globe(3);
  const SphereLocator locator = make_sphere_locator(globe.sphere, globe.triangles);
  const MapSamples grid = sample_grid(locator, Projection::mollweide, 72, 36);
  const SurfaceProperty* octant = find_globe_property(globe, "octant");
  const SurfaceProperty* z = find_globe_property(globe, "z");
  for (const int threads : {1, 2}) {
    const std::vector<std::string> both = map_grid_tsvs(globe, {octant, z}, grid, threads);
    ASSERT_EQ(both.size(), 2u);
    EXPECT_EQ(both[0], map_grid_tsv(globe, *octant, grid, 1));
    EXPECT_EQ(both[1], map_grid_tsv(globe, *z, grid, 1));
    EXPECT_NE(both[0], both[1]);
  }
}

TEST(HemisphereFigure, HasTheSizeIsNotBlankAndIsDeterministic) {
  const Globe globe = test_globe(3);
  HemisphereOptions options;
  options.width = 600;
  options.height = 640;
  options.supersampling = 2;
  options.threads = 1;
  const std::string one = hemisphere_figure(globe, *find_globe_property(globe, "octant"), options);
  options.threads = 2;
  EXPECT_EQ(one, hemisphere_figure(globe, *find_globe_property(globe, "octant"), options));
  const std::filesystem::path path =
      std::filesystem::temp_directory_path() / ("spheremap-hemispheres-" + std::to_string(::getpid()) + ".png");
  testing_support::write_text(path, one);
  const RgbImage image = read_png(path);
  std::filesystem::remove(path);
  EXPECT_EQ(image.width, 600);
  EXPECT_EQ(image.height, 640);
  // Each octant colour appears, shaded: count pixels whose hue is near an octant colour and not grey.
  int coloured = 0;
  for (std::size_t i = 0; i < image.pixels.size(); i += 3) {
    const int r = image.pixels[i], g = image.pixels[i + 1], b = image.pixels[i + 2];
    if (std::max({r, g, b}) - std::min({r, g, b}) > 40) ++coloured;
  }
  EXPECT_GT(coloured, image.width * image.height / 10);
  options.supersampling = 9;
  EXPECT_THROW(hemisphere_figure(globe, *find_globe_property(globe, "octant"), options), InputError);
}

TEST(HemisphereFigure, SeveralPropertiesAtOnceGiveEachOnesFigure) {
  const Globe globe = test_globe(3);
  HemisphereOptions options;
  options.width = 500;
  options.height = 520;
  options.threads = 2;
  const SurfaceProperty* octant = find_globe_property(globe, "octant");
  const SurfaceProperty* z = find_globe_property(globe, "z");
  const std::vector<std::string> both = hemisphere_figures(globe, {z, octant}, options);
  ASSERT_EQ(both.size(), 2u);
  EXPECT_EQ(both[0], hemisphere_figure(globe, *z, options));
  EXPECT_EQ(both[1], hemisphere_figure(globe, *octant, options));
  EXPECT_NE(both[0], both[1]);
  EXPECT_TRUE(hemisphere_figures(globe, {}, options).empty());
  options.trace = {TracePath{{{0, 0, 0}, {1, 0, 0}}, {0, 1}}};  // a trace's values are one property's
  EXPECT_THROW(hemisphere_figures(globe, {z, octant}, options), std::invalid_argument);
}

TEST(GlobeProperties, SequencePositionRanksPolymerResiduesOfEachChainAndLeavesLigandsOut) {
  const Mesh sphere = make_icosphere(1);  // 42 vertices
  Mesh surface = sphere;
  TextAttribute chain{{"A", "B"}, {}}, name{{"ALA", "HOH"}, {}};
  std::vector<std::int32_t> number;
  for (std::size_t v = 0; v < sphere.vertex_count(); ++v) {
    // Chain A: residues 10, 11, 12 and a water 500; chain B: residue 7 only.
    const int k = static_cast<int>(v % 5);
    chain.codes.push_back(k == 4 ? 1 : 0);
    name.codes.push_back(k == 3 ? 1 : 0);
    number.push_back(k == 4 ? 7 : k == 3 ? 500 : 10 + k);
  }
  surface.text_attributes["vertex_chain"] = chain;
  surface.text_attributes["vertex_residue_name"] = name;
  surface.integer_attributes["vertex_residue_number"] = number;
  const auto properties = properties_from_attributes(surface, sphere.positions);
  const Globe globe = make_globe(surface, sphere.positions, properties, "test");
  const SurfaceProperty* position = find_globe_property(globe, "sequence_position");
  ASSERT_NE(position, nullptr);
  EXPECT_EQ(position->info.scale, ScaleKind::spectrum);
  for (std::size_t v = 0; v < sphere.vertex_count(); ++v) {
    const int k = static_cast<int>(v % 5);
    if (k == 3) {
      EXPECT_TRUE(std::isnan(position->values[v])) << v;
    } else {
      EXPECT_DOUBLE_EQ(position->values[v], k == 4 ? 0.0 : k / 2.0) << v;
    }
  }
  const SurfaceProperty* chains = find_globe_property(globe, "chain_index");
  ASSERT_NE(chains, nullptr);
  EXPECT_EQ(chains->info.categories, (std::vector<std::string>{"A", "B"}));
  EXPECT_EQ(globe.residues.size(), 5u);
}

TEST(ViewerData, ShowsThePicturesProperties) {
  const Mesh sphere = make_icosphere(2);
  const Globe globe = test_globe(2);
  const ViewerData data = viewer_data_for_map(sphere, globe.sphere, "t", globe.properties);
  ASSERT_EQ(data.properties.size(), globe.properties.size());
  for (std::size_t k = 0; k < globe.properties.size(); ++k) {
    EXPECT_EQ(data.properties[k].name, globe.properties[k].info.name);
    EXPECT_EQ(data.properties[k].scale, globe.properties[k].info.scale);
  }
  const auto& z = data.properties.back();
  EXPECT_EQ(z.name, "z");
  EXPECT_EQ(z.range.lo, -1);  // its default range
  EXPECT_EQ(z.range.hi, 1);
  EXPECT_GT(viewer_html(data).size(), 1000u);
}

TEST(HemisphereViews, LookAlongTheAxisOfLeastSpread) {
  const Mesh ellipsoid = make_ellipsoid(3, 1, 3, 2);  // most spread along y, least along x
  const HemisphereViews views = hemisphere_views(ellipsoid.positions);
  EXPECT_NEAR(std::abs(views.front[1]), 1, 1e-9);  // right = ±y
  EXPECT_NEAR(std::abs(views.front[5]), 1, 1e-9);  // up = ±z
  EXPECT_NEAR(std::abs(views.front[6]), 1, 1e-9);  // towards = ±x
}

}  // namespace
}  // namespace spheremap
