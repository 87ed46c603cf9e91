// seam internal, pipeline step 5: re-triangulate one face with its constraints (report: the
// Triangle sub-meshing step; here CGAL's constrained Delaunay triangulation and mesher).
//
// The face is mapped to 2D by an affine map onto its own plane: X = L (p - a).u,
// Y = (p - a).v with u = b - a, v = n x u, n the face normal and L a double close to |n|.
// The map is exact and invertible over the rationals, and close to a similarity of ratio |u| L
// (so refinement sees the true angles, up to the rounding of L); a Steiner point (X, Y) lifts
// back to a + u X/(L |u|^2) + v Y/|v|^2, which lies exactly in the face's plane under the exact
// kernel.
// Input points are never lifted: the patch refers to them by id.
//
// Constraints: the three edges split at their points, and the curve segments inside the face.
// Refinement: Delaunay refinement by off-centers that never splits a constrained edge: every
// new point falls strictly inside a triangle of the domain, so no point is ever put on an edge of
// the face or on the curve. (CGAL::Delaunay_mesher_no_edge_refinement_2 was the first choice, but
// it refuses every point that encroaches on a constrained edge, and inside a face bounded by
// constraints on all sides that is every circumcenter: it inserts nothing.) Criteria: smallest
// angle at least min_angle_deg, and, when max_area > 0, area at most max_area; at most
// max_steiner points. Angles forced by two constraints meeting at a vertex are left alone. The
// refinement is kept only if every constraint is still an edge and the worst angle did not get
// worse (or an area bound was asked for).
//
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <seam/internal/surface_point.h>

#include <array>
#include <unordered_map>
#include <vector>

namespace seam::internal {

/// One face to re-triangulate. Ids are output vertex indices.
template <class K> struct FaceConstraints {
  std::array<std::size_t, 3> corner_ids;
  std::array<typename K::Point_3, 3> corners;  ///< in the face's orientation
  /// Points strictly inside edge i (from corner i to corner (i+1)%3), in order from corner i.
  std::array<std::vector<std::pair<std::size_t, typename K::Point_3>>, 3> edge_points;
  std::vector<std::pair<std::size_t, typename K::Point_3>> interior_points;
  std::vector<std::pair<std::size_t, std::size_t>> segments;  ///< curve segments inside the face
};

/// The patch replacing a face: triangles in the face's orientation. A vertex reference r >= 0 is
/// an output vertex id; r < 0 means steiner_points[-r - 1].
template <class K> struct FacePatch {
  std::vector<typename K::Point_3> steiner_points;
  std::vector<std::array<long, 3>> triangles;
  bool refinement_undone = false;
};

/// Points that new Steiner points must keep away from, by at least `distance` (doubles: a hash
/// grid of cells `distance` wide); each Steiner point inserted joins them. `seam pair` under an
/// area bound gives each mesh's refinement the vertices of both meshes and the curve points, so
/// that no Steiner point lies closer than the vertex separation to another vertex of either (a
/// volume mesher would take the two for one point): refinement that cascades into a tiny spot
/// (a grazing crossing) stops there instead. Judged in doubles: a bound on what is written.
class InputSurface;  // seam/internal/improve_state.h

class KeepAway {
 public:
  explicit KeepAway(double distance);
  void add(const std::array<double, 3>& p);
  /// Adds a kernel point (rounded to doubles), a mesh's vertices, polylines' points.
  template <class P> void add_point(const P& p) {
    const auto q = to_filtered(p);
    add({q.x(), q.y(), q.z()});
  }
  template <class K> void add_vertices(const Mesh<K>& mesh) {
    for (auto v : mesh.vertices()) add_point(mesh.point(v));
  }
  template <class K> void add_points(const std::vector<Polyline<K>>& polylines) {
    for (const auto& c : polylines)
      for (const auto& p : c) add_point(p);
  }
  /// Surfaces to keep away from too (not owned; may be empty): `seam pair` gives each mesh the
  /// other's, since a Steiner point that close to it, rounded to doubles, can put the new faces
  /// through it where the two touch (a contact of two tows over an area).
  void set_surfaces(std::vector<const InputSurface*> surfaces) { surfaces_ = std::move(surfaces); }
  /// True when some point added, or a surface, lies closer than `distance` to p.
  bool near(const std::array<double, 3>& p) const;
  /// True when some point added lies closer than `distance` to p but not at it (the surfaces
  /// are not asked).
  bool crowded(const std::array<double, 3>& p) const;

 private:
  /// Some point added lies closer than `distance` to p (at p too, with `at_p`).
  bool point_near(const std::array<double, 3>& p, bool at_p) const;
  using Cell = std::array<long long, 3>;
  struct CellHash {
    std::size_t operator()(const Cell& c) const;
  };
  Cell cell_of(const std::array<double, 3>& p) const;
  double distance_;
  std::unordered_map<Cell, std::vector<std::array<double, 3>>, CellHash> cells_;
  std::vector<const InputSurface*> surfaces_;
};

struct RetriangulateOptions {
  double min_angle_deg = 20.0;
  double max_area = 0.0;
  std::size_t max_steiner = 256;
  KeepAway* keep_away = nullptr;  ///< a candidate Steiner point near these is skipped
};

/// Throws InvalidInput when curve segments cross each other inside the face, InternalError when
/// the constraints are inconsistent (rounded arithmetic).
template <class K>
FacePatch<K> retriangulate_face(const FaceConstraints<K>& face, const RetriangulateOptions& options);

}  // namespace seam::internal
