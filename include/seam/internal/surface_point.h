// seam internal: a point on a triangle mesh, with the mesh element it lies on.
//
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <seam/errors.h>
#include <seam/kernels.h>
#include <seam/types.h>

#include <algorithm>
#include <vector>

namespace seam::internal {

template <class K> struct MeshTypes {
  using M = Mesh<K>;
  using V = typename M::Vertex_index;
  using H = typename M::Halfedge_index;
  using E = typename M::Edge_index;
  using F = typename M::Face_index;
};

/// Which element of the mesh a point lies on: exactly at a vertex, strictly inside an edge, or
/// strictly inside a face. Under the exact kernel the classification is exact.
enum class Where { vertex, edge, face };

template <class K> struct SurfacePoint {
  using T = MeshTypes<K>;
  Where where = Where::face;
  typename T::V v;  ///< where == vertex
  typename T::E e;  ///< where == edge
  typename T::F f;  ///< where == face
  typename K::Point_3 p;

  /// Same location: same element and the same point (the point compared exactly).
  bool same_as(const SurfacePoint& o) const {
    if (where != o.where) return false;
    switch (where) {
      case Where::vertex: return v == o.v;
      case Where::edge: return e == o.e && p == o.p;
      case Where::face: return f == o.f && p == o.p;
    }
    return false;
  }
};

/// Where some curve points lie, known before locating them (the direct intersection curves of
/// a pair in general position know each point's edge and face in both meshes): looked up by
/// exact point comparison, in place of the search and the exact classification of locating.
template <class K> struct KnownSites {
  std::vector<std::pair<typename K::Point_3, SurfacePoint<K>>> sites;  ///< sorted by point (compare_xyz)

  void sort() {
    std::sort(sites.begin(), sites.end(), [](const auto& x, const auto& y) {
      return CGAL::compare_xyz(x.first, y.first) == CGAL::SMALLER;
    });
  }
  const SurfacePoint<K>* find(const typename K::Point_3& p) const {
    auto it = std::lower_bound(sites.begin(), sites.end(), p, [](const auto& x, const typename K::Point_3& q) {
      return CGAL::compare_xyz(x.first, q) == CGAL::SMALLER;
    });
    return it != sites.end() && it->first == p ? &it->second : nullptr;
  }
};

/// Face f as a kernel triangle, in the face's orientation.
template <class K> typename K::Triangle_3 face_triangle(const Mesh<K>& mesh, typename MeshTypes<K>::F f) {
  const auto h = mesh.halfedge(f);
  return {mesh.point(mesh.source(h)), mesh.point(mesh.target(h)), mesh.point(mesh.target(mesh.next(h)))};
}

/// The faces whose closure contains the point (one for a face point, one or two for an edge
/// point, the fan for a vertex).
template <class K>
std::vector<typename MeshTypes<K>::F> incident_faces(const Mesh<K>& mesh, const SurfacePoint<K>& sp) {
  std::vector<typename MeshTypes<K>::F> faces;
  switch (sp.where) {
    case Where::face: faces.push_back(sp.f); break;
    case Where::edge:
      for (int i = 0; i < 2; ++i) {
        auto h = mesh.halfedge(sp.e, i);
        if (!mesh.is_border(h)) faces.push_back(mesh.face(h));
      }
      break;
    case Where::vertex:
      for (auto f : CGAL::faces_around_target(mesh.halfedge(sp.v), mesh))
        if (f != Mesh<K>::null_face()) faces.push_back(f);
      break;
  }
  return faces;
}

/// True when the closed face f contains the point's element.
template <class K>
bool face_contains(const Mesh<K>& mesh, typename MeshTypes<K>::F f, const SurfacePoint<K>& sp) {
  switch (sp.where) {
    case Where::face: return sp.f == f;
    case Where::edge: {
      for (int i = 0; i < 2; ++i) {
        auto h = mesh.halfedge(sp.e, i);
        if (!mesh.is_border(h) && mesh.face(h) == f) return true;
      }
      return false;
    }
    case Where::vertex:
      for (auto v : CGAL::vertices_around_face(mesh.halfedge(f), mesh))
        if (v == sp.v) return true;
      return false;
  }
  return false;
}

/// A curve followed on the mesh: consecutive points lie in the closed face step_face[i].
template <class K> struct TracedCurve {
  std::vector<SurfacePoint<K>> points;
  /// step_face[i] holds points[i] and points[i+1]; for a closed curve the last entry holds the
  /// closing step from points.back() to points.front().
  std::vector<typename MeshTypes<K>::F> step_face;
  std::vector<long> input_node;  ///< input node index of each point, -1 for crossings found on the way
  bool closed = false;           ///< points.back() is the same location as points.front()
  /// When true, a point inside a face (where == face) holds the input node it was located from,
  /// not the node's projection onto the face: use traced_location() (seam/internal/trace.h) for
  /// where it lies. Vertex and edge points always hold their exact location.
  bool face_points_deferred = false;
};

}  // namespace seam::internal
