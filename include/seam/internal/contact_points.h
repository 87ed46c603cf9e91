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

/// Makes each of `points` (each exactly on the surface of `mesh`) a vertex of `mesh`: the vertex
/// already there, or a new one splitting the edge (the two faces on it split in their planes) or
/// the face that holds it (three faces in its plane): the surface is unchanged. New faces keep
/// the source face of the face they were cut from and are marked new. Exact tests under the exact
/// kernel. Returns the vertices in the order of `points`, or an empty vector when a point lies on
/// no face exactly (rounded kernels): then nothing was inserted.
template <class K>
std::vector<typename MeshTypes<K>::V> insert_points(Mesh<K>& mesh, const std::vector<typename K::Point_3>& points);

}  // namespace seam::internal
