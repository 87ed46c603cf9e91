// internal::cut_into_pieces / join_pieces: curves of several pairs that share segments go to the
// quality stage as pieces that share none, and come back as they were.
//
// SPDX-License-Identifier: GPL-3.0-or-later
#include <catch2/catch.hpp>

#include <seam/internal/curve_pieces.h>

#include <algorithm>
#include <cstdint>
#include <map>
#include <set>
#include <utility>
#include <vector>

namespace {

using K = seam::Exact;
using Point = K::Point_3;
using V = seam::Mesh<K>::Vertex_index;
using Curves = std::vector<seam::Polyline<K>>;
using Vertices = std::vector<std::vector<V>>;

/// Vertex lists for `curves` in a tow: point i of the plane gets vertex `offset` + its index in
/// `points` (one vertex per point, as in a mesh).
Vertices vertices_for(const Curves& curves, const std::vector<Point>& points, std::size_t offset) {
  Vertices out;
  for (const auto& c : curves) {
    auto& vs = out.emplace_back();
    for (const auto& p : c)
      vs.push_back(V(std::uint32_t(offset + std::size_t(std::find(points.begin(), points.end(), p) - points.begin()))));
  }
  return out;
}

}  // namespace

TEST_CASE("curve pieces: common stretches go once, held by every tow holding them; joining gives the curves back",
          "[curve_pieces]") {
  // Points along a line (the overlap, 0..3) and off it. Tow 2 crosses the contact of tows 0 and
  // 1: its closed curve with 0 runs 4-0-1-2-3-5-4, its curve with 1 runs 3-2-1-0-6-7-3 (the other
  // way round, from another start), sharing the stretch 0-1-2-3.
  const std::vector<Point> pts{{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}, {0, 1, 0}, {3, 1, 0}, {0, -1, 0}, {3, -1, 0}};
  Curves c02{{pts[4], pts[0], pts[1], pts[2], pts[3], pts[5], pts[4]}};
  Curves c12{{pts[3], pts[2], pts[1], pts[0], pts[6], pts[7], pts[3]}};
  // A pair sharing nothing: one piece, unchanged.
  Curves c01{{pts[6], pts[4]}};
  // Vertex numbers per tow: tow t numbers point i as 100 t + i.
  Vertices v02_0 = vertices_for(c02, pts, 0), v02_2 = vertices_for(c02, pts, 200);
  Vertices v12_1 = vertices_for(c12, pts, 100), v12_2 = vertices_for(c12, pts, 200);
  Vertices v01_0 = vertices_for(c01, pts, 0), v01_1 = vertices_for(c01, pts, 100);
  const Curves c02_in = c02, c12_in = c12, c01_in = c01;
  const Vertices v02_0_in = v02_0, v02_2_in = v02_2, v12_1_in = v12_1, v12_2_in = v12_2;
  std::vector<seam::internal::PairCurveRefs<K>> refs{
      {0, 1, &c01, &v01_0, &v01_1}, {0, 2, &c02, &v02_0, &v02_2}, {1, 2, &c12, &v12_1, &v12_2}};

  auto pieces = seam::internal::cut_into_pieces<K>(refs, 3);
  CHECK(pieces.shared_segments == 3);
  const auto& shared = pieces.shared;
  REQUIRE(shared.curves.size() == 4);  // c01; c02's stretch and its rest; c12's rest
  CHECK(shared.curves[0] == c01_in[0]);
  // Every segment in exactly one piece; a piece's holders are the tows holding its segments.
  std::map<std::pair<Point, Point>, int> count;
  for (std::size_t p = 0; p < shared.curves.size(); ++p) {
    const auto& c = shared.curves[p];
    for (std::size_t i = 0; i + 1 < c.size(); ++i) ++count[std::minmax(c[i], c[i + 1])];
    std::set<std::size_t> holders;
    for (std::size_t t = 0; t < 3; ++t) {
      if (shared.vertices[t][p].empty()) continue;
      holders.insert(t);
      REQUIRE(shared.vertices[t][p].size() == c.size());
      for (std::size_t i = 0; i < c.size(); ++i)  // each point's vertex in that tow
        CHECK(std::size_t(shared.vertices[t][p][i]) ==
              100 * t + std::size_t(std::find(pts.begin(), pts.end(), c[i]) - pts.begin()));
    }
    auto has = [&](const Point& x) { return std::find(c.begin(), c.end(), x) != c.end(); };
    const std::set<std::size_t> expected = p == 0      ? std::set<std::size_t>{0, 1}      // c01
                                           : has(pts[4]) ? std::set<std::size_t>{0, 2}  // c02's rest
                                           : has(pts[6]) ? std::set<std::size_t>{1, 2}  // c12's rest
                                                         : std::set<std::size_t>{0, 1, 2};
    CHECK(holders == expected);
  }
  for (const auto& [segment, n] : count) CHECK(n == 1);
  CHECK(count.size() == 1 + 3 + 3 + 3);

  // Joined back unchanged (the stage changed nothing): the same curves, from the same places.
  seam::internal::join_pieces<K>(pieces, refs);
  CHECK(c01 == c01_in);
  REQUIRE(c02.size() == 1);
  REQUIRE(c12.size() == 1);
  auto same_loop = [](const seam::Polyline<K>& x, const seam::Polyline<K>& y) {
    // The same closed curve, perhaps from another start (both repeat their first point).
    if (x.size() != y.size() || x.front() != x.back() || y.front() != y.back()) return false;
    const std::size_t n = x.size() - 1;
    for (std::size_t shift = 0; shift < n; ++shift) {
      bool ok = true;
      for (std::size_t i = 0; i < n && ok; ++i) ok = x[i] == y[(i + shift) % n];
      if (ok) return true;
    }
    return false;
  };
  CHECK(same_loop(c02[0], c02_in[0]));
  CHECK(same_loop(c12[0], c12_in[0]));
  CHECK(c02 == c02_in);  // from the same first point, as before the cut
  CHECK(c12 == c12_in);
  // Vertex lists follow their points.
  for (std::size_t i = 0; i < c02[0].size(); ++i) {
    const std::size_t k = std::size_t(std::find(pts.begin(), pts.end(), c02[0][i]) - pts.begin());
    CHECK(std::size_t(v02_0[0][i]) == k);
    CHECK(std::size_t(v02_2[0][i]) == 200 + k);
  }
  for (std::size_t i = 0; i < c12[0].size(); ++i) {
    const std::size_t k = std::size_t(std::find(pts.begin(), pts.end(), c12[0][i]) - pts.begin());
    CHECK(std::size_t(v12_1[0][i]) == 100 + k);
    CHECK(std::size_t(v12_2[0][i]) == 200 + k);
  }
}

TEST_CASE("curve pieces: a stretch that moved where two curves part is an error, not a silent join", "[curve_pieces]") {
  const std::vector<Point> pts{{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {0, 1, 0}, {2, 1, 0}, {0, -1, 0}};
  Curves ca{{pts[3], pts[0], pts[1], pts[2], pts[4]}};
  Curves cb{{pts[5], pts[0], pts[1], pts[2]}};
  Vertices a0 = vertices_for(ca, pts, 0), a2 = vertices_for(ca, pts, 200);
  Vertices b1 = vertices_for(cb, pts, 100), b2 = vertices_for(cb, pts, 200);
  std::vector<seam::internal::PairCurveRefs<K>> refs{{0, 2, &ca, &a0, &a2}, {1, 2, &cb, &b1, &b2}};
  auto pieces = seam::internal::cut_into_pieces<K>(refs, 3);
  CHECK(pieces.shared_segments == 2);
  // The common stretch 0-1-2 loses its first point (as if merged away): the pieces no longer meet.
  for (auto& c : pieces.shared.curves)
    if (c.size() == 3 && c.front() == pts[0]) {
      c.erase(c.begin());
      for (auto& per_tow : pieces.shared.vertices)
        for (auto& vs : per_tow)
          if (vs.size() == 3 && std::size_t(vs.front()) % 100 == 0) vs.erase(vs.begin());
    }
  CHECK_THROWS_AS(seam::internal::join_pieces<K>(pieces, refs), seam::InternalError);
}

TEST_CASE("curve pieces: a stretch along which one curve continues and two others meet end to end is cut there",
          "[curve_pieces]") {
  // Tow 2's curve with tow 1 runs 0-1-2-3-4 along a line; its two curves with tow 0 run 5-0-1-2
  // and 2-3-4-6, meeting at 2. The tows holding each segment of the line are the same on both
  // sides of 2 ({0, 1, 2}); the curves along it are not, and every curve is cut there.
  const std::vector<Point> pts{{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {3, 0, 0}, {4, 0, 0}, {0, 1, 0}, {4, 1, 0}};
  Curves c02{{pts[5], pts[0], pts[1], pts[2]}, {pts[2], pts[3], pts[4], pts[6]}};
  Curves c12{{pts[0], pts[1], pts[2], pts[3], pts[4]}};
  Vertices a0 = vertices_for(c02, pts, 0), a2 = vertices_for(c02, pts, 200);
  Vertices b1 = vertices_for(c12, pts, 100), b2 = vertices_for(c12, pts, 200);
  const Curves c02_in = c02, c12_in = c12;
  std::vector<seam::internal::PairCurveRefs<K>> refs{{0, 2, &c02, &a0, &a2}, {1, 2, &c12, &b1, &b2}};
  auto pieces = seam::internal::cut_into_pieces<K>(refs, 3);
  CHECK(pieces.shared_segments == 4);
  std::map<std::pair<Point, Point>, int> count;
  for (const auto& c : pieces.shared.curves)
    for (std::size_t i = 0; i + 1 < c.size(); ++i) ++count[std::minmax(c[i], c[i + 1])];
  CHECK(count.size() == 6);
  for (const auto& [segment, n] : count) CHECK(n == 1);
  seam::internal::join_pieces<K>(pieces, refs);
  CHECK(c02 == c02_in);
  CHECK(c12 == c12_in);
  CHECK(a0 == vertices_for(c02_in, pts, 0));
  CHECK(b2 == vertices_for(c12_in, pts, 200));
}
