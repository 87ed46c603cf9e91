// seam internal: the length of a bounding box's diagonal, the scale of the relative tolerances
// (the vertex separation, the verification's least tolerance). In doubles, from the boxes of the
// coordinates as doubles: a measure, not a test.
//
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <seam/types.h>

#include <CGAL/Bbox_3.h>
#include <CGAL/Polygon_mesh_processing/bbox.h>

#include <cmath>

namespace seam::internal {

inline double bbox_diagonal(const CGAL::Bbox_3& box) {
  const double dx = box.xmax() - box.xmin(), dy = box.ymax() - box.ymin(), dz = box.zmax() - box.zmin();
  return std::sqrt(dx * dx + dy * dy + dz * dz);
}

template <class K> double bbox_diagonal(const Mesh<K>& mesh) {
  return bbox_diagonal(CGAL::Polygon_mesh_processing::bbox(mesh));
}

/// The diagonal of the box around both meshes.
template <class K> double bbox_diagonal(const Mesh<K>& a, const Mesh<K>& b) {
  return bbox_diagonal(CGAL::Polygon_mesh_processing::bbox(a) + CGAL::Polygon_mesh_processing::bbox(b));
}

}  // namespace seam::internal
