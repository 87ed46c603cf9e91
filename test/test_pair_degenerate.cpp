// Tests of seam::pair on degenerate pairs (issue 3, "Tests"): flat faces in contact, tangency at a
// vertex and along an edge, curves through vertices of both meshes, and a copy shifted so that
// vertices of one lie exactly on faces and edges of the other. The meshes are axis-aligned grid
// boxes and small polyhedra with dyadic coordinates, so every input coordinate is an exact double
// and the expected curves are known exactly.
#include <catch2/catch.hpp>

#include <seam/check.h>
#include <seam/io.h>
#include <seam/pair.h>
#include <seam/verify.h>

#include <algorithm>
#include <array>
#include <map>
#include <string>
#include <vector>

#include "test_support.h"

namespace {

using seam::Point3d;

/// Appends point p to `s` unless an identical point is there already; returns its index.
std::size_t add_point(seam::TriangleSoup& s, std::map<Point3d, std::size_t>& index, const Point3d& p) {
  const auto [it, inserted] = index.try_emplace(p, s.points.size());
  if (inserted) s.points.push_back(p);
  return it->second;
}

/// The closed surface of the box [lo, hi], each side a grid of n[u] x n[v] squares, each square
/// split by a diagonal; outward orientation. The grid coordinate i on axis d is
/// lo[d] + (hi[d] - lo[d]) * i / n[d], the same double on every side.
seam::TriangleSoup grid_box(const Point3d& lo, const Point3d& hi, const std::array<int, 3>& n) {
  seam::TriangleSoup s;
  std::map<Point3d, std::size_t> index;
  auto coord = [&](int d, int i) { return lo[d] + (hi[d] - lo[d]) * i / n[d]; };
  for (int axis = 0; axis < 3; ++axis)
    for (int side = 0; side < 2; ++side) {
      const int u = (axis + 1) % 3, v = (axis + 2) % 3;  // (u, v, axis) is right-handed
      auto at = [&](int i, int j) {
        Point3d p;
        p[axis] = side ? hi[axis] : lo[axis];
        p[u] = coord(u, i);
        p[v] = coord(v, j);
        return add_point(s, index, p);
      };
      for (int i = 0; i < n[u]; ++i)
        for (int j = 0; j < n[v]; ++j) {
          const std::size_t p00 = at(i, j), p10 = at(i + 1, j), p11 = at(i + 1, j + 1), p01 = at(i, j + 1);
          if (side) {  // outward is +axis: counterclockwise in (u, v)
            s.triangles.push_back({p00, p10, p11});
            s.triangles.push_back({p00, p11, p01});
          } else {
            s.triangles.push_back({p00, p11, p10});
            s.triangles.push_back({p00, p01, p11});
          }
        }
    }
  return s;
}

/// The octahedron with centre c and vertices c +- r along the axes, outward orientation.
seam::TriangleSoup octahedron(const Point3d& c, double r) {
  seam::TriangleSoup s;
  for (int d = 0; d < 3; ++d)
    for (int sign : {1, -1}) {
      Point3d p = c;
      p[d] += sign * r;
      s.points.push_back(p);  // index 2 d + (sign < 0)
    }
  for (int sx = 0; sx < 2; ++sx)
    for (int sy = 0; sy < 2; ++sy)
      for (int sz = 0; sz < 2; ++sz) {
        const std::size_t x = 0 + sx, y = 2 + sy, z = 4 + sz;
        if ((sx + sy + sz) % 2 == 0)
          s.triangles.push_back({x, y, z});
        else
          s.triangles.push_back({x, z, y});
      }
  return s;
}

/// The tetrahedron p0 p1 p2 p3, outward orientation.
seam::TriangleSoup tetrahedron(const Point3d& p0, const Point3d& p1, const Point3d& p2, const Point3d& p3) {
  seam::TriangleSoup s;
  s.points = {p0, p1, p2, p3};
  auto sub = [](const Point3d& a, const Point3d& b) { return Point3d{a[0] - b[0], a[1] - b[1], a[2] - b[2]}; };
  const Point3d a = sub(p1, p0), b = sub(p2, p0), c = sub(p3, p0);
  const double det = a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) +
                     a[2] * (b[0] * c[1] - b[1] * c[0]);
  REQUIRE(det != 0);
  s.triangles = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
  if (det < 0)
    for (auto& t : s.triangles) std::swap(t[1], t[2]);
  return s;
}

template <class K> seam::Mesh<K> mesh(const seam::TriangleSoup& s) {
  seam::validate_triangle_mesh(s, "test mesh");
  return seam::mesh_from_soup<K>(s, "test mesh");
}

template <class K> typename K::Point_3 point(const Point3d& p) { return typename K::Point_3(p[0], p[1], p[2]); }

void require_ok(const seam::PairCheckReport& report) {
  for (const auto& p : report.problems) UNSCOPED_INFO(p);
  REQUIRE(report.ok());
}

/// The one curve is closed, every point of it lies on the closed polygon `corners` (exact
/// predicates), and every corner is a curve point.
template <class K> void require_curve_is_polygon(const std::vector<seam::Polyline<K>>& curves,
                                                 const std::vector<Point3d>& corners) {
  REQUIRE(curves.size() == 1);
  const auto& c = curves.front();
  REQUIRE(seam::is_closed(c));
  for (std::size_t i = 0; i < c.size(); ++i) {
    bool on = false;
    for (std::size_t k = 0; k < corners.size() && !on; ++k)
      on = typename K::Segment_3(point<K>(corners[k]), point<K>(corners[(k + 1) % corners.size()])).has_on(c[i]);
    INFO("curve point " << i << " at " << CGAL::to_double(c[i].x()) << " " << CGAL::to_double(c[i].y()) << " "
                        << CGAL::to_double(c[i].z()));
    CHECK(on);
  }
  for (const auto& q : corners) {
    INFO("corner " << q[0] << " " << q[1] << " " << q[2]);
    CHECK(std::find(c.begin(), c.end(), point<K>(q)) != c.end());
  }
}

/// The intersection of the surfaces of two boxes [0, h]^3 and [l, l + 2]^3 with 0 < l < h < l + 2
/// (coordinatewise): a hexagon on the boundary of their common box [l, h].
std::vector<Point3d> box_hexagon(const Point3d& l, const Point3d& h) {
  return {{h[0], l[1], l[2]}, {h[0], l[1], h[2]}, {l[0], l[1], h[2]},
          {l[0], h[1], h[2]}, {l[0], h[1], l[2]}, {h[0], h[1], l[2]}};
}

/// The snapping tolerance pair() uses by default (what `seam check --tol` needs).
template <class K> double default_snap(const seam::Mesh<K>& a, const seam::Mesh<K>& b) {
  return 0.1 * std::min(seam::mean_edge_length<K>(a), seam::mean_edge_length<K>(b));
}

/// Pairs copies of a and b with snap_tol `snap`; requires the independent check to pass (tolerance
/// 0 without snapping: exactly the input surfaces) and, without snapping, unchanged surfaces.
template <class K> seam::PairResult<K> pair_and_check(const seam::Mesh<K>& a, const seam::Mesh<K>& b, double snap) {
  auto a2 = a, b2 = b;
  seam::PairOptions o;
  o.embed.snap_tol = snap;
  const auto r = seam::pair<K>(a2, b2, o);
  INFO("note: " << r.stats.note);
  CHECK(seam::check_curves_embedded<K>(a2, r.a).empty());
  CHECK(seam::check_curves_embedded<K>(b2, r.b).empty());
  const double tol = snap == 0 ? 0 : r.stats.snap_tol + 1e-12;
  require_ok(seam::check_pair<K>(a, b, a2, b2, r.curves, tol));
  if (snap == 0) {
    CHECK(seam::check_same_surface<K>(a, a2).empty());
    CHECK(seam::check_same_surface<K>(b, b2).empty());
  }
  return r;
}

}  // namespace

// ------------------------------------------------------------------------------ tangency

TEMPLATE_TEST_CASE("pair degenerate: surfaces touching at one point share a vertex there, a curve of one point",
                   "[pair][degenerate]", seam::Exact, seam::Filtered) {
  using K = TestType;
  // A: [0, 2]^3 in 4 x 4 x 4 squares per side. B: an octahedron standing on A's top face (z = 2)
  // on its lowest vertex; every other point of B is above z = 2. The point of contact becomes a
  // vertex of A too (the vertex there, or a split of the edge or face holding it: A's surface is
  // unchanged), and a curve of one point: the outputs meet exactly in that common vertex.
  const auto a = mesh<K>(grid_box({0, 0, 0}, {2, 2, 2}, {4, 4, 4}));
  struct Case {
    const char* name;
    Point3d touch;
  };
  for (const Case& cs : {Case{"on a vertex of A", {1.0, 1.0, 2.0}}, Case{"inside an edge of A", {1.25, 1.0, 2.0}},
                         Case{"inside a face of A", {1.375, 1.125, 2.0}}}) {
    INFO("B touches A " << cs.name);
    const double r = 0.25;
    const auto b = mesh<K>(octahedron({cs.touch[0], cs.touch[1], cs.touch[2] + r}, r));
    // Unpaired, seam check flags the contact (a meeting off the curves, a point of the
    // intersection no curve covers) and nothing else.
    const auto report = seam::check_pair<K>(a, b, a, b, {}, 0);
    for (const auto& p : report.problems) UNSCOPED_INFO(p);
    REQUIRE(report.problems.size() == 2);
    CHECK(report.problems[0].find("intersect off the curves") != std::string::npos);
    CHECK(report.problems[1].find("points of the intersection of A and B") != std::string::npos);
    for (double snap : {0.0, -1.0}) {
      INFO("snap_tol " << snap);
      const auto res = pair_and_check<K>(a, b, snap);
      CHECK(res.stats.touching_only);
      CHECK(res.stats.contact_points == 1);
      REQUIRE(res.curves.size() == 1);
      REQUIRE(res.curves.front().size() == 1);
      CHECK(res.curves.front().front() == point<K>(cs.touch));
    }
  }
}

TEMPLATE_TEST_CASE("pair degenerate: surfaces touching along one edge share that edge as a curve", "[pair][degenerate]",
                   seam::Exact, seam::Filtered) {
  using K = TestType;
  // A: [0, 2]^3 in 4 x 4 x 4 squares per side. B: a tetrahedron whose lowest edge lies in A's top
  // face (z = 2); its two other vertices are above. The outputs meet along that edge, so it is a
  // curve of both (open: the surfaces only touch there), and the merged outputs are a valid
  // complex: seam check passes, the curve is the edge.
  const auto a = mesh<K>(grid_box({0, 0, 0}, {2, 2, 2}, {4, 4, 4}));
  struct Case {
    const char* name;
    Point3d p, q;
  };
  for (const Case& cs : {Case{"along an edge of A", {0.5, 1.0, 2.0}, {1.0, 1.0, 2.0}},
                         Case{"along edges of A, through a vertex", {0.5, 1.0, 2.0}, {1.5, 1.0, 2.0}},
                         Case{"across faces and edges of A", {0.625, 0.875, 2.0}, {1.375, 1.125, 2.0}},
                         Case{"inside one face of A", {0.5625, 1.0625, 2.0}, {0.6875, 1.125, 2.0}}}) {
    INFO("B touches A " << cs.name);
    const Point3d m = {(cs.p[0] + cs.q[0]) / 2, (cs.p[1] + cs.q[1]) / 2, 2.0};
    const Point3d d = {cs.p[1] - cs.q[1], cs.q[0] - cs.p[0], 0};  // perpendicular to pq in z = 2
    const auto b = mesh<K>(tetrahedron(cs.p, cs.q, {m[0] + d[0] / 2, m[1] + d[1] / 2, 2.5},
                                       {m[0] - d[0] / 2, m[1] - d[1] / 2, 2.5}));
    // Unpaired, seam check flags the contact.
    CHECK_FALSE(seam::check_pair<K>(a, b, a, b, {}, 0).ok());
    for (double snap : {0.0, -1.0}) {
      INFO("snap_tol " << snap);
      const auto res = pair_and_check<K>(a, b, snap);
      REQUIRE(res.curves.size() == 1);
      CHECK_FALSE(seam::is_closed(res.curves.front()));
      // Both ends are explained: the surfaces only touch along the curve.
      CHECK(res.stats.curve_ends.touching == 2);
      CHECK(res.stats.curve_ends.junction + res.stats.curve_ends.border + res.stats.curve_ends.unexplained == 0);
      // Every curve point lies on the edge pq, and both of its ends are curve points.
      const typename K::Segment_3 pq(point<K>(cs.p), point<K>(cs.q));
      for (const auto& x : res.curves.front()) CHECK(pq.has_on(x));
      CHECK(std::find(res.curves.front().begin(), res.curves.front().end(), point<K>(cs.p)) != res.curves.front().end());
      CHECK(std::find(res.curves.front().begin(), res.curves.front().end(), point<K>(cs.q)) != res.curves.front().end());
    }
  }
}

// ------------------------------------------------------------------------------ through vertices

TEMPLATE_TEST_CASE("pair degenerate: a curve through vertices and along edges of both meshes", "[pair][degenerate]",
                   seam::Exact, seam::Filtered) {
  using K = TestType;
  // A = [0, 2]^3 and B = [1, 3]^3 on grids with vertices at the same coordinates: the curve is the
  // hexagon on the boundary of [1, 2]^3, through vertices of both and along grid lines of both.
  struct Case {
    const char* name;
    std::array<int, 3> na, nb;
  };
  for (const Case& cs : {Case{"same grids", {4, 4, 4}, {4, 4, 4}}, Case{"B coarser", {4, 4, 4}, {2, 2, 2}},
                         Case{"different grids per axis", {2, 4, 8}, {4, 2, 4}}}) {
    INFO("case: " << cs.name);
    const auto a = mesh<K>(grid_box({0, 0, 0}, {2, 2, 2}, cs.na));
    const auto b = mesh<K>(grid_box({1, 1, 1}, {3, 3, 3}, cs.nb));
    const auto hexagon = box_hexagon({1, 1, 1}, {2, 2, 2});
    {
      INFO("snap_tol 0");
      const auto r = pair_and_check<K>(a, b, 0.0);
      require_curve_is_polygon<K>(r.curves, hexagon);
      if (cs.na == cs.nb) {  // the curve runs along existing edges of both: nothing to split
        CHECK(r.a.stats.faces_added == 0);
        CHECK(r.b.stats.faces_added == 0);
      }
    }
    if (seam::kernel_traits<K>::exact_constructions) {
      INFO("default snap_tol");
      const auto r = pair_and_check<K>(a, b, -1.0);
      // Nothing to snap: every vertex near the curve is on it already.
      require_curve_is_polygon<K>(r.curves, hexagon);
    }
  }
}

// ------------------------------------------------------------------------------ shifted copies

TEMPLATE_TEST_CASE("pair degenerate: a copy shifted by fractions of an edge (vertices on faces and edges of the other)",
                   "[pair][degenerate]", seam::Exact, seam::Filtered) {
  using K = TestType;
  // A = [0, 2]^3 with edges 0.5; B = A shifted by s. Where s_d is a multiple of 0.5, vertices of B
  // lie in A's sides at 2 along d, and vertices of A in B's sides at s_d; where it is not, B's
  // vertices fall inside A's squares. No two sides are coplanar (every s_d > 0).
  const auto soup_a = grid_box({0, 0, 0}, {2, 2, 2}, {4, 4, 4});
  for (const Point3d& s : {Point3d{0.5, 0.25, 0.125}, Point3d{0.25, 0.5, 0.5}, Point3d{0.375, 0.0625, 0.5}}) {
    INFO("shift " << s[0] << " " << s[1] << " " << s[2]);
    auto soup_b = soup_a;
    for (auto& p : soup_b.points)
      for (int d = 0; d < 3; ++d) p[d] += s[d];
    const auto a = mesh<K>(soup_a), b = mesh<K>(soup_b);
    {
      INFO("snap_tol 0");
      const auto r = pair_and_check<K>(a, b, 0.0);
      require_curve_is_polygon<K>(r.curves, box_hexagon(s, {2, 2, 2}));
    }
    if (seam::kernel_traits<K>::exact_constructions) {
      INFO("default snap_tol");
      const auto r = pair_and_check<K>(a, b, -1.0);
      REQUIRE(r.curves.size() == 1);
      CHECK(seam::is_closed(r.curves.front()));
    }
  }
}

// ------------------------------------------------------------------------------ coplanar contact

TEMPLATE_TEST_CASE("pair degenerate: flat sides in contact give the boundary of the contact region as the curve",
                   "[pair][degenerate][coplanar]", seam::Exact, seam::Filtered) {
  using K = TestType;
  // A = [0, 2] x [0, 2] x [0, 1] and B a box on top of it, B's bottom in A's top (z = 1): the
  // boxes touch in a rectangle of that plane and are apart elsewhere. The grids do not match (B's
  // vertices fall inside A's squares), so inside the rectangle the two triangulations cross.
  const auto a = mesh<K>(grid_box({0, 0, 0}, {2, 2, 1}, {4, 4, 2}));
  struct Case {
    const char* name;
    Point3d lo, hi;
    std::array<int, 3> n;
    std::vector<Point3d> rectangle;  // the contact region
    bool exact_only;  // B's grid is in thirds: the filtered kernel's rounded curve points are not
                      // on the faces, and the inside of the contact is not recognised
  };
  const std::vector<Case> cases = {
      {"overlapping corners", {0.75, 1.25, 1}, {2.75, 3.25, 2}, {4, 4, 2},
       {{0.75, 1.25, 1}, {2, 1.25, 1}, {2, 2, 1}, {0.75, 2, 1}}, false},
      {"B's bottom inside A's top", {0.75, 0.25, 1}, {1.75, 1.25, 1.5}, {2, 2, 1},
       {{0.75, 0.25, 1}, {1.75, 0.25, 1}, {1.75, 1.25, 1}, {0.75, 1.25, 1}}, false},
      {"B's bottom inside A's top, B's grid in thirds", {0.75, 0.25, 1}, {1.75, 1.25, 1.5}, {3, 3, 1},
       {{0.75, 0.25, 1}, {1.75, 0.25, 1}, {1.75, 1.25, 1}, {0.75, 1.25, 1}}, true},
      {"sides flush with A's (coplanar sides meet along the rectangle)", {0, 1.25, 1}, {2, 3.25, 2}, {4, 4, 2},
       {{0, 1.25, 1}, {2, 1.25, 1}, {2, 2, 1}, {0, 2, 1}}, false},
  };
  for (const auto& cs : cases) {
    if (cs.exact_only && !seam::kernel_traits<K>::exact_constructions) continue;
    INFO("case: " << cs.name);
    const auto b = mesh<K>(grid_box(cs.lo, cs.hi, cs.n));
    {
      INFO("snap_tol 0");
      const auto r = pair_and_check<K>(a, b, 0.0);
      require_curve_is_polygon<K>(r.curves, cs.rectangle);
      CHECK_FALSE(r.stats.touching_only);
      // The inputs themselves do not pass: where a side leaves the common plane it meets the
      // other box's face off any curve.
      const auto unpaired = seam::check_pair<K>(a, b, a, b, {}, 0);
      CHECK(unpaired.intersecting_face_pairs_off_curve > 0);
      CHECK_FALSE(unpaired.ok());
    }
    if (seam::kernel_traits<K>::exact_constructions) {
      INFO("default snap_tol");
      const auto r = pair_and_check<K>(a, b, -1.0);
      REQUIRE(r.curves.size() == 1);
      CHECK(seam::is_closed(r.curves.front()));
    }
  }
}
