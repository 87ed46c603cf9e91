// seam internal: isolated points of contact made vertices of a mesh (pair step, after the
// embedding). Where two tows touch at a point (a vertex of one on a face or edge of the other,
// or two vertices at one point) and nowhere else near, no curve passes: the point becomes a
// vertex of both meshes, and a curve of one point, so that the outputs meet exactly in a common
// vertex there (a valid complex for a volume mesher, and what seam check requires).
//
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <seam/internal/surface_point.h>

#include <vector>

namespace seam::internal {

/// Makes each of `points` (each exactly on both surfaces) a vertex of `a` and of `b`: the vertex
/// already there, or a new one splitting the edge (the two faces on it split in their planes) or
/// the face that holds it (three faces in its plane): the surfaces are unchanged. New faces keep
/// the source face of the face they were cut from and are marked new. Exact tests under the exact
/// kernel. Fills `in_a` and `in_b` with the vertices in the order of `points` and returns true; or
/// returns false when a point lies on no face of one of them exactly (rounded kernels), and then
/// neither mesh is changed (both vectors are left empty).
template <class K>
bool insert_points(Mesh<K>& a, Mesh<K>& b, const std::vector<typename K::Point_3>& points,
                   std::vector<typename MeshTypes<K>::V>& in_a, std::vector<typename MeshTypes<K>::V>& in_b);

}  // namespace seam::internal
