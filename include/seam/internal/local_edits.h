// seam internal: what the steps that edit the mesh next to the curves share (src/improve.cpp,
// src/thin_faces.cpp): normal and cap tests, the curve edges, and the provenance marks of faces.
// All in doubles (rounded); none of it decides exactness.
//
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <seam/kernels.h>
#include <seam/types.h>

#include <CGAL/boost/graph/iterator.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <set>
#include <tuple>
#include <utility>
#include <vector>

namespace seam::internal {

/// Whether non-zero vectors u and v (face normals, say) are less than (`closer` true) or more
/// than (false) the angle whose cosine is `cosine` apart (doubles). A zero vector is neither.
inline bool apart(const Filtered::Vector_3& u, const Filtered::Vector_3& v, double cosine, bool closer) {
  const double norms = std::sqrt(u.squared_length() * v.squared_length());
  return norms > 0 && (closer ? u * v > cosine * norms : u * v < cosine * norms);
}
inline bool less_apart_than(const Filtered::Vector_3& u, const Filtered::Vector_3& v, double cosine) {
  return apart(u, v, cosine, true);
}
inline bool more_apart_than(const Filtered::Vector_3& u, const Filtered::Vector_3& v, double cosine) {
  return apart(u, v, cosine, false);
}

/// The source face of a face that no single input face contains (remeshed, or reshaped).
inline constexpr std::uint32_t remeshed_face = std::numeric_limits<std::uint32_t>::max();

/// The curve edges (consecutive curve vertices), each as (smaller, larger) vertex.
template <class V> std::set<std::pair<V, V>> curve_edge_set(const std::vector<std::vector<V>>& curve_vertices) {
  std::set<std::pair<V, V>> edges;
  for (const auto& vs : curve_vertices)
    for (std::size_t i = 0; i + 1 < vs.size(); ++i) edges.emplace(std::min(vs[i], vs[i + 1]), std::max(vs[i], vs[i + 1]));
  return edges;
}

/// Normals `before` and `after` (of a face before and after a change) are non-zero and less than
/// 30 degrees apart (doubles).
inline bool turns_less_than_30_degrees(const Filtered::Vector_3& before, const Filtered::Vector_3& after) {
  return less_apart_than(before, after, 0.866);
}

/// A triangle whose largest angle is `degrees` or more (doubles): a cap. From 150 degrees its
/// normal says little about the surface; within a degree of 180, nothing.
inline bool is_cap(const Filtered::Point_3& a, const Filtered::Point_3& b, const Filtered::Point_3& c, double degrees) {
  const std::array<Filtered::Vector_3, 3> sides = {b - a, c - b, a - c};
  for (int i = 0; i < 3; ++i) {  // the angle between sides i and i + 1, at their common corner
    const auto &u = sides[i], &v = sides[(i + 1) % 3];
    const double norms = std::sqrt(u.squared_length() * v.squared_length());
    if (norms > 0 && -(u * v) < std::cos(degrees * M_PI / 180) * norms) return true;
  }
  return false;
}

/// Faces next to a frozen stretch of curve (left as embedded after remeshing attempts failed
/// there twice, see coarsen_and_remesh_near_curves): no step after the remeshing changes them, so
/// that the steps cannot make the same conflict there again. (The collapses of dropped curve
/// positions onto the kept ones still reshape the faces at the ends of a stretch.) A mesh without
/// the property has none.
inline constexpr const char* frozen_face_property = "f:seam_frozen";

/// Face property (bool) of both meshes of a pair: a face of the common triangulation of a flat
/// contact (see seam/internal/flat_contacts.h). The same triangle is in both meshes; no step
/// changes it, so that it stays so: it counts as frozen.
inline constexpr const char* shared_face_property = "f:seam_shared";

/// Which faces of a mesh are frozen (see frozen_face_property), shared faces included.
template <class K> struct FrozenFaces {
  using M = seam::Mesh<K>;
  using F = typename M::Face_index;
  using V = typename M::Vertex_index;
  typename M::template Property_map<F, bool> map, shared;
  bool any = false;         ///< whether the mesh has the frozen property
  bool any_shared = false;  ///< whether it has the shared property
  explicit FrozenFaces(const M& mesh) {
    std::tie(map, any) = mesh.template property_map<F, bool>(frozen_face_property);
    std::tie(shared, any_shared) = mesh.template property_map<F, bool>(shared_face_property);
  }
  bool face(F f, bool count_shared = true) const {
    return f != M::null_face() && ((any && map[f]) || (count_shared && any_shared && shared[f]));
  }
  /// Whether a face around v is frozen: moving, merging or splitting at v would change it.
  /// `count_shared` false: shared faces do not count (an edit made identically in both meshes,
  /// at vertices both have at the same point, keeps them shared).
  bool around(const M& mesh, V v, bool count_shared = true) const {
    if (!any && !(count_shared && any_shared)) return false;
    for (auto h : CGAL::halfedges_around_target(mesh.halfedge(v), mesh))
      if (face(mesh.face(h), count_shared)) return true;
    return false;
  }
};

/// The provenance of the faces as the steps on thin faces read and write it, and which are frozen.
template <class K> struct FaceMarks {
  using F = typename seam::Mesh<K>::Face_index;
  using V = typename seam::Mesh<K>::Vertex_index;
  typename seam::Mesh<K>::template Property_map<F, std::uint32_t> source;
  typename seam::Mesh<K>::template Property_map<F, bool> is_new;
  FrozenFaces<K> frozen;
  explicit FaceMarks(seam::Mesh<K>& mesh)
      : source(mesh.template property_map<F, std::uint32_t>(seam::source_face_property).first),
        is_new(mesh.template property_map<F, bool>(seam::new_face_property).first),
        frozen(mesh) {}
  /// A face of the input that no step changed.
  bool untouched_input(F f) const { return source[f] != remeshed_face && !is_new[f]; }
  /// A face the steps may reshape: remeshed, or new (of the embedding, or changed already), and
  /// not frozen.
  bool changeable(F f) const { return !untouched_input(f) && !frozen.face(f); }
  /// f's shape changed: a face of the input whose corner moved by the tolerance at most keeps its
  /// input face, as after snapping; any other face is remeshed.
  void reshaped(F f, bool moved_within_tolerance) {
    if (!moved_within_tolerance || !untouched_input(f)) source[f] = remeshed_face;
    is_new[f] = true;
  }
};

}  // namespace seam::internal
