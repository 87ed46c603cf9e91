// seam internal: CGAL's isotropic remeshing of the band of faces next to the curves, on double
// coordinates (a step of seam/internal/improve.h). See src/remesh_band.cpp.
//
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <CGAL/Filtered_kernel.h>
#include <CGAL/Simple_cartesian.h>
#include <CGAL/Surface_mesh.h>

#include <vector>

namespace seam::internal {

/// Double coordinates, exact (filtered) predicates: the same numbers as Epick, but a kernel type
/// of its own, so that no mesh code compiled in remesh_band.cpp (where CGAL's preconditions are
/// off) is shared with the rest of the library (where they are on in the fuzz build).
using BandKernel = CGAL::Filtered_kernel<CGAL::Simple_cartesian<double>>;
using BandMesh = CGAL::Surface_mesh<BandKernel::Point_3>;

/// Remeshes `band_faces` of `mesh` with CGAL's isotropic remeshing (3 iterations, target
/// `target_edge_length`). Vertices marked in the bool property "v:fixed" do not move; edges marked
/// in "e:constrained", and the border of the band, are neither split, collapsed nor flipped, even
/// when longer than 4/3 of the target (CGAL then leaves them as they are). Removed elements are
/// garbage collected by the caller.
void remesh_band(BandMesh& mesh, const std::vector<BandMesh::Face_index>& band_faces, double target_edge_length);

}  // namespace seam::internal
