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
// dropped), holds every vertex of both meshes' faces there, with the edges the two meshes have in
// common (the border, and any curve segment inside) as constraints; the triangles inside the
// border are kept (odd nesting depth). Exact under the exact kernel: the CDT only decides
// orientations and in-circle tests on the given points (Exact_predicates_tag: no point is
// constructed), and its projected area is checked to equal that of the faces it replaces. Under
// the rounded kernels the same tests are exact on the rounded coordinates.
//
// No vertex is removed or moved: vertex i of a mesh keeps index i, the other mesh's vertices of
// the patch are appended. New faces get the source face of the face of their own mesh that
// holds their centroid, are marked new unless they are a face of that mesh already, and get
// shared_face_property, which every later step of pair treats like a frozen face.
//
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <seam/internal/local_edits.h>

#include <cstddef>
#include <string>

namespace seam::internal {

/// (The faces made get shared_face_property, seam/internal/local_edits.h.)
struct FlatContactStats {
  std::size_t patches = 0;       ///< planar contact patches made one common triangulation
  std::size_t shared_faces = 0;  ///< faces of those triangulations (each is in both meshes)
  std::size_t faces_replaced_a = 0, faces_replaced_b = 0;
  /// Patches left as they were (the borders differ in the two meshes, or the triangulation did
  /// not reproduce the patch): seam check rejects their overlaps. `first_left` says why.
  std::size_t patches_left = 0;
  std::string first_left;
};

/// Unifies the flat contacts of `a` and `b` (see above). \pre both are triangle meshes without
/// garbage; the curves where they meet are embedded in both. Throws InternalError when a
/// triangulation does not fit into a mesh (the meshes are then unchanged).
/// A point of B only that is closer than `min_separation` to a point of A in the same patch is
/// not a point of the triangulation: B's vertex there moves onto A's point, within the plane
/// (so no two vertices of the outputs are that close: seam check's check 5).
template <class K> FlatContactStats unify_flat_contacts(Mesh<K>& a, Mesh<K>& b, double min_separation);

}  // namespace seam::internal
