// seam internal: flat contacts made one common triangulation (pair step, after the embedding).
//
// Where two tows coincide over an area (faces of A in the plane of faces of B and overlapping
// them: voxel-derived CT tows, compressed textile models, a tow against a copy of itself moved
// along a grid plane), embedding the boundary of the contact is not enough: inside it the two
// meshes would keep two different triangulations of one planar region, which cross each other
// (a volume mesher rejects the merged surface). This step replaces, in each planar contact
// patch, the faces of both meshes by one constrained Delaunay triangulation of the patch, so
// that both outputs hold the same triangles there (shared faces, bit-identical).
//
// A patch is a connected set of faces of A and B in one plane: A faces overlapping B faces with
// positive area (exact coplanarity and 2D separating-axis tests), joined across edges to
// neighbours that are contact faces in the same plane. It is unified only when the border of its
// A faces equals the border of its B faces, edge for edge (exact coordinates): the curves
// embedded before (the boundary of the contact region and its ridges) make it so. Its CDT, in the
// plane projected along the axis of the normal's largest component (exact: a coordinate is
// dropped), holds the points that are vertices of both meshes there (the border's, the curves'
// and the points of contact), with the border and the curve segments inside as constraints (and
// the segments of `others` that both meshes hold inside, a third tow's curves with each where it
// crosses the contact: constraints never split); the
// triangles inside the border are kept (odd nesting depth). The vertices of one mesh only inside
// the patch are dropped: interleaved, the two meshes' own vertices made the common
// triangulation's slivers.
//
// Refinement (when `min_angle_deg` > 0): Ruppert's Delaunay refinement of the inside, in the
// projection (an affine map of the plane: it changes angles, so the bound is held in the
// projection along the dominant axis, where angles shrink by at most the factor the normal's
// tilt allows; the figures are measured in 3D afterwards).
//   1. A constraint encroached by a vertex of the patch (it sees the constraint at 90 degrees or
//      more) is split at its middle.
//   2. A face below the bound, or with `max_area`, larger than it: its circumcenter c (rounded to
//      doubles in the projection, then lifted exactly onto the plane). If a constraint lies between the face and c, or c lies in
//      the diametral circle of a constraint of its conflict zone, that constraint is split;
//      otherwise c is inserted.
//   A constraint may be split when it is at least 2 x `feature_size` long and is a curve segment
//   inside the patch, or a curve segment of the border whose faces outside the patch (in A and in
//   B) belong to no contact patch and are not frozen: its middle is a point of both surfaces
//   (exact under the exact kernel), the face beyond it in each mesh is split with it (a fan of
//   that face's plane: the surface is unchanged), and the curves get the point. A circumcenter
//   nearer than `feature_size` to the face's corners (circumradius below it) is not inserted.
//   Termination: every inserted point is at least `feature_size` from the points it sees (an
//   empty circumcircle), and every split halves a segment at least twice that long, so the points
//   a patch can receive are bounded by its area and border length over feature_size; a budget of
//   4 x (points) + 64 edits, plus twice the patch's area over max_area, bounds it outright. The
//   bound: in the plane, with no constraint split refused and input angles between constraints
//   of at least 60 degrees, Ruppert's algorithm ends with every angle above
//   arcsin(1/(2 sqrt 2)) = 20.7 degrees. What can force a smaller
//   angle: a small angle between two constraints (curves meeting at the border), constraints
//   that may not be split (the border next to another patch or a frozen face, or shorter than
//   2 x feature_size), and points closer than feature_size. The faces left below the bound are
//   counted (shared_faces_below_bound) and reported by the quality stage as flat_contact.
//
// Exact under the exact kernel: the CDT decides orientations and in-circle tests on the points
// (Exact_predicates_tag), split points are exact middles, Steiner points lie exactly in the plane,
// and the triangulation's projected area is checked to equal that of the faces it replaces.
// Under the rounded kernels the tests are exact on the rounded coordinates.
//
// The vertices kept keep their order; those dropped are gone from the result, the new points are
// appended; the curves given follow (their vertices renumbered, split points inserted). New
// faces get the source face of the face of their own mesh that holds their centroid (a split
// face: its own), are marked new unless they are a face of that mesh already, and patch faces get
// shared_face_property, which every later step of pair treats like a frozen face.
//
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <seam/internal/local_edits.h>

#include <cstddef>
#include <string>
#include <vector>

namespace seam::internal {

/// Face property of both meshes: per shared face below the angle bound after its contact's
/// refinement, 1 + the ShortfallCause it stays for (std::uint8_t; 0: none recorded):
/// constraint_angle (a border that may not be split, or two constraints meeting at a small
/// angle), feature_size (corners or a segment too close to refine), shape (a degenerate step),
/// budget. A face at the bound in the projection but below it in 3D has none.
inline constexpr const char* shared_reason_property = "f:seam_shared_reason";

/// (The faces made get shared_face_property, seam/internal/local_edits.h.)
struct FlatContactStats {
  std::size_t patches = 0;       ///< planar contact patches made one common triangulation
  std::size_t shared_faces = 0;  ///< faces of those triangulations (each is in both meshes)
  std::size_t faces_replaced_a = 0, faces_replaced_b = 0;
  std::size_t steiner_points = 0;            ///< points inserted inside the patches (in both meshes)
  std::size_t border_splits = 0;             ///< curve segments split (in both meshes)
  std::size_t points_dropped = 0;            ///< vertices of one mesh only inside a patch, both meshes
  std::size_t shared_faces_below_bound = 0;  ///< shared faces left below the angle bound (in the projection)
  /// Patches left as they were (the borders differ in the two meshes, or the triangulation did
  /// not reproduce the patch): seam check rejects their overlaps. `first_left` says why.
  std::size_t patches_left = 0;
  std::string first_left;
  /// Not empty: the refined triangulations did not fit into a mesh (why), and the plain ones
  /// were made instead.
  std::string refinement_failed;
};

struct FlatContactOptions {
  /// The angle bound of the refinement (degrees); 0: no refinement.
  double min_angle_deg = 0;
  /// No point inserted nearer than this to the corners of its face, no constraint shorter than
  /// twice this split.
  double feature_size = 0;
  /// With the refinement: faces larger than this (area on the plane) are refined like faces below
  /// the bound (their circumcenter; its circumradius is at least 0.87 sqrt(max_area), so the
  /// feature size, at most sqrt(max_area) / 2, never refuses it for the face's own corners; a
  /// constraint beyond it or encroached that may not be split does, and the face stays larger). 0:
  /// no bound.
  double max_area = 0;
};

/// The curves both meshes hold: points, and each point's vertex in A and in B (the same sizes).
template <class K> struct ContactCurves {
  std::vector<Polyline<K>>& curves;
  std::vector<std::vector<typename Mesh<K>::Vertex_index>>& vertices_a;
  std::vector<std::vector<typename Mesh<K>::Vertex_index>>& vertices_b;
};

/// Vertex lists of other curves that `a` (`b`) holds, renumbered with the mesh when it is rebuilt
/// (seam::textile: a tow's curves with its other neighbours). A vertex of theirs inside a contact
/// that is dropped is an InternalError (nothing is changed then).
template <class K> struct OtherCurveVertices {
  std::vector<std::vector<typename Mesh<K>::Vertex_index>*> a, b;
};

/// Unifies the flat contacts of `a` and `b` (see above) and updates `curves`. \pre both are
/// triangle meshes without garbage; the curves where they meet are embedded in both. Where the
/// refined triangulations do not fit, the plain ones are made (FlatContactStats::refinement_failed);
/// throws InternalError when those do not fit either (the meshes and curves are then unchanged).
/// Faces shared already (shared_face_property: a contact of a mesh with a third one) stay as they
/// are, with their flags: the border next to them is not split.
template <class K>
FlatContactStats unify_flat_contacts(Mesh<K>& a, Mesh<K>& b, ContactCurves<K> curves, const FlatContactOptions& options,
                                     OtherCurveVertices<K> others = {});

}  // namespace seam::internal
