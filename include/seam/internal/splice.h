// seam internal, pipeline step 6: splice the patches into the mesh.
//
// The output mesh is rebuilt in one pass: the input vertices keep their indices, the new curve
// points and then the Steiner points are appended, and each input face is either copied or
// replaced by its patch, in input order (so the output is deterministic). A crossing point is
// one vertex shared by the patches on both sides of its edge.
//
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <seam/internal/retriangulate.h>

#include <array>
#include <map>

namespace seam::internal {

/// Adds oriented triangles to a mesh that has its vertices and no face yet, face i =
/// triangles[i], in time linear in their number. Returns triangles.size() on success, else the
/// index of the first triangle that makes the surface non-manifold (the mesh is then unusable).
template <class K>
std::size_t add_triangles(Mesh<K>& mesh, const std::vector<std::array<typename MeshTypes<K>::V, 3>>& triangles);

/// Builds the output mesh. `new_points` are the coordinates of output vertices number
/// mesh.number_of_vertices() + i; `patches` maps a replaced input face to its patch. Sets the
/// face properties source_face_property and new_face_property. Throws InternalError when a
/// patch does not fit (a face cannot be added).
template <class K>
Mesh<K> splice_patches(const Mesh<K>& mesh, const std::vector<typename K::Point_3>& new_points,
                       const std::map<typename MeshTypes<K>::F, FacePatch<K>>& patches);

}  // namespace seam::internal
