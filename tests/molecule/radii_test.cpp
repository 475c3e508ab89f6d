#include "spheremap/molecule/radii.hpp"

#include <gtest/gtest.h>

namespace spheremap {
namespace {

TEST(Radii, BondiTableAndCustomTables) {
  EXPECT_DOUBLE_EQ(*bondi_radius("C"), 1.70);
  EXPECT_DOUBLE_EQ(*bondi_radius("cl"), 1.75);
  EXPECT_DOUBLE_EQ(*bondi_radius("O"), 1.52);
  EXPECT_FALSE(bondi_radius("FE").has_value());
}

}  // namespace
}  // namespace spheremap
