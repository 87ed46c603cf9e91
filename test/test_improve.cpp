// Tests of the pair step that improves the triangles next to the curves (internal/improve.h).
#include <catch2/catch.hpp>

#include <seam/internal/improve.h>

#include <algorithm>

TEST_CASE("improve: a point where two curves cross is kept for both, however close the spacing asks",
          "[pair][remesh]") {
  using K = seam::Exact;
  using P = K::Point_3;
  // Two open curves of 21 points, 0.1 apart, crossing at (1, 0, 0): point 10 of each.
  seam::Polyline<K> along_x, along_y;
  for (int i = 0; i <= 20; ++i) {
    along_x.emplace_back(0.1 * i, 0, 0);
    along_y.emplace_back(1, 0.1 * i - 1, 0);
  }
  along_y[10] = along_x[10];  // the same point, exactly
  // A spacing that keeps only the two ends of each.
  const auto kept = seam::internal::choose_curve_points<K>({along_x, along_y}, 10.0, 0.0);
  REQUIRE(kept.size() == 2);
  for (const auto& k : kept) {
    CHECK(std::is_sorted(k.begin(), k.end()));
    CHECK(std::find(k.begin(), k.end(), 10u) != k.end());
    CHECK(std::find(k.begin(), k.end(), 0u) != k.end());
    CHECK(std::find(k.begin(), k.end(), 20u) != k.end());
    CHECK(k.size() == 3);
  }
  // Without the shared point, only the ends.
  along_y[10] = P(1, 0.001, 0);
  const auto apart = seam::internal::choose_curve_points<K>({along_x, along_y}, 10.0, 0.0);
  CHECK(apart[0].size() == 2);
  CHECK(apart[1].size() == 2);
}
