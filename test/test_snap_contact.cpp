// Closing thin features (seam pair's second way: vertices within the vertex separation of a curve
// move onto it) leaves the vertices of a flat contact where they are: moving one tilts its faces
// out of the other surface's plane, and the part of the contact they held is lost (found on a CT
// tow against a copy moved along a grid plane, where seam check then found the intersection
// uncovered). With a list of points (seam pair's targeted way: the points of the pairs of
// vertices a failed output left too close), only the vertices next to them move.
#include <catch2/catch.hpp>

#include <seam/internal/snap.h>

#include <array>
#include <vector>

namespace {

using K = seam::Exact;
using M = seam::Mesh<K>;
using P = K::Point_3;

M mesh_of(const std::vector<P>& points, const std::vector<std::array<int, 3>>& faces) {
  M m;
  std::vector<M::Vertex_index> v;
  for (const P& p : points) v.push_back(m.add_vertex(p));
  for (const auto& f : faces) REQUIRE(m.add_face(v[std::size_t(f[0])], v[std::size_t(f[1])], v[std::size_t(f[2])]) != M::null_face());
  return m;
}

}  // namespace

TEST_CASE("snap to segments: a vertex of a flat contact stays, others move", "[snap]") {
  // A: the unit square in z = 0, fanned from its centre v. The curve passes 1e-9 above v.
  const M a = mesh_of({P(0, 0, 0), P(1, 0, 0), P(1, 1, 0), P(0, 1, 0), P(0.5, 0.5, 0)},
                      {{0, 1, 4}, {1, 2, 4}, {2, 3, 4}, {3, 0, 4}});
  const std::vector<seam::Polyline<K>> curves{{P(0, 0.5, 1e-9), P(1, 0.5, 1e-9)}};
  const M::Vertex_index v(4);
  const double tolerance = 1e-8;

  SECTION("no other surface: v moves onto the curve") {
    M a2 = a;
    const auto r = seam::internal::snap_vertices_to_segments<K>(a2, curves, tolerance, false, true);
    CHECK(r.snapped == 1);
    CHECK(a2.point(v) != a.point(v));
    CHECK(K::Segment_3(curves[0][0], curves[0][1]).has_on(a2.point(v)));
  }
  SECTION("the other surface lies in A's plane over v (a flat contact): v stays") {
    const M b = mesh_of({P(0.2, 0.2, 0), P(0.8, 0.2, 0), P(0.5, 0.8, 0)}, {{0, 1, 2}});
    M a2 = a;
    const auto r = seam::internal::snap_vertices_to_segments<K>(a2, curves, tolerance, false, true, &b);
    CHECK(r.snapped == 0);
    CHECK(a2.point(v) == a.point(v));
  }
  SECTION("the other surface crosses A's plane there (no flat contact): v moves") {
    const M b = mesh_of({P(0.2, 0.2, -0.1), P(0.8, 0.2, 0.1), P(0.5, 0.8, 0)}, {{0, 1, 2}});
    M a2 = a;
    const auto r = seam::internal::snap_vertices_to_segments<K>(a2, curves, tolerance, false, true, &b);
    CHECK(r.snapped == 1);
  }
  SECTION("the other surface lies in A's plane away from v's faces: v moves") {
    const M b = mesh_of({P(2, 0, 0), P(3, 0, 0), P(2, 1, 0)}, {{0, 1, 2}});
    M a2 = a;
    const auto r = seam::internal::snap_vertices_to_segments<K>(a2, curves, tolerance, false, true, &b);
    CHECK(r.snapped == 1);
  }
}

TEST_CASE("snap to segments: with points given, only the vertices next to them move", "[snap]") {
  // A: the rectangle [0, 2] x [0, 1] in z = 0, each unit square fanned from its centre (v6, v7).
  // The curve passes 1e-9 above both centres.
  const M a = mesh_of({P(0, 0, 0), P(1, 0, 0), P(2, 0, 0), P(2, 1, 0), P(1, 1, 0), P(0, 1, 0), P(0.5, 0.5, 0),
                       P(1.5, 0.5, 0)},
                      {{0, 1, 6}, {1, 4, 6}, {4, 5, 6}, {5, 0, 6}, {1, 2, 7}, {2, 3, 7}, {3, 4, 7}, {4, 1, 7}});
  const std::vector<seam::Polyline<K>> curves{{P(0, 0.5, 1e-9), P(2, 0.5, 1e-9)}};
  const M::Vertex_index left(6), right(7);
  const double tolerance = 1e-8;
  M a2 = a;
  SECTION("a point next to the right centre") {
    const std::vector<std::array<double, 3>> near{{1.5, 0.5, 5e-9}};
    const auto r = seam::internal::snap_vertices_to_segments<K>(a2, curves, tolerance, false, true, nullptr, &near);
    CHECK(r.snapped == 1);
    CHECK(a2.point(left) == a.point(left));
    CHECK(K::Segment_3(curves[0][0], curves[0][1]).has_on(a2.point(right)));
  }
  SECTION("points farther than the tolerance from both and from their faces: none moves") {
    const std::vector<std::array<double, 3>> near{{1.5, 0.5, 1e-6}, {3.0, 0.5, 0}};
    const auto r = seam::internal::snap_vertices_to_segments<K>(a2, curves, tolerance, false, true, nullptr, &near);
    CHECK(r.snapped == 0);
  }
  SECTION("a point on a face of the left centre, far from it: the corners of that face may move") {
    // (A vertex poking through the other surface leaves a curve around it whose points can lie
    // farther than the tolerance from it: CT row 10.) Of the corners, only the centre lies within
    // the tolerance of the curve.
    const std::vector<std::array<double, 3>> near{{0.5, 0.1, 0}};
    const auto r = seam::internal::snap_vertices_to_segments<K>(a2, curves, tolerance, false, true, nullptr, &near);
    CHECK(r.snapped == 1);
    CHECK(a2.point(right) == a.point(right));
    CHECK(K::Segment_3(curves[0][0], curves[0][1]).has_on(a2.point(left)));
  }
  SECTION("no list: both move") {
    const auto r = seam::internal::snap_vertices_to_segments<K>(a2, curves, tolerance, false, true);
    CHECK(r.snapped == 2);
  }
}

TEST_CASE("snap to segments: a move that would take a part of the intersection is refused", "[snap]") {
  // A: one face whose edge [p0, p1] lies on B (the square [-2, 2]^2 in z = 0): A meets B in that
  // edge, 1 long. The curve passes 1e-8 above p1; moving p1 onto it lifts the edge off B, and
  // the faces then meet B in p0 alone: 1 away from the part of the contact at p1.
  const M a = mesh_of({P(0, 0, 0), P(1, 0, 0), P(0.5, 1, 1)}, {{0, 1, 2}});
  const M b = mesh_of({P(-2, -2, 0), P(2, -2, 0), P(2, 2, 0), P(-2, 2, 0)}, {{0, 1, 2}, {0, 2, 3}});
  const std::vector<seam::Polyline<K>> curves{{P(1, -1, 1e-8), P(1, 1, 1e-8)}};
  const M::Vertex_index p1(1);
  const double tolerance = 1e-7;
  M a2 = a;
  SECTION("without a contact tolerance p1 moves") {
    const auto r = seam::internal::snap_vertices_to_segments<K>(a2, curves, tolerance, false, true, &b);
    CHECK(r.snapped == 1);
    CHECK(a2.point(p1) != a.point(p1));
  }
  SECTION("with one, under the contact's length, p1 stays") {
    const auto r = seam::internal::snap_vertices_to_segments<K>(a2, curves, tolerance, false, true, &b, nullptr, 0.1);
    CHECK(r.snapped == 0);
    CHECK(r.refused == 1);
    CHECK(a2.point(p1) == a.point(p1));
  }
  SECTION("with one over the contact's length, p1 moves") {
    const auto r = seam::internal::snap_vertices_to_segments<K>(a2, curves, tolerance, false, true, &b, nullptr, 2.0);
    CHECK(r.snapped == 1);
  }
  SECTION("a crossing moved by less than the tolerance: p1 moves") {
    // B tilted so that it crosses A's face along a line through the face: the move shifts that
    // line by about 1e-8, far under the tolerance.
    const M tilted = mesh_of({P(-2, 0.5, -2), P(2, 0.5, -2), P(2, 0.5, 2), P(-2, 0.5, 2)}, {{0, 1, 2}, {0, 2, 3}});
    const auto r = seam::internal::snap_vertices_to_segments<K>(a2, curves, tolerance, false, true, &tilted, nullptr, 0.1);
    CHECK(r.snapped == 1);
  }
}

TEST_CASE("crowded curve points: a curve point with a vertex or another curve point that close", "[snap]") {
  const M a = mesh_of({P(0, 0, 0), P(1, 0, 0), P(0, 1, 0)}, {{0, 1, 2}});
  const M b = mesh_of({P(0, 0, 1), P(1, 0, 1), P(0, 1, 1)}, {{0, 1, 2}});
  const double distance = 1e-6;
  SECTION("a curve point 1e-7 from a vertex of A is crowded; one at a vertex, or far, is not") {
    const std::vector<seam::Polyline<K>> curves{{P(1e-7, 0, 0), P(0.5, 0.5, 0), P(0, 1, 0)}};
    const auto c = seam::internal::crowded_curve_points<K>(curves, a, b, distance);
    REQUIRE(c.size() == 1);
    CHECK(c[0] == std::array<double, 3>{1e-7, 0, 0});
  }
  SECTION("two curve points 1e-7 apart (of two curves) are both crowded") {
    const std::vector<seam::Polyline<K>> curves{{P(0.5, 0.5, 0.5), P(0.6, 0.5, 0.5)},
                                                {P(0.5, 0.5, 0.5 + 1e-7), P(0.5, 0.6, 0.5)}};
    const auto c = seam::internal::crowded_curve_points<K>(curves, a, b, distance);
    CHECK(c.size() == 2);
  }
  SECTION("a point repeated (a closed curve's ends) is not crowded by itself") {
    const std::vector<seam::Polyline<K>> curves{{P(0.5, 0.5, 0.5), P(0.6, 0.5, 0.5), P(0.5, 0.6, 0.5), P(0.5, 0.5, 0.5)}};
    CHECK(seam::internal::crowded_curve_points<K>(curves, a, b, distance).empty());
  }
}

TEST_CASE("snap to segments: a point of contact or a closed curve smaller than the tolerance is one target",
          "[snap]") {
  // The square [0, 2] x [0, 2] in z = 0 fanned from its centre v4 = (1, 1, 0).
  const M a = mesh_of({P(0, 0, 0), P(2, 0, 0), P(2, 2, 0), P(0, 2, 0), P(1, 1, 0)},
                      {{0, 1, 4}, {1, 2, 4}, {2, 3, 4}, {3, 0, 4}});
  const M::Vertex_index centre(4);
  const double tolerance = 1e-8;
  M a2 = a;
  SECTION("a curve of one point (an isolated point of contact) 3e-14 away: the centre moves onto it") {
    const P contact(1 + 3e-14, 1, 0);
    const std::vector<seam::Polyline<K>> curves{{contact}};
    const auto r = seam::internal::snap_vertices_to_segments<K>(a2, curves, tolerance);
    CHECK(r.snapped == 1);
    CHECK(a2.point(centre) == contact);
  }
  SECTION("a closed curve 2e-15 across (a tangential contact's crossing): the centre moves onto its first point") {
    // Onto the segments, vertices of the two tows would land at different points of the loop,
    // 1e-15 apart; all onto one point, they meet there.
    const std::vector<seam::Polyline<K>> curves{
        {P(1 + 9e-14, 1, 0), P(1 + 8e-14, 1 - 1e-15, 0), P(1 + 7e-14, 1, 0), P(1 + 8e-14, 1 + 1e-15, 0),
         P(1 + 9e-14, 1, 0)}};  // (its first point is the farthest from the centre)
    const auto r = seam::internal::snap_vertices_to_segments<K>(a2, curves, tolerance);
    CHECK(r.snapped == 1);
    CHECK(a2.point(centre) == curves[0][0]);
  }
  SECTION("a closed curve larger than the tolerance: onto its nearest segment, as before") {
    const std::vector<seam::Polyline<K>> curves{
        {P(1 + 7e-9, 1 - 1e-8, 0), P(1 + 7e-9, 1 + 1e-8, 0), P(1 + 2e-8, 1, 0), P(1 + 7e-9, 1 - 1e-8, 0)}};
    const auto r = seam::internal::snap_vertices_to_segments<K>(a2, curves, tolerance);
    CHECK(r.snapped == 1);
    CHECK(K::Segment_3(curves[0][0], curves[0][1]).has_on(a2.point(centre)));
  }
}

TEST_CASE("snap to segments: a point of contact takes one vertex of a mesh, none if one is there", "[snap]") {
  // Two unit squares 1e-9 apart (z = 0 and z = 1e-9), each fanned from its centre; a point of
  // contact between the two centres, within the tolerance of both. Moved onto it, both centres
  // would be one point twice (two vertices of the mesh at one point).
  const M a = mesh_of({P(0, 0, 0), P(2, 0, 0), P(2, 2, 0), P(0, 2, 0), P(1, 1, 0), P(0, 0, 1e-9), P(2, 0, 1e-9),
                       P(2, 2, 1e-9), P(0, 2, 1e-9), P(1 + 3e-9, 1, 1e-9)},
                      {{0, 1, 4}, {1, 2, 4}, {2, 3, 4}, {3, 0, 4}, {5, 6, 9}, {6, 7, 9}, {7, 8, 9}, {8, 5, 9}});
  const M::Vertex_index low(4), high(9);
  const double tolerance = 1e-8;
  M a2 = a;
  SECTION("the nearer centre moves, the other stays") {
    const P contact(1 + 1e-9, 1, 0);
    const auto r = seam::internal::snap_vertices_to_segments<K>(a2, {{contact}}, tolerance);
    CHECK(r.snapped == 1);
    CHECK(a2.point(low) == contact);
    CHECK(a2.point(high) == a.point(high));
  }
  SECTION("a centre at the point already: the other stays") {
    const auto r = seam::internal::snap_vertices_to_segments<K>(a2, {{a.point(low)}}, tolerance);
    CHECK(r.snapped == 0);
    CHECK(a2.point(high) == a.point(high));
  }
}
