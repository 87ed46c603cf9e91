// seam: the mesh and curve types of the public API.
//
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <CGAL/Surface_mesh.h>

#include <vector>

namespace seam {

/// A triangle surface mesh over kernel K.
template <class K> using Mesh = CGAL::Surface_mesh<typename K::Point_3>;

/// A polyline: its points in order. It is closed when its last point equals its first.
template <class K> using Polyline = std::vector<typename K::Point_3>;

template <class Point> bool is_closed(const std::vector<Point>& polyline) {
  return polyline.size() > 2 && polyline.front() == polyline.back();
}

/// Name of the face property (std::uint32_t) giving, for each output face, the index of the
/// input face it came from ("J so that F_out(i) came from F_in(J(i))").
inline constexpr const char* source_face_property = "f:seam_source_face";
/// Name of the face property (bool): true for faces created by re-triangulation.
inline constexpr const char* new_face_property = "f:seam_new_face";

}  // namespace seam
