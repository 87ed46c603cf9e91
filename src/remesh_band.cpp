// seam: the isotropic remeshing step of improve.cpp, in its own translation unit.
// SPDX-License-Identifier: GPL-3.0-or-later
//
// CGAL 5.5's isotropic_remeshing has a precondition, checked only in builds with assertions on,
// that protected edges are at most 4/3 of the target length ("Remeshing aborted" otherwise). The
// band's border is made of input edges, which can be longer; CGAL's remesher handles them (a
// protected edge is never split) and Release builds, where preconditions are off, rely on that. So
// that every build (the fuzz and sanitizer builds keep CGAL's assertions on) remeshes the same way,
// CGAL's preconditions are off in this file, and only here.
#define CGAL_NO_PRECONDITIONS 1

#include <seam/internal/remesh_band.h>

#include <CGAL/Polygon_mesh_processing/remesh.h>

namespace seam::internal {

void remesh_band(BandMesh& mesh, const std::vector<BandMesh::Face_index>& band_faces, double target_edge_length) {
  auto fixed = mesh.property_map<BandMesh::Vertex_index, bool>("v:fixed").first;
  auto constrained = mesh.property_map<BandMesh::Edge_index, bool>("e:constrained").first;
  namespace PMP = CGAL::Polygon_mesh_processing;
  PMP::isotropic_remeshing(band_faces, target_edge_length, mesh,
                           CGAL::parameters::number_of_iterations(3)
                               .edge_is_constrained_map(constrained)
                               .vertex_is_constrained_map(fixed)
                               .collapse_constraints(false)
                               .protect_constraints(true));
}

}  // namespace seam::internal
