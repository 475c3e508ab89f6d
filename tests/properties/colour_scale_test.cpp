// Colour scales: the tables at published points, and the value -> entry rule.
#include "spheremap/properties/colour_scale.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <limits>
#include <set>
#include <vector>

namespace spheremap {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

void expect_near_colour(const Rgb8& actual, const Rgb8& expected, int tolerance, int entry) {
  EXPECT_LE(std::abs(actual.r - expected.r), tolerance) << "entry " << entry;
  EXPECT_LE(std::abs(actual.g - expected.g), tolerance) << "entry " << entry;
  EXPECT_LE(std::abs(actual.b - expected.b), tolerance) << "entry " << entry;
}

TEST(ColourScale, ViridisAtPublishedPoints) {
  const ColourTable& v = viridis_table();
  // matplotlib's viridis: #440154 at 0, #21918c at the middle entry, #fde725 at 1.
  EXPECT_EQ(v[0], (Rgb8{0x44, 0x01, 0x54}));
  EXPECT_EQ(v[128], (Rgb8{0x21, 0x91, 0x8c}));
  EXPECT_EQ(v[255], (Rgb8{0xfd, 0xe7, 0x25}));
  // R viridisLite's viridis(5) (#440154 #3B528B #21908C #5DC863 #FDE725), sampled between entries from the
  // same data: within one level of the nearest entry.
  const Rgb8 five[] = {
      {0x44, 0x01, 0x54}, {0x3b, 0x52, 0x8b}, {0x21, 0x90, 0x8c}, {0x5d, 0xc8, 0x63}, {0xfd, 0xe7, 0x25}};
  for (int k = 0; k < 5; ++k) expect_near_colour(v[static_cast<int>(std::lround(k * 255 / 4.0))], five[k], 1, k);
}

TEST(ColourScale, ViridisIsSmoothAndGetsLighter) {
  // A mistyped digit in the table would show as a jump or a dip in lightness.
  const ColourTable& v = viridis_table();
  const auto luminance = [](const Rgb8& c) { return 0.2126 * c.r + 0.7152 * c.g + 0.0722 * c.b; };
  for (int i = 1; i < kColourTableSize; ++i) {
    EXPECT_LE(std::abs(v[i].r - v[i - 1].r), 3) << i;
    EXPECT_LE(std::abs(v[i].g - v[i - 1].g), 3) << i;
    EXPECT_LE(std::abs(v[i].b - v[i - 1].b), 3) << i;
    if (i >= 4) EXPECT_GT(luminance(v[i]), luminance(v[i - 4])) << i;
  }
}

TEST(ColourScale, RedWhiteBlueRunsFromRedThroughWhiteToBlue) {
  const ColourTable& d = red_white_blue_table();
  EXPECT_EQ(d[0], (Rgb8{178, 24, 43}));     // ColorBrewer RdBu's red end (#b2182b)
  EXPECT_EQ(d[255], (Rgb8{33, 102, 172}));  // and blue end (#2166ac)
  for (const int middle : {127, 128}) {
    EXPECT_GE(d[middle].r, 240);
    EXPECT_GE(d[middle].g, 240);
    EXPECT_GE(d[middle].b, 240);
  }
  for (int i = 0; i < 120; ++i) EXPECT_GT(d[i].r, d[i].b) << i;
  for (int i = 136; i < 256; ++i) EXPECT_LT(d[i].r, d[i].b) << i;
}

TEST(ColourScale, CategoricalColoursAreDistinctAndNotGrey) {
  const ColourTable& c = categorical_table();
  std::set<std::tuple<int, int, int>> distinct;
  for (int k = 0; k < 10; ++k) {
    distinct.insert({c[k].r, c[k].g, c[k].b});
    EXPECT_NE(c[k], kMissingValueColour);
  }
  EXPECT_EQ(distinct.size(), 10u);
  EXPECT_EQ(c[0], (Rgb8{78, 121, 167}));  // Tableau blue
  EXPECT_EQ(c[13], c[3]);                 // the palette repeats every 10 classes
  EXPECT_EQ(&colour_table(ScaleKind::categorical), &c);
  EXPECT_EQ(&colour_table(ScaleKind::sequential), &viridis_table());
  EXPECT_EQ(&colour_table(ScaleKind::diverging), &red_white_blue_table());
}

TEST(ColourScale, ContinuousValuesFallInEqualBinsAndSaturate) {
  const ValueRange range{-2, 2};
  for (const ScaleKind kind : {ScaleKind::sequential, ScaleKind::diverging}) {
    EXPECT_EQ(colour_index(kind, range, -2), 0);
    EXPECT_EQ(colour_index(kind, range, 2), 255);
    EXPECT_EQ(colour_index(kind, range, 0), 128);
    EXPECT_EQ(colour_index(kind, range, -7), 0);
    EXPECT_EQ(colour_index(kind, range, 7), 255);
    EXPECT_EQ(colour_index(kind, range, -kInf), 0);
    EXPECT_EQ(colour_index(kind, range, kInf), 255);
    EXPECT_EQ(colour_index(kind, range, kNaN), -1);
    for (int i = 0; i < kColourTableSize; ++i)
      EXPECT_EQ(colour_index(kind, range, -2 + 4 * (i + 0.5) / kColourTableSize), i);
    EXPECT_EQ(colour_index(kind, ValueRange{1, 1}, 5), 128);  // no width: the middle entry
  }
  EXPECT_EQ(colour_of(ScaleKind::diverging, range, -3), red_white_blue_table()[0]);
  EXPECT_EQ(colour_of(ScaleKind::sequential, range, kNaN), kMissingValueColour);
}

TEST(ColourScale, CategoricalValuesRoundToTheirClass) {
  const ValueRange unused{0, 1};
  EXPECT_EQ(colour_index(ScaleKind::categorical, unused, 3), 3);
  EXPECT_EQ(colour_index(ScaleKind::categorical, unused, 2.4), 2);
  EXPECT_EQ(colour_index(ScaleKind::categorical, unused, 2.5), 3);  // halves away from zero
  EXPECT_EQ(colour_index(ScaleKind::categorical, unused, -0.4), 0);
  EXPECT_EQ(colour_index(ScaleKind::categorical, unused, -0.5), -1);
  EXPECT_EQ(colour_index(ScaleKind::categorical, unused, 255.4), 255);
  EXPECT_EQ(colour_index(ScaleKind::categorical, unused, 255.5), -1);
  EXPECT_EQ(colour_index(ScaleKind::categorical, unused, 1e300), -1);
  EXPECT_EQ(colour_index(ScaleKind::categorical, unused, kNaN), -1);
  EXPECT_EQ(colour_of(ScaleKind::categorical, unused, 300), kMissingValueColour);
}

TEST(ColourScale, DataRangeIgnoresMissingValues) {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const std::vector<float> values{3, nan, -1, 2};
  const ValueRange s = data_range(ScaleKind::sequential, values);
  EXPECT_EQ(s.lo, -1);
  EXPECT_EQ(s.hi, 3);
  const ValueRange d = data_range(ScaleKind::diverging, values);
  EXPECT_EQ(d.lo, -3);
  EXPECT_EQ(d.hi, 3);
  const std::vector<float> flat{4, 4};
  EXPECT_EQ(data_range(ScaleKind::sequential, flat).lo, 3.5);
  EXPECT_EQ(data_range(ScaleKind::sequential, flat).hi, 4.5);
  const std::vector<float> none{nan};
  EXPECT_EQ(data_range(ScaleKind::sequential, none).hi, 1);
  EXPECT_EQ(data_range(ScaleKind::diverging, std::vector<float>{0}).hi, 1);
  EXPECT_EQ(to_string(ScaleKind::diverging), "diverging");
}

}  // namespace
}  // namespace spheremap
