// Private to the surface stage: lowering the SES field around the probe centres on the SAS surface
// (probe_centres.hpp), the exact squared distance to them within a ball around each.
#pragma once

#include <vector>

#include "spheremap/mesh.hpp"
#include "spheremap/surface/grid.hpp"

namespace spheremap::detail {

/// Lowers every sample within `radius` (grid units) of a centre (and some a little farther: any sample
/// may take its exact distance to a valid centre) to its squared distance in grid units², except where
/// every sample of the row's segments is at most `settled` (grid units²): such rows keep their values.
/// Rows of a ball of radius `radius` + sqrt(3)/2 around the nearest sample hold every sample within
/// `radius` of the centre; they come from one table, so the inner loop has no square root or rounding.
/// Plane k belongs to chunk k % threads; min is exact and order-free, so the result is deterministic.
/// `use_avx2`: a float field may use AVX2 where the processor has it (the same values).
/// Preconditions: centres in grid units (finite); threads >= 1.
template <typename T>
void lower_near_centres(Grid3<T>& field, const std::vector<Vec3>& centres, double radius, double settled, int threads,
                        bool use_avx2);

}  // namespace spheremap::detail
