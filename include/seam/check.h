// seam::check_pair: the independent verification of a conforming pair (`seam check`), run before
// volume meshing. It uses none of the code that produced the pair (no embedding, no curve
// computation): only the four meshes, the curves and CGAL predicates.
//
// What is checked (each failure is one line in PairCheckReport::problems):
//   1. A2 and B2 are valid triangle meshes: a valid halfedge structure
//      (CGAL::is_valid_polygon_mesh), triangles only, no isolated vertex, no degenerate face
//      (exact collinearity test), no two vertices at the same point, closed when A (B) is closed,
//      and no self-intersection: two faces meet only in their common vertex or edge (the test of
//      CGAL::Polygon_mesh_processing::does_self_intersect, on box_intersection_d candidates).
//   2. Every curve point is a vertex of A2 and of B2 with identical coordinates (looked up by
//      exact comparison, so a point off by one unit in the last place is missing), and every
//      curve segment (two consecutive points) is an edge of both.
//   3. A2 and B2 intersect nowhere but along the curves and their shared faces: merged into one
//      surface (common vertices merged), they are a valid piecewise-linear complex, as a volume
//      mesher needs. A shared face is a face of A2 whose three corners are those of a face of B2
//      (where the surfaces coincide, a flat contact, both hold one common triangulation).
//      Candidate face pairs come from CGAL::box_intersection_d on the face bounding boxes; each
//      is tested exactly. An intersecting pair (A2 face, B2 face) is allowed only when
//        - it is the same triangle (a shared face), or
//        - the two faces share exactly one vertex (same coordinates), neither face's opposite edge
//          meets the other face (the intersection is exactly that vertex), and that vertex is a
//          curve point or both faces are shared faces, or
//        - the two faces share two vertices, they do not overlap in a common plane (the
//          intersection is exactly that edge), and the edge is a curve segment or both faces are
//          shared faces.
//      Anything else fails: crossing, touching off the curves, and two different triangles
//      overlapping in one plane (the interior of a flat contact left as two triangulations).
//      With no curves, any intersection (touching at a point included) is a problem. Only
//      predicates are used, no constructed intersection: the test is exact under the exact and
//      filtered kernels (on the coordinates as given) and rounded under the float kernel; the
//      exact kernel is the reference. `tetgen -d` on the merged outputs agrees (tested).
//   Speed: each face pair is first decided, where possible, by interval arithmetic that is
//   certified to agree with the exact answer (separating axes, plane sides, axis projections);
//   only the rest goes to the kernel's predicates. Near the curves the configurations are
//   degenerate by construction, where the exact kernel's own filters fail; without this the
//   rationals of an in-memory exact result (hundreds of bits after snapping) cost seconds per
//   thousand faces. Measured: two meshes of 85,000 faces read from files, 1.5 s (exact); an
//   in-memory snapped pair of 3,800 faces, 0.1 s.
//   4. The outputs stay within `tol` of the inputs: every vertex of A2 lies within `tol` of the
//      surface of A (AABB tree on double coordinates; a distance found above `tol` is computed
//      again in the kernel to the closest face, so that points exactly on the surface pass with
//      tol = 0 under the exact kernel), and the same for B2 and B. With snapping, vertices
//      moved by up to the snap tolerance, so `tol` must be at least that.
//   5. Distinct vertices of A2 and B2, rounded to doubles, are at least min_vertex_separation x
//      the diagonal of their bounding box apart: TetGen merges closer points (its -T tolerance,
//      1e-8 of that diagonal) and then rejects the faces between them. Two vertices of the
//      inputs that close (A's and B's) are counted, not a problem: the outputs keep them.
//   6. The curves cover the intersection of the inputs: every face pair of A and B that meets is
//      intersected exactly (Epeck on the input coordinates) and sampled (a point; a segment's
//      ends and middle; a coplanar overlap's corners and centroid), the samples rounded to
//      doubles; every sample must lie within `tol` of a curve or of a shared face where the two
//      faces are coplanar (a flat contact does not move), and within 2 tol / sin(angle between the
//      faces) where they cross: how far their line of intersection moves when each face moves by
//      tol (snapping moves a grazing crossing far along the surfaces). A touching contact left
//      out of the curves, or a piece of curve lost, fails here. This uses none of the curve
//      computation of seam::pair (CGAL's triangle-triangle intersection on the inputs only).
// And the figures: sizes, the largest distances of 4, the smallest angle over all faces of A2
// and B2, and the number of faces of A2 (B2) below 10 and 20 degrees that are not faces of A (B)
// (faces compared by their three vertex coordinates, exactly).
//
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <seam/kernels.h>
#include <seam/types.h>

#include <array>
#include <cstddef>
#include <string>
#include <vector>

namespace seam {

/// Check 5: distinct output vertices closer than this fraction of the diagonal of the outputs'
/// bounding box fail (twice TetGen's default tolerance, -T 1e-8, under which it merges points).
inline constexpr double min_vertex_separation = 2e-8;

struct PairCheckReport {
  /// Empty when every check holds; otherwise one one-line description per problem found.
  std::vector<std::string> problems;
  // figures
  std::size_t curves = 0;
  std::size_t curve_vertices = 0;  ///< curve points (the closing repeat of a closed curve not counted)
  std::size_t curve_segments = 0;
  /// Intersecting face pairs (A2 face, B2 face) whose intersection is not on the curves.
  std::size_t intersecting_face_pairs_off_curve = 0;
  /// Face pairs whose bounding boxes overlap (tested exactly) and, of those, intersecting on a curve.
  std::size_t candidate_face_pairs = 0, face_pairs_on_curve = 0;
  /// Largest distance of a vertex of A2 (B2) from the surface of A (B).
  double max_distance_a = 0, max_distance_b = 0;
  /// Smallest angle (degrees) over all faces of A2 / B2.
  double min_angle_deg_a = 0, min_angle_deg_b = 0;
  /// Faces of A2 / B2 whose smallest angle is below 10 / 20 degrees and which are not faces of
  /// the input (compared by their vertex coordinates).
  std::size_t below_10_a = 0, below_20_a = 0, below_10_b = 0, below_20_b = 0;
  /// Faces of A2 / B2 that are not faces of A / B.
  std::size_t new_faces_a = 0, new_faces_b = 0;
  std::size_t vertices_a2 = 0, faces_a2 = 0, vertices_b2 = 0, faces_b2 = 0;
  double tolerance = 0;  ///< the tolerance of checks 4 and 6
  /// Faces of A2 that are also faces of B2 (same three corners): the common triangulation of flat
  /// contacts, written once in a merged surface.
  std::size_t shared_faces = 0;
  /// Check 5: the separation required (min_vertex_separation x the diagonal), and the pairs of
  /// distinct vertices closer than it.
  double min_separation = 0;
  std::size_t close_vertex_pairs = 0;
  /// Pairs that close which are both vertices of the inputs (not a problem of the outputs).
  std::size_t close_vertex_pairs_in_inputs = 0;
  /// Both points of each such pair (of the first 1,000), as written: where a repair must look.
  std::vector<std::array<double, 3>> close_vertex_points;
  /// Check 6: points sampled on the intersection of A and B, those farther than the tolerance
  /// from the curves and the shared faces, and the largest such distance.
  std::size_t intersection_samples = 0, uncovered_samples = 0;
  double max_uncovered_distance = 0;
  /// Faces of A2 / B2 that fail check 1 or 3 (degenerate, in a self-intersection, or meeting the
  /// other mesh off the curves), by face index, sorted, each once: where a repair must look.
  std::vector<std::size_t> conflict_faces_a, conflict_faces_b;
  bool ok() const { return problems.empty(); }
};

/// Runs the checks above on inputs `a`, `b`, outputs `a2`, `b2` and the shared `curves` (closed
/// ones repeat their first point). `a` and `b` are assumed valid (seam::validate_triangle_mesh).
/// Never throws for a failed check: every failure is in the report.
/// Restricts a check to the faces that changed (seam::pair checks the faces it remeshed this
/// way): degenerate faces and face pairs (checks 1 and 3) are tested only where at least one face
/// is marked (faces_a / faces_b, indexed by face index of A2 / B2), and check 4 and the quality
/// figures are skipped, and checks 5 and 6. The rest of checks 1 and 2 runs on the whole meshes.
/// An empty focus (no face marked in either mesh) restricts nothing: checks 1-3 on the whole
/// meshes, 4-6 skipped.
struct CheckFocus {
  std::vector<char> faces_a, faces_b;
};

/// `separation` false skips check 5, which is about outputs as written to a file: for meshes
/// whose inputs are exact values that are not doubles (made in memory; a file cannot hold them
/// either), whose outputs are used as they are.
template <class K>
PairCheckReport check_pair(const Mesh<K>& a, const Mesh<K>& b, const Mesh<K>& a2, const Mesh<K>& b2,
                           const std::vector<Polyline<K>>& curves, double tol, const CheckFocus* focus = nullptr,
                           bool separation = true);

/// The check of one mesh with embedded curves (`seam check-embed`, and seam embed's output as
/// written): checks 1, 2, 4 and 5 above for the output alone, against its input.
///   1. the output is a valid triangle mesh: no degenerate face, no two vertices at one point, no
///      self-intersection, closed when the input is;
///   2. every curve point is a vertex with identical coordinates, every curve segment an edge;
///   4. every output vertex lies within `tol` of the input surface;
///   5. distinct output vertices, in doubles, are min_vertex_separation x the diagonal apart
///      (pairs that close in the input counted apart, not a problem).
/// With `given` (the curves as the user gave them, which need not lie on the surface), the
/// largest distances between them and the embedded curves, both ways (figures: coarsening drops
/// the given points between two crossings).
struct EmbedCheckReport {
  std::vector<std::string> problems;
  std::size_t curves = 0, curve_vertices = 0, curve_segments = 0;
  double tolerance = 0;
  double max_distance = 0;  ///< largest distance of an output vertex from the input surface
  double min_angle_deg = 0;  ///< smallest angle over all output faces
  /// Faces that are not input faces (by their three corners' coordinates), and those of them
  /// below 10 and 20 degrees.
  std::size_t new_faces = 0, below_10 = 0, below_20 = 0;
  std::size_t vertices = 0, faces = 0;
  double min_separation = 0;
  std::size_t close_vertex_pairs = 0, close_vertex_pairs_in_input = 0;
  double given_to_embedded = 0, embedded_to_given = 0;
  /// Output faces that are degenerate or in a self-intersection, by index.
  std::vector<std::size_t> conflict_faces;
  bool ok() const { return problems.empty(); }
};

/// Runs the checks of EmbedCheckReport on `output`, the `curves` embedded in it (closed ones
/// repeat their first point) and its `input`. Never throws for a failed check.
template <class K>
EmbedCheckReport check_embedding(const Mesh<K>& input, const Mesh<K>& output, const std::vector<Polyline<K>>& curves,
                                 double tol, const std::vector<Polyline<K>>* given = nullptr);

}  // namespace seam
