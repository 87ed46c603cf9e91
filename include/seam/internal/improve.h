// seam internal: improve the triangles next to the shared curves of a pair (pair step, with
// snapping on). See src/improve.cpp.
//
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <seam/internal/surface_point.h>

namespace seam::internal {

/// Chooses which curve points to keep so that consecutive kept points are between about 0.5 and
/// 1.2 `spacing` apart along the curve (every point is kept where the curve is shorter). Returns,
/// per curve, the indices of the kept points (for a closed curve, without the closing repeat).
template <class K>
std::vector<std::vector<std::size_t>> choose_curve_points(const std::vector<Polyline<K>>& curves, double spacing);

/// In `mesh`, whose curve vertices are `curve_vertices` (as embedded, closed curves repeating
/// their first vertex), removes the curve vertices not in `kept` by collapsing them onto kept
/// neighbours along the curve, then remeshes the faces within two rings of the curve with CGAL's
/// isotropic remeshing (target `target_edge_length`; curve vertices fixed, curve edges neither
/// split, collapsed nor flipped) on double coordinates. Kept curve vertices keep their exact
/// coordinates, so two meshes treated with the same `kept` share the coarser curve exactly.
/// Returns false (mesh unchanged) when it fails; `refused` then lists, per curve, the positions
/// that could not be dropped (a collapse would make the surface non-manifold): keep those too and
/// call again, for both meshes. On success `curve_vertices` holds the new curve vertices.
template <class K>
bool coarsen_and_remesh_near_curves(Mesh<K>& mesh, std::vector<std::vector<typename MeshTypes<K>::V>>& curve_vertices,
                                    const std::vector<std::vector<std::size_t>>& kept, double target_edge_length,
                                    std::vector<std::vector<std::size_t>>& refused);

}  // namespace seam::internal
