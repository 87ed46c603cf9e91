// Tests of the pair step that improves the triangles next to the curves (internal/improve.h).
#include <catch2/catch.hpp>

#include <seam/internal/improve.h>
#include <seam/internal/thin_faces.h>
#include <seam/quality.h>

#include <CGAL/boost/graph/helpers.h>

#include <algorithm>
#include <array>
#include <limits>
#include <map>
#include <set>

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

namespace {
using K = seam::Exact;
using M = seam::Mesh<K>;
using V = M::Vertex_index;
using F = M::Face_index;

/// A flat 8 x 8 grid of unit squares in z = 0, two triangles each (diagonal from (i, j) to
/// (i + 1, j + 1)), and the exact figures the tests check on it.
struct FlatGrid {
  M mesh;
  std::vector<V> grid;
  FlatGrid() {
    for (int j = 0; j <= 8; ++j)
      for (int i = 0; i <= 8; ++i) grid.push_back(mesh.add_vertex(K::Point_3(i, j, 0)));
    for (int j = 0; j < 8; ++j)
      for (int i = 0; i < 8; ++i) {
        mesh.add_face(at(i, j), at(i + 1, j), at(i + 1, j + 1));
        mesh.add_face(at(i, j), at(i + 1, j + 1), at(i, j + 1));
      }
  }
  V at(int i, int j) const { return grid[std::size_t(j * 9 + i)]; }
  /// The grid's row y = j, as the one curve.
  std::vector<std::vector<V>> row(int j) const {
    std::vector<std::vector<V>> curve(1);
    for (int i = 0; i <= 8; ++i) curve[0].push_back(at(i, j));
    return curve;
  }
  /// The provenance maps, every face of input face `source` (remeshed when none is given), not new.
  std::pair<M::Property_map<F, std::uint32_t>, M::Property_map<F, bool>> mark_faces(
      std::uint32_t source = std::numeric_limits<std::uint32_t>::max()) {
    return {mesh.add_property_map<F, std::uint32_t>(seam::source_face_property, source).first,
            mesh.add_property_map<F, bool>(seam::new_face_property, false).first};
  }
  std::array<K::Point_3, 3> corners(F f) const {
    const auto h = mesh.halfedge(f);
    return {mesh.point(mesh.source(h)), mesh.point(mesh.target(h)), mesh.point(mesh.target(mesh.next(h)))};
  }
  double smallest_angle() const {
    double worst = 180;
    for (F f : mesh.faces()) {
      const auto [p, q, r] = corners(f);
      worst = std::min(worst, seam::min_angle_deg(p, q, r));
    }
    return worst;
  }
  K::FT twice_area() const {  // signed
    K::FT sum = 0;
    for (F f : mesh.faces()) {
      const auto [p, q, r] = corners(f);
      sum += CGAL::cross_product(q - p, r - p).z();
    }
    return sum;
  }
  bool all_faces_up() const {  // every face keeps its orientation: nothing folded (exact)
    for (F f : mesh.faces()) {
      const auto [p, q, r] = corners(f);
      if (!(CGAL::cross_product(q - p, r - p).z() > 0)) return false;
    }
    return true;
  }
};
}  // namespace

TEST_CASE("improve: the needles of a remeshed band are merged away, no vertex moves, the curve stays",
          "[pair][remesh]") {
  // A flat 8 x 8 grid, all of it "remeshed"; the curve is the row y = 4. Vertices (2, 2) and
  // (5, 6) are pulled to 0.02 from a neighbour: needles.
  FlatGrid g;
  M& mesh = g.mesh;
  const auto flat = seam::internal::triangles_of<K>(mesh);  // the input surface: the plane
  mesh.point(g.at(2, 2)) = K::Point_3(2.98, 2, 0);
  mesh.point(g.at(5, 6)) = K::Point_3(5, 5.02, 0);
  g.mark_faces();
  auto curve = g.row(4);

  std::set<K::Point_3> points_before;
  for (V v : mesh.vertices()) points_before.insert(mesh.point(v));
  const K::FT area_before = g.twice_area();
  const double worst_before = g.smallest_angle();
  REQUIRE(worst_before < 2);

  const seam::internal::SurfaceDistance surface(flat);
  const std::size_t merges = seam::internal::collapse_short_edges_of_thin_faces<K>(mesh, curve, surface, 0.01, 20, 3);
  CHECK(merges >= 2);  // the two needles, and what they leave thin around them
  CHECK(mesh.number_of_removed_vertices() == 0);  // compacted
  REQUIRE(CGAL::is_valid_polygon_mesh(mesh));
  CHECK(g.smallest_angle() > 20);
  CHECK(g.twice_area() == area_before);  // the same square
  CHECK(g.all_faces_up());
  for (V v : mesh.vertices()) CHECK(points_before.count(mesh.point(v)) == 1);  // no vertex moved
  // The curve: the same points, consecutive ones joined by edges.
  REQUIRE(curve[0].size() == 9);
  for (int i = 0; i <= 8; ++i) CHECK(mesh.point(curve[0][std::size_t(i)]) == K::Point_3(i, 4, 0));
  for (std::size_t i = 0; i + 1 < curve[0].size(); ++i)
    CHECK(mesh.halfedge(curve[0][i], curve[0][i + 1]) != M::null_halfedge());

  // A needle along the curve itself is left: curve edges are shared with the other mesh, so the
  // short curve edge stays, and the faces on it stay thin.
  mesh.point(curve[0][3]) = K::Point_3(3.99, 4, 0);
  seam::internal::collapse_short_edges_of_thin_faces<K>(mesh, curve, surface, 0.01, 20, 3);
  REQUIRE(curve[0].size() == 9);
  CHECK(mesh.point(curve[0][3]) == K::Point_3(3.99, 4, 0));
  CHECK(mesh.point(curve[0][4]) == K::Point_3(4, 4, 0));
  for (std::size_t i = 0; i + 1 < curve[0].size(); ++i)
    CHECK(mesh.halfedge(curve[0][i], curve[0][i + 1]) != M::null_halfedge());
  const auto short_edge = mesh.halfedge(curve[0][3], curve[0][4]);
  for (auto h : {short_edge, mesh.opposite(short_edge)}) {
    REQUIRE_FALSE(mesh.is_border(h));
    CHECK(seam::min_angle_deg(mesh.point(mesh.source(h)), mesh.point(mesh.target(h)),
                              mesh.point(mesh.target(mesh.next(h)))) < 2);
  }
  CHECK(g.twice_area() == area_before);
  CHECK(g.all_faces_up());
}

TEST_CASE("improve: a merge may reshape faces of the input over an edge longer than the tolerance, which become remeshed",
          "[pair][remesh]") {
  // A flat 8 x 8 grid of input faces; the curve is the row y = 2. Vertex (5, 6) is pulled to
  // (5, 5.3), 0.3 from (5, 5) (six times the tolerance 0.05): its thinnest face is a new face,
  // the others are faces of the input. Merging it into a neighbour reshapes faces of the input;
  // the surface stays (the plane), so the merge is allowed, and those faces count as remeshed.
  FlatGrid g;
  M& mesh = g.mesh;
  const seam::internal::SurfaceDistance surface(seam::internal::triangles_of<K>(mesh));
  mesh.point(g.at(5, 6)) = K::Point_3(5, 5.3, 0);
  auto marks = g.mark_faces(7);
  auto& source = marks.first;
  auto& is_new = marks.second;
  F thinnest = M::null_face();
  double thinnest_angle = 180;
  for (F f : CGAL::faces_around_target(mesh.halfedge(g.at(5, 6)), mesh)) {
    const double angle = std::apply(seam::min_angle_deg<K::Point_3>, g.corners(f));
    if (angle < thinnest_angle) thinnest_angle = angle, thinnest = f;
  }
  is_new[thinnest] = true;
  REQUIRE(thinnest_angle < 20);
  std::set<std::array<K::Point_3, 3>> faces_before;
  for (F f : mesh.faces()) {
    auto c = g.corners(f);
    std::rotate(c.begin(), std::min_element(c.begin(), c.end()), c.end());
    faces_before.insert(c);
  }
  std::set<K::Point_3> points_before;
  for (V v : mesh.vertices()) points_before.insert(mesh.point(v));
  const K::FT area_before = g.twice_area();
  auto curve = g.row(2);

  CHECK(seam::internal::collapse_short_edges_of_thin_faces<K>(mesh, curve, surface, 0.05, 20, 3) >= 1);
  REQUIRE(CGAL::is_valid_polygon_mesh(mesh));
  CHECK(g.twice_area() == area_before);  // the same square, covered once
  CHECK(g.all_faces_up());
  for (V v : mesh.vertices()) CHECK(points_before.count(mesh.point(v)) == 1);  // no vertex moved
  CHECK(mesh.number_of_vertices() < points_before.size());
  // A face with the corners of a face before is that face: it keeps its input face. Any other
  // is a face of the input reshaped over an edge longer than the tolerance: remeshed, and new.
  std::size_t reshaped = 0;
  for (F f : mesh.faces()) {
    auto c = g.corners(f);
    std::rotate(c.begin(), std::min_element(c.begin(), c.end()), c.end());
    if (faces_before.count(c)) {
      CHECK(source[f] == 7);
      continue;
    }
    ++reshaped;
    CHECK(source[f] == std::numeric_limits<std::uint32_t>::max());
    CHECK(is_new[f]);
    CHECK(std::apply(seam::min_angle_deg<K::Point_3>, c) > thinnest_angle + 1);
  }
  CHECK(reshaped > 0);
  for (int i = 0; i <= 8; ++i) CHECK(mesh.point(curve[0][std::size_t(i)]) == K::Point_3(i, 2, 0));
}

TEST_CASE("improve: the apex of a cap moves onto its long edge, exactly on it, the surface unchanged",
          "[pair][remesh]") {
  // A flat 8 x 8 grid of input faces. The curve runs along the row y = 3 but steps around the
  // edge from (5, 3) to (6, 3): (4, 3), (5, 3), (5, 4), (6, 4), (6, 3), (7, 3). Vertex (5, 2) is
  // pulled to (5.5, 2.99), just below that edge: the face (x, (6, 3), (5, 3)) is a cap, the only
  // new face. No merge removes it: the edge's ends are curve vertices, and merging the apex into
  // either end would fold a face, (4, 2) being pulled to (4.95, 2.5) and (6, 2) to (5.6, 2.5).
  // But the apex is within the tolerance 0.05 of the long edge.
  FlatGrid g;
  M& mesh = g.mesh;
  auto at = [&](int i, int j) { return g.at(i, j); };
  const seam::internal::SurfaceDistance surface(seam::internal::triangles_of<K>(mesh));
  mesh.point(at(5, 2)) = K::Point_3(5.5, 2.99, 0);
  mesh.point(at(4, 2)) = K::Point_3(4.95, 2.5, 0);
  mesh.point(at(6, 2)) = K::Point_3(5.6, 2.5, 0);
  REQUIRE(g.all_faces_up());
  auto marks = g.mark_faces(7);
  auto& source = marks.first;
  auto& is_new = marks.second;
  const F cap = mesh.face(mesh.halfedge(at(6, 3), at(5, 3)));
  REQUIRE(cap != M::null_face());
  source[cap] = std::numeric_limits<std::uint32_t>::max();
  is_new[cap] = true;
  std::vector<std::vector<V>> curve = {{at(4, 3), at(5, 3), at(5, 4), at(6, 4), at(6, 3), at(7, 3)}};
  std::vector<K::Point_3> curve_points;
  for (V v : curve[0]) curve_points.push_back(mesh.point(v));
  const K::FT area_before = g.twice_area();
  REQUIRE(g.smallest_angle() < 2);
  const double cap_angle = std::apply(seam::min_angle_deg<K::Point_3>, g.corners(cap));
  // One pass: the cap alone (the faces it leaves are treated in later passes).
  CHECK(seam::internal::collapse_short_edges_of_thin_faces<K>(mesh, curve, surface, 0.05, 20, 1) == 1);
  REQUIRE(CGAL::is_valid_polygon_mesh(mesh));
  // The cap went, and every face that changed is better than it by more than a degree (the
  // pulls left thin faces of the input around the apex: they stay thin, but not as thin).
  for (F f : mesh.faces())
    if (is_new[f]) CHECK(std::apply(seam::min_angle_deg<K::Point_3>, g.corners(f)) > cap_angle + 1);
  CHECK(g.twice_area() == area_before);  // the same square (projected)
  CHECK(g.all_faces_up());                // covered once
  // Every face kept its input face: the one across the edge was split in its plane, the apex's
  // other faces moved by 0.01 (as snapping would move them); the cap went.
  std::size_t changed = 0;
  for (F f : mesh.faces()) {
    CHECK(source[f] == 7);
    changed += is_new[f] ? 1 : 0;
  }
  CHECK(changed == 7);  // two halves across, five around the apex
  // The apex went onto the edge: a vertex strictly inside it, exactly on the line y = 3.
  std::size_t on_edge = 0;
  for (V v : mesh.vertices()) {
    const auto& p = mesh.point(v);
    if (p.y() == 3 && p.x() > 5 && p.x() < 6) ++on_edge;
    CHECK(p != K::Point_3(5.5, 2.99, 0));
  }
  CHECK(on_edge == 1);
  REQUIRE(curve[0].size() == curve_points.size());
  for (std::size_t i = 0; i < curve[0].size(); ++i) CHECK(mesh.point(curve[0][i]) == curve_points[i]);
}

TEST_CASE("improve: a flat cap is flipped away, judged by the face across only", "[pair][remesh]") {
  // A flat 8 x 8 grid, all of it "remeshed"; the curve is the row y = 6. Vertex (5, 2) is moved
  // to the middle of the diagonal from (4, 2) to (5, 3), 1e-4 above the plane: the face (4, 2),
  // x, (5, 3) is a flat cap standing on its edge (its normal lies in the plane), as CGAL's
  // remeshing leaves some on straight lines of the input. Its normal says nothing about the
  // surface: the flip of its long edge is judged against the face across, and makes two right
  // isosceles triangles.
  FlatGrid g;
  M& mesh = g.mesh;
  const seam::internal::SurfaceDistance surface(seam::internal::triangles_of<K>(mesh));
  const V x = g.at(5, 2);
  mesh.point(x) = K::Point_3(4.5, 2.5, 1e-4);
  g.mark_faces();
  const auto curve = g.row(6);
  const K::FT area_before = g.twice_area();
  REQUIRE(g.smallest_angle() < 0.1);
  REQUIRE_FALSE(g.all_faces_up());  // the cap's normal has no z component
  REQUIRE(mesh.halfedge(g.at(4, 2), g.at(5, 3)) != M::null_halfedge());
  CHECK(seam::internal::flip_to_improve_angles<K>(mesh, curve, surface, 0.01, 2) >= 1);
  REQUIRE(CGAL::is_valid_polygon_mesh(mesh));
  CHECK(mesh.halfedge(g.at(4, 2), g.at(5, 3)) == M::null_halfedge());  // the long edge went
  CHECK(mesh.halfedge(x, g.at(4, 3)) != M::null_halfedge());           // for the other diagonal
  CHECK(g.smallest_angle() > 10);
  CHECK(g.all_faces_up());
  CHECK(g.twice_area() == area_before);  // the same square, covered once
}

TEST_CASE("improve: a wide cap is flipped away, judged by the face across only", "[pair][remesh]") {
  // As above, but vertex (5, 2) goes 0.125 off the diagonal from (4, 2) to (5, 3), towards its
  // own side, and 0.1 above the plane: the face (4, 2), x, (5, 3) is a cap with a largest angle
  // of 154 degrees, its normal 39 degrees from the plane's (caps of three curve vertices where
  // the curve bends look like this). The flip of its long edge makes faces within 11 degrees of
  // the face across and the plane's normal; against the cap's own normal it turns them by more
  // than 30 degrees, and was refused.
  FlatGrid g;
  M& mesh = g.mesh;
  const seam::internal::SurfaceDistance surface(seam::internal::triangles_of<K>(mesh));
  const V x = g.at(5, 2);
  mesh.point(x) = K::Point_3(4.588388, 2.411612, 0.1);
  g.mark_faces();
  const auto curve = g.row(6);
  const K::FT area_before = g.twice_area();
  const F cap = mesh.face(mesh.halfedge(g.at(4, 2), x));
  REQUIRE(cap != M::null_face());
  const auto [p, q, r] = g.corners(cap);
  const double cap_angle = seam::min_angle_deg(p, q, r);
  REQUIRE(cap_angle < 15);
  REQUIRE(g.all_faces_up());
  REQUIRE(mesh.halfedge(g.at(4, 2), g.at(5, 3)) != M::null_halfedge());
  CHECK(seam::internal::flip_to_improve_angles<K>(mesh, curve, surface, 0.1, 2) >= 1);
  REQUIRE(CGAL::is_valid_polygon_mesh(mesh));
  CHECK(mesh.halfedge(g.at(4, 2), g.at(5, 3)) == M::null_halfedge());  // the long edge went
  CHECK(mesh.halfedge(x, g.at(4, 3)) != M::null_halfedge());           // for the other diagonal
  CHECK(g.smallest_angle() > cap_angle + 1);
  CHECK(g.all_faces_up());
  CHECK(g.twice_area() == area_before);  // the same square (projected), covered once
}

TEST_CASE("improve: a vertex next to the curve moves away from it, onto the surface, the curve stays",
          "[pair][remesh]") {
  // An 8 x 8 grid bent into a trough (z = 0.02 (x - 4)^2), all of it "remeshed"; the curve is the
  // row y = 4. Vertex (3, 3) is pulled to (3.05, 3.95), next to the curve vertex (3, 4), on the
  // surface: its faces are thin. The search runs in a tangent plane, so the point it finds is off
  // the bent surface until moved onto it.
  FlatGrid g;
  M& mesh = g.mesh;
  for (int j = 0; j <= 8; ++j)
    for (int i = 0; i <= 8; ++i) mesh.point(g.at(i, j)) = K::Point_3(i, j, 0.02 * (i - 4) * (i - 4));
  const seam::internal::SurfaceDistance surface(seam::internal::triangles_of<K>(mesh));
  const V x = g.at(3, 3);
  mesh.point(x) = K::Point_3(3.05, 3.95, 0.019);  // on the face ((3, 3), (4, 4), (3, 4))
  const auto source = g.mark_faces().first;
  auto curve = g.row(4);
  std::vector<K::Point_3> curve_points;
  for (V v : curve[0]) curve_points.push_back(mesh.point(v));
  REQUIRE(g.smallest_angle() < 5);
  const std::size_t vertices_before = mesh.number_of_vertices();
  const double tol = 0.02;

  CHECK(seam::internal::relocate_vertices_of_thin_faces<K>(mesh, curve, surface, tol, 20, 2) >= 1);
  REQUIRE(CGAL::is_valid_polygon_mesh(mesh));
  CHECK(mesh.number_of_vertices() == vertices_before);
  CHECK(g.smallest_angle() > 20);  // no face below 20 degrees is left, so no vertex is a candidate
  const auto moved_to = seam::to_filtered(mesh.point(x));
  CHECK(surface.distance(moved_to) < 1e-12);  // onto the surface
  CHECK(std::abs(moved_to.z() - 0.02 * (moved_to.x() - 4) * (moved_to.x() - 4)) > 1e-5);  // a chord: not the trough's own z
  for (F f : mesh.faces()) {
    const auto [p, q, r] = g.corners(f);
    CHECK(surface.sampled_distance(seam::to_filtered(p), seam::to_filtered(q), seam::to_filtered(r)) <= tol);
  }
  CHECK(g.all_faces_up());  // nothing folded (exact)
  for (std::size_t i = 0; i < curve[0].size(); ++i) CHECK(mesh.point(curve[0][i]) == curve_points[i]);
  for (std::size_t i = 0; i + 1 < curve[0].size(); ++i)
    CHECK(mesh.halfedge(curve[0][i], curve[0][i + 1]) != M::null_halfedge());
  for (F f : mesh.faces()) CHECK(source[f] == std::numeric_limits<std::uint32_t>::max());  // remeshed stays
}

TEST_CASE("improve: a vertex of faces of the input moves as snapping would, by the tolerance at most",
          "[pair][remesh]") {
  // A flat 8 x 8 grid of input faces. Vertex (6, 1) is pulled to (6.47, 1.96): its thinnest face
  // is a new face (of the embedding), the others are faces of the input.
  FlatGrid g;
  M& mesh = g.mesh;
  const seam::internal::SurfaceDistance surface(seam::internal::triangles_of<K>(mesh));
  const V y = g.at(6, 1);
  mesh.point(y) = K::Point_3(6.47, 1.96, 0);
  auto marks = g.mark_faces(7);
  auto& source = marks.first;
  auto& is_new = marks.second;
  auto curve = g.row(6);
  auto star_angle = [&]() {
    double worst = 180;
    for (F f : CGAL::faces_around_target(mesh.halfedge(y), mesh)) {
      const auto [p, q, r] = g.corners(f);
      worst = std::min(worst, seam::min_angle_deg(p, q, r));
    }
    return worst;
  };
  F thinnest = M::null_face();
  double thinnest_angle = 180;
  for (F f : CGAL::faces_around_target(mesh.halfedge(y), mesh)) {
    const auto [p, q, r] = g.corners(f);
    if (seam::min_angle_deg(p, q, r) < thinnest_angle) thinnest_angle = seam::min_angle_deg(p, q, r), thinnest = f;
  }
  is_new[thinnest] = true;
  const double before = star_angle();
  REQUIRE(before < 10);
  std::map<F, std::array<K::Point_3, 3>> corners_before;
  for (F f : mesh.faces()) corners_before[f] = g.corners(f);
  const double tol = 0.05;

  // Moves change no connectivity. A changed face is new. One that keeps its input face was a
  // face of the input and changed as snapping would change it: one corner moved, by tol at most.
  // Any other change (a second corner, a second move, a new face) makes it remeshed. Returns how
  // many faces changed, and how many of them keep their input face.
  auto check_provenance = [&]() {
    std::size_t changed = 0, snapped = 0;
    for (F f : mesh.faces()) {
      const auto corners = g.corners(f);
      const auto& old_corners = corners_before.at(f);
      std::size_t moved_corners = 0;
      double moved_by = 0;
      for (int i = 0; i < 3; ++i)
        if (corners[i] != old_corners[i]) {
          ++moved_corners;
          moved_by = std::sqrt(CGAL::to_double(CGAL::squared_distance(corners[i], old_corners[i])));
        }
      if (moved_corners == 0) {
        CHECK(source[f] == 7);
        CHECK(is_new[f] == (f == thinnest));
        continue;
      }
      ++changed;
      CHECK(is_new[f]);
      if (source[f] == 7) {
        ++snapped;
        CHECK(f != thinnest);
        CHECK(moved_corners == 1);
        CHECK(moved_by <= tol * (1 + 1e-12));
      } else {
        CHECK(source[f] == std::numeric_limits<std::uint32_t>::max());
      }
    }
    return std::make_pair(changed, snapped);
  };
  // One pass: every vertex that can move touches faces of the input, so moves by tol at most.
  CHECK(seam::internal::relocate_vertices_of_thin_faces<K>(mesh, curve, surface, tol, 20, 1) >= 1);
  REQUIRE(CGAL::is_valid_polygon_mesh(mesh));
  CHECK(star_angle() > before + 1);
  CHECK(g.all_faces_up());
  const auto [changed, snapped] = check_provenance();
  CHECK(changed >= 3);
  CHECK(snapped >= 1);
  // More passes: faces changed once are new faces now, and may change further (then remeshed).
  seam::internal::relocate_vertices_of_thin_faces<K>(mesh, curve, surface, tol, 20, 3);
  REQUIRE(CGAL::is_valid_polygon_mesh(mesh));
  CHECK(star_angle() > before + 1);
  CHECK(g.all_faces_up());
  check_provenance();
}

TEST_CASE("improve: a sharp edge that a collapse next to the border leaves on the border is no trouble",
          "[pair][remesh]") {
  // The flat grid with vertex (3, 1) lifted to z = 2: the edge from (3, 0) to (4, 1) is sharp
  // (its faces far more than 60 degrees apart). The curve is the column x = 4; position 1, (4, 1),
  // is dropped, so (4, 1) collapses into (4, 0): the face (3, 0), (4, 0), (4, 1), which has a
  // border edge, goes, and the sharp edge becomes a border edge. The remeshing must not read the
  // face beyond it (there is none).
  FlatGrid g;
  M& mesh = g.mesh;
  mesh.point(g.at(3, 1)) = K::Point_3(3, 1, 2);
  g.mark_faces(7);
  std::vector<std::vector<V>> curve(1);
  for (int j = 0; j <= 8; ++j) curve[0].push_back(g.at(4, j));
  const std::vector<std::vector<std::size_t>> kept = {{0, 2, 3, 4, 5, 6, 7, 8}};
  std::vector<std::vector<std::size_t>> refused;
  const bool remeshed = seam::internal::coarsen_and_remesh_near_curves<K>(mesh, curve, kept, {}, 0.7, refused);
  CHECK(CGAL::is_valid_polygon_mesh(mesh));
  if (remeshed) {
    REQUIRE(curve.size() == 1);
    CHECK(curve[0].size() == 8);
    CHECK(mesh.point(curve[0][0]) == K::Point_3(4, 0, 0));
    CHECK(mesh.point(curve[0][1]) == K::Point_3(4, 2, 0));
    for (std::size_t i = 0; i + 1 < curve[0].size(); ++i)
      CHECK(mesh.halfedge(curve[0][i], curve[0][i + 1]) != M::null_halfedge());
  } else {
    CHECK_FALSE(refused[0].empty());
  }
}
