// The quality stage near a small curve (ImproveOptions::small_curve_limit): a curve smaller than
// the feature size, alone, sets its own, graded scale. Two tows that barely overlap: the tip of a
// tetrahedron 5e-4 into the top face of a box, so that their curve is a triangle with sides of
// about 6e-4 (its box's diagonal about 9e-4) inside a face about 1 across (feature size 0.05). With the rule the stage puts points
// around the curve and no new face is left below 10 degrees; at the global scale alone its faces
// stay slivers from the curve's three points to the face's corners.
#include <catch2/catch.hpp>

#include <seam/check.h>
#include <seam/pair.h>

#include "tow_fixtures.h"

namespace {

using K = seam::Exact;

struct Outcome {
  seam::PairResult<K> result;
  seam::PairCheckReport check;
};

Outcome pair_tip_in_box(double small_curve_limit) {
  const auto box = seam::mesh_from_soup<K>(seam_test::box_soup({0, 0, 0}, {1, 1, 0.2}), "box");
  const double tip = 0.2 - 5e-4;
  const auto tet = seam::mesh_from_soup<K>(
      seam_test::tetrahedron({0.1, 0.15, 0.6}, {0.6, 0.2, 0.6}, {0.35, 0.65, 0.6}, {0.37, 0.41, tip}), "tet");
  Outcome out;
  seam::Mesh<K> a = box, b = tet;
  seam::PairOptions options;
  options.quality.small_curve_limit = small_curve_limit;
  out.result = seam::pair<K>(a, b, options);
  out.check = seam::check_pair<K>(box, tet, a, b, out.result.curves, out.result.stats.verify_tolerance);
  return out;
}

}  // namespace

TEST_CASE("improve: a curve smaller than the feature size gets points around it, at its own scale", "[improve]") {
  const Outcome with = pair_tip_in_box(1.0);  // the default
  REQUIRE(with.result.stats.verified);
  INFO(with.check.problems.size());
  REQUIRE(with.check.ok());
  // One closed curve of three segments, about 9e-4 across, far below the feature size.
  REQUIRE(with.result.curves.size() == 1);
  CHECK(with.result.stats.improve.feature_size > 50 * 9e-4);
  CHECK(with.result.stats.improve.small_curves == 1);
  // Points were put around it (the curve's own three points and the box's face corners alone
  // make slivers), and no new face of either tow is left below 10 degrees.
  CHECK(with.result.stats.improve.insertions + with.result.stats.improve.curve_splits > 0);
  CHECK(with.check.below_10_a + with.check.below_10_b == 0);

  // Without the rule (small_curve_limit 0), the same input leaves slivers: the rule is what
  // removes them, not the input being easy.
  const Outcome without = pair_tip_in_box(0.0);
  REQUIRE(without.check.ok());
  CHECK(without.result.stats.improve.small_curves == 0);
  CHECK(without.check.below_10_a + without.check.below_10_b > 0);
}
