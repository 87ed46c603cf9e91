// seam internal, pair step after the embedding: collapse short curve segments in both meshes.
//
// The curve points of a computed intersection are the crossings of both meshes' edges, so two of
// them can lie very close together along the curve: a crossing of an edge of A just next to a
// crossing of an edge of B. No re-triangulation of the faces around such a short segment avoids
// a thin triangle: its corner facing the segment is tiny. With a snapping tolerance, the curve
// may move by that much: the short segment (P, Q) is collapsed in both meshes at once (P merged
// into Q, an edge collapse in A and the same in B), so both keep sharing the curve, now without
// P. No vertex moves; the faces around P tilt by at most |PQ|. (After the pair's remeshing, with
// a test that keeps faces within the tolerance, both ends may instead merge at a point between.)
//
// A collapse is made only when, in both meshes, it keeps the mesh a 2-manifold (link
// condition), keeps every remaining face around P non-degenerate with its orientation (exact
// under the exact kernel), removes no input vertex, and raises the smallest angle of the faces
// around P and Q. After the collapses, the faces around each merged vertex are tested against
// the other mesh (bounding boxes, then exact triangle tests): they may meet it only in a common
// curve vertex or along a common curve segment. Collapses whose faces fail are undone.
//
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <seam/internal/surface_point.h>

#include <cstddef>
#include <functional>
#include <vector>

namespace seam::internal {

struct CurveCollapseReport {
  std::size_t collapsed = 0;  ///< curve vertices removed from both meshes
  std::size_t tiny_edges_collapsed = 0;  ///< vertices off the curves merged over a tiny edge
  std::size_t refused = 0;    ///< short segments left (topology, fold, no gain, or a crossing)
};

/// Collapses curve segments shorter than `max_length` in both meshes (see above). `curves`,
/// `curve_vertices_a` and `curve_vertices_b` (as in EmbedResult) are updated; both meshes have
/// no garbage afterwards and their vertices below `input_vertices_a` / `_b` keep their indices.
/// Faces around a merged vertex are marked new (new_face_property).
/// Edges not longer than `tiny_length` are collapsed whenever allowed, whatever the angles: on
/// the curves in both meshes, elsewhere in their own mesh when one end is a new vertex off the
/// curves. They are the features (down to 1e-17 here) that exact constructions leave where a
/// snapped vertex lies on the other surface; rounded to doubles on output, their faces would be
/// flat or would cross the other mesh.
/// Optional (`accept_face`): a test of each face as it would be after a merge (mesh 0 is A, 1 is
/// B; its corners rounded to doubles); a merge is made only if every changed face passes it in
/// both meshes (the pair's remeshing uses it to keep faces within the tolerance of the inputs,
/// and then allows segments longer than the tolerance). With it, where neither end of a segment
/// merges into the other, both may merge at P + t (Q - P), t = 1/4, 1/2 or 3/4 (exact: the same
/// point in both meshes and in `curves`): the ends' faces share the move. Then Q moves too; it
/// must not be an input vertex nor on two curves, nor, on an open curve, its end.
/// Optional (`only_next_to_faces_below`, degrees): only segments whose merged end is a corner of a
/// face with a smaller angle, in either mesh, are tried (and tiny ones).
/// Optional (`merge_onto_curves`): a tiny edge from a vertex off the curves (an input vertex too)
/// to a curve vertex is collapsed into the curve vertex, in that mesh alone: the vertex moves by
/// at most tiny_length onto the curve, as snapping would (the last pass of seam::pair, so that no
/// two output vertices are closer than a volume mesher's tolerance).
using MergedFaceTest = std::function<bool(int mesh, const Filtered::Point_3&, const Filtered::Point_3&,
                                          const Filtered::Point_3&)>;
template <class K>
CurveCollapseReport collapse_short_curve_segments(Mesh<K>& a, Mesh<K>& b, std::vector<Polyline<K>>& curves,
                                                  std::vector<std::vector<typename MeshTypes<K>::V>>& curve_vertices_a,
                                                  std::vector<std::vector<typename MeshTypes<K>::V>>& curve_vertices_b,
                                                  double max_length, double tiny_length,
                                                  std::size_t input_vertices_a, std::size_t input_vertices_b,
                                                  const MergedFaceTest& accept_face = {},
                                                  double only_next_to_faces_below = 0, bool merge_onto_curves = false);

/// Removes `m`'s garbage (removed elements) and maps the vertex lists to the vertices' new
/// indices; throws InternalError if a listed vertex was removed.
template <class K>
void compact_keeping_curve_vertices(Mesh<K>& m, std::vector<std::vector<typename MeshTypes<K>::V>>& lists);

}  // namespace seam::internal
