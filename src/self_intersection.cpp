// seam: the self-intersection test of input meshes. See check_no_self_intersection in seam/io.h.
// SPDX-License-Identifier: GPL-3.0-or-later
#include <seam/io.h>
#include <seam/kernels.h>

#include <CGAL/Polygon_mesh_processing/self_intersections.h>

#include <boost/iterator/function_output_iterator.hpp>

#include <algorithm>
#include <utility>

namespace seam {

namespace {
struct FoundOne {};  // stops the search at the first intersecting pair
}  // namespace

void check_no_self_intersection(const TriangleSoup& soup, const std::string& name) {
  // Epick: exact predicates on the file's doubles. mesh_from_soup adds the faces in order, so a
  // face index of the mesh is the face's index in the file.
  const Mesh<Filtered> mesh = mesh_from_soup<Filtered>(soup, name);
  using F = Mesh<Filtered>::Face_index;
  std::pair<F, F> found;
  auto record = [&](const std::pair<F, F>& faces) {
    found = faces;
    throw FoundOne{};
  };
  try {
    CGAL::Polygon_mesh_processing::self_intersections(mesh, boost::make_function_output_iterator(record));
  } catch (const FoundOne&) {
    const std::size_t f = std::min(std::size_t(found.first), std::size_t(found.second));
    const std::size_t g = std::max(std::size_t(found.first), std::size_t(found.second));
    throw InvalidInput(name + ": faces " + std::to_string(f) + " and " + std::to_string(g) +
                       " intersect (the surface intersects itself)");
  }
}

}  // namespace seam
