// seam internal: CGAL's isotropic remeshing of the band of faces next to the curves, on double
// coordinates (a step of seam/internal/improve.h). See src/remesh_band.cpp.
//
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Surface_mesh.h>

#include <vector>

namespace seam::internal {

using BandMesh = CGAL::Surface_mesh<CGAL::Exact_predicates_inexact_constructions_kernel::Point_3>;

/// Remeshes `band_faces` of `mesh` with CGAL's isotropic remeshing (3 iterations, target
/// `target_edge_length`). Vertices marked in the bool property "v:fixed" do not move; edges marked
/// in "e:constrained", and the border of the band, are neither split, collapsed nor flipped, even
/// when longer than 4/3 of the target (CGAL then leaves them as they are). Removed elements are
/// garbage collected by the caller.
void remesh_band(BandMesh& mesh, const std::vector<BandMesh::Face_index>& band_faces, double target_edge_length);

}  // namespace seam::internal
