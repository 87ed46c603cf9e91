// seam internal: the piecewise-linear complex of a volume mesh (tows + box faces) and the
// steps of seam::volume_mesh that build and check it. See include/seam/volume_mesh.h.
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <seam/kernels.h>
#include <seam/io.h>
#include <seam/volume_mesh.h>

#include <array>
#include <cstddef>
#include <map>
#include <string>
#include <unordered_map>
#include <vector>

namespace seam::internal {

/// A triangle by its corners, sorted (orientation ignored).
using FaceKey = std::array<std::size_t, 3>;
inline FaceKey face_key(std::size_t a, std::size_t b, std::size_t c) {
  FaceKey k{a, b, c};
  if (k[0] > k[1]) std::swap(k[0], k[1]);
  if (k[1] > k[2]) std::swap(k[1], k[2]);
  if (k[0] > k[1]) std::swap(k[0], k[1]);
  return k;
}
struct FaceKeyHash {
  std::size_t operator()(const FaceKey& k) const {
    std::size_t h = k[0] * 0x9E3779B97F4A7C15ull;
    h ^= k[1] + 0x9E3779B97F4A7C15ull + (h << 6) + (h >> 2);
    h ^= k[2] + 0x9E3779B97F4A7C15ull + (h << 6) + (h >> 2);
    return h;
  }
};

/// Who a triangle of the complex belongs to: one tow (tow_b < 0), two tows (a shared face), the
/// box (tow_a < 0), or a tow and the box (a tow face lying in a box face).
struct TriangleOwner {
  int tow_a = -1;
  std::size_t face_a = 0;  ///< index in tow_a's soup
  int tow_b = -1;
  std::size_t face_b = 0;
  bool on_box = false;
};

/// One connected component (by edges) of a tow: its triangles, as oriented in the tow, in
/// indices of Plc::points.
struct TowComponent {
  int tow = 0;
  std::vector<std::array<std::size_t, 3>> triangles;
};

struct Plc {
  std::vector<Point3d> points;
  std::map<Point3d, std::size_t> index;  ///< exact coordinates -> point
  std::vector<std::array<std::size_t, 3>> triangles;  ///< the tows' first, then the box faces'
  std::size_t tow_triangle_count = 0;
  std::vector<TriangleOwner> owner;
  std::unordered_map<FaceKey, std::size_t, FaceKeyHash> triangle_of;
  std::vector<TowComponent> components;
  std::vector<int> orientation;  ///< per tow: +1 outward normals, -1 inward

  std::size_t add_point(const Point3d& p);
  Filtered::Point_3 point(std::size_t i) const { return {points[i][0], points[i][1], points[i][2]}; }
};

/// All tows in one complex: points merged by exact equality, a triangle of two tows once (a
/// third owner, or the same triangle twice in one tow, is InvalidInput), components per tow.
/// `closed`, when given, holds the closed surfaces the tows were cut from (their orientations).
Plc merge_tows(const std::vector<TriangleSoup>& tows, const std::vector<std::string>& names,
               const std::vector<TriangleSoup>* closed = nullptr);

/// Exact test that the triangles of the complex meet only in common vertices and edges (no
/// crossing, no touching elsewhere, no coplanar overlap). InvalidInput naming both tows and faces.
void check_no_overlap(const Plc& plc, const std::vector<std::string>& names);

/// Exact test that two tows sharing an edge do not cross there (each tow's faces at the edge
/// bound a wedge; no face of one may enter the other's wedge): conforming but overlapping tows,
/// the output of seam pair, meet only in common edges and pass check_no_overlap.
/// InvalidInput naming both tows. Indices above 2^32 are not supported (edge keys).
void check_no_crossing_at_edges(const Plc& plc, const std::vector<std::string>& names);

/// The volume enclosed by a closed surface, times 6, signed by its orientation (long double: only
/// the sign is used, and a closed valid surface does not enclose a volume near zero).
long double signed_volume(const TriangleSoup& s);

/// The mean edge length over all tow triangles.
double mean_edge_length(const std::vector<TriangleSoup>& tows);

/// Adds the six faces of `box`, each triangulated (CDT) through the tow vertices and edges lying
/// in it and, when spacing > 0, a grid of that spacing away from them. Tow triangles in a box face
/// are marked on_box, not added again.
void add_box_faces(Plc& plc, const AxisBox& box, double spacing);

/// Tows cut by the matrix box (periodic unit cells): per tow, its surface inside the box and
/// whether it crossed the box. A face inside the closed box is kept as it is; a face crossing it
/// is cut exactly by the box planes (Sutherland-Hodgman with exact cut points) and the convex
/// piece inside is Delaunay-triangulated in a projection (exact predicates, symbolic perturbation:
/// the triangles depend on the piece's corners only, so a face two tows share is cut alike in
/// both); the new corners are then rounded to doubles, each lying exactly in its box plane. A
/// crossing tow is left open along the box; close_clipped_tows adds its caps from the box faces.
/// A face of a crossing tow lying in a box plane is kept where the tow lies inside the box there
/// (it is then part of the box's boundary) and dropped where the tow lies outside. A triangle of
/// a piece whose corners round onto one point is dropped (the same in every face that has them).
/// InvalidInput (naming the tow) when nothing of a tow is inside the box.
///
/// Before the cut, when some tow crosses the box and `snap` > 0: every tow vertex closer than
/// `snap` to a box plane (and within `snap` of the box in the other two axes) is a candidate to
/// move onto that plane. A candidate moves only if, with all other candidates moved, no face at
/// it (in any tow) is degenerate (exact) or turned over, no two points end at one place, and the
/// plane still crosses the tow there: around the point, in each tow, the neighbours off the plane
/// form at most one arc on either side, and where they (or the two faces at an edge in the plane)
/// are all on one side, those faces, their normals summed, face away from the plane (otherwise
/// the tow's part in the box would be pinched to a point or a line). Candidates that fail go back
/// and the rest are tested again, until all pass: each round drops one or ends. The decision
/// depends on the points only, so tows that share a vertex move it alike. `uncut` holds the tows
/// so moved (the tows themselves when nothing moved).
struct ClippedTows {
  std::vector<TriangleSoup> surfaces;
  std::vector<TriangleSoup> uncut;
  std::vector<char> clipped;
  std::size_t snapped = 0;
  double max_move = 0;
};
ClippedTows clip_tows_to_box(const std::vector<TriangleSoup>& tows, const std::vector<std::string>& names,
                             const AxisBox& box, double snap = 0);

/// After add_box_faces, on a complex of clipped tows: the box triangles inside a clipped tow are
/// its caps (owned by the tow and the box). The box faces' triangles are grouped into regions
/// that no tow edge separates; each region lies inside or outside each tow as a whole, which an
/// exact side test against the tow's uncut surface (clipped.uncut) decides on a point inside
/// one of the region's largest triangles (three of them, which must agree). Returns the tows
/// closed (the clipped
/// surfaces plus their caps, oriented as the tow), rebuilds their components. InvalidInput when a
/// region lies inside two tows; InternalError when the tests on one region disagree.
std::vector<TriangleSoup> close_clipped_tows(Plc& plc, const ClippedTows& clipped, const AxisBox& box,
                                             const std::vector<std::string>& names);

/// Minimum / maximum dihedral angle, largest radius-edge ratio and the tets above `bound` (0: none).
void tet_quality(const TetMesh& mesh, double bound, VolumeMeshStats& stats);

}  // namespace seam::internal
