// seam, pipeline step 1: snapping. See seam/internal/snap.h.
// SPDX-License-Identifier: GPL-3.0-or-later
#include <seam/internal/snap.h>

#include <CGAL/AABB_segment_primitive.h>
#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/Kd_tree.h>
#include <CGAL/Orthogonal_k_neighbor_search.h>
#include <CGAL/Search_traits_3.h>
#include <CGAL/Search_traits_adapter.h>
#include <CGAL/property_map.h>

#include <algorithm>
#include <cmath>
#include <tuple>

namespace seam::internal {

namespace {

using DK = CGAL::Exact_predicates_inexact_constructions_kernel;  // search on doubles
using DPoint = DK::Point_3;
using NodePointMap = CGAL::Pointer_property_map<DPoint>::type;
using BaseTraits = CGAL::Search_traits_3<DK>;
using Traits = CGAL::Search_traits_adapter<std::size_t, NodePointMap, BaseTraits>;
using Search = CGAL::Orthogonal_k_neighbor_search<Traits>;
using Tree = Search::Tree;
using Distance = Search::Distance;

}  // namespace

/// Would moving v to `target` keep every incident face non-degenerate with its orientation?
/// Under the exact kernel both tests are exact.
template <class K>
bool move_keeps_faces(const Mesh<K>& mesh, typename MeshTypes<K>::V v, const typename K::Point_3& target) {
  for (auto h : CGAL::halfedges_around_target(mesh.halfedge(v), mesh)) {
    if (mesh.is_border(h)) continue;
    // Face (v, a, b) in its orientation, with v = target(h).
    const auto& a = mesh.point(mesh.target(mesh.next(h)));
    const auto& b = mesh.point(mesh.source(h));
    const auto& old_v = mesh.point(v);
    if (CGAL::collinear(target, a, b)) return false;  // flattened
    const auto n_old = CGAL::cross_product(a - old_v, b - old_v);
    const auto n_new = CGAL::cross_product(a - target, b - target);
    if (CGAL::is_negative(n_old * n_new) || CGAL::is_zero(n_old * n_new)) return false;  // flipped
  }
  return true;
}


template <class K>
SnapReport<K> snap_vertices(Mesh<K>& mesh, const std::vector<Polyline<K>>& curves, double tolerance) {
  SnapReport<K> report;
  if (!(tolerance > 0)) return report;

  // Curve nodes (closing repeats included: a duplicate is harmless to the search).
  std::vector<const typename K::Point_3*> nodes;
  for (const auto& c : curves)
    for (const auto& p : c) nodes.push_back(&p);
  if (nodes.empty()) return report;
  std::vector<DPoint> dnodes;
  dnodes.reserve(nodes.size());
  for (auto* p : nodes) dnodes.push_back(to_filtered(*p));

  NodePointMap pmap(dnodes.data());
  std::vector<std::size_t> ids(dnodes.size());
  for (std::size_t i = 0; i < ids.size(); ++i) ids[i] = i;
  Tree tree(ids.begin(), ids.end(), Tree::Splitter(), Traits(pmap));
  tree.build();
  Distance distance(pmap);

  // Candidates: (distance, vertex, node), nearest first; ties broken by indices (deterministic).
  using V = typename MeshTypes<K>::V;
  std::vector<std::tuple<double, std::size_t, std::size_t>> candidates;
  const double tol2 = tolerance * tolerance;
  for (V v : mesh.vertices()) {
    Search search(tree, to_filtered(mesh.point(v)), 1, 0, true, distance);
    auto it = search.begin();
    if (it == search.end()) continue;
    if (it->second <= tol2) candidates.emplace_back(std::sqrt(it->second), std::size_t(v), it->first);
  }
  std::sort(candidates.begin(), candidates.end());

  // Nodes at the same place (a closing repeat, duplicate points) are one node: `canonical`
  // maps each to the first of its group, and a group takes at most one vertex.
  std::vector<std::size_t> order(ids), canonical(ids.size());
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return std::make_tuple(dnodes[a].x(), dnodes[a].y(), dnodes[a].z(), a) <
           std::make_tuple(dnodes[b].x(), dnodes[b].y(), dnodes[b].z(), b);
  });
  for (std::size_t k = 0; k < order.size(); ++k)
    canonical[order[k]] = (k > 0 && dnodes[order[k]] == dnodes[order[k - 1]]) ? canonical[order[k - 1]] : order[k];

  std::vector<char> node_taken(dnodes.size(), 0);
  for (const auto& [d, vi, node] : candidates) {
    if (node_taken[canonical[node]]) continue;
    const V v(static_cast<typename V::size_type>(vi));
    const auto& target = *nodes[node];
    if (!move_keeps_faces<K>(mesh, v, target)) {
      ++report.refused;
      continue;
    }
    mesh.point(v) = target;
    node_taken[canonical[node]] = 1;
    ++report.snapped;
    report.max_move = std::max(report.max_move, d);
    report.moved.push_back(v);
  }
  return report;
}


template <class K>
SnapReport<K> snap_vertices_to_segments(Mesh<K>& mesh, const std::vector<Polyline<K>>& curves, double tolerance) {
  SnapReport<K> report;
  if (!(tolerance > 0)) return report;
  using Point = typename K::Point_3;
  using DK = CGAL::Exact_predicates_inexact_constructions_kernel;
  std::vector<DK::Segment_3> segments;
  std::vector<std::pair<const Point*, const Point*>> ends;
  for (const auto& c : curves)
    for (std::size_t i = 0; i + 1 < c.size(); ++i) {
      const auto p = to_filtered(c[i]), q = to_filtered(c[i + 1]);
      if (p == q) continue;
      segments.emplace_back(p, q);
      ends.emplace_back(&c[i], &c[i + 1]);
    }
  if (segments.empty()) return report;
  using Prim = CGAL::AABB_segment_primitive<DK, std::vector<DK::Segment_3>::const_iterator>;
  CGAL::AABB_tree<CGAL::AABB_traits<DK, Prim>> tree(segments.cbegin(), segments.cend());
  tree.accelerate_distance_queries();
  using V = typename MeshTypes<K>::V;
  std::vector<std::tuple<double, std::size_t, std::size_t>> candidates;
  for (V v : mesh.vertices()) {
    const auto q = to_filtered(mesh.point(v));
    const auto [cp, it] = tree.closest_point_and_primitive(q);
    const double d = std::sqrt(CGAL::squared_distance(q, cp));
    if (d <= tolerance) candidates.emplace_back(d, std::size_t(v), std::size_t(it - segments.cbegin()));
  }
  std::sort(candidates.begin(), candidates.end());
  for (const auto& [d, vi, si] : candidates) {
    const V v(static_cast<typename V::size_type>(vi));
    // The exact closest point of the segment (the segment lies on the surface).
    const Point &p = *ends[si].first, &q = *ends[si].second;
    const auto pq = q - p;
    auto t = ((mesh.point(v) - p) * pq) / pq.squared_length();
    if (t < 0) t = 0;
    if (t > 1) t = 1;
    Point target = p + pq * t;
    make_exact(target);
    if (!move_keeps_faces<K>(mesh, v, target)) {
      ++report.refused;
      continue;
    }
    mesh.point(v) = target;
    ++report.snapped;
    report.max_move = std::max(report.max_move, d);
    report.moved.push_back(v);
  }
  return report;
}

template SnapReport<Exact> snap_vertices<Exact>(Mesh<Exact>&, const std::vector<Polyline<Exact>>&, double);
template SnapReport<Exact> snap_vertices_to_segments<Exact>(Mesh<Exact>&, const std::vector<Polyline<Exact>>&, double);
template bool move_keeps_faces<Exact>(const Mesh<Exact>&, typename MeshTypes<Exact>::V, const Exact::Point_3&);
template SnapReport<Filtered> snap_vertices<Filtered>(Mesh<Filtered>&, const std::vector<Polyline<Filtered>>&, double);
template SnapReport<Filtered> snap_vertices_to_segments<Filtered>(Mesh<Filtered>&, const std::vector<Polyline<Filtered>>&, double);
template bool move_keeps_faces<Filtered>(const Mesh<Filtered>&, typename MeshTypes<Filtered>::V, const Filtered::Point_3&);
template SnapReport<Float> snap_vertices<Float>(Mesh<Float>&, const std::vector<Polyline<Float>>&, double);
template SnapReport<Float> snap_vertices_to_segments<Float>(Mesh<Float>&, const std::vector<Polyline<Float>>&, double);
template bool move_keeps_faces<Float>(const Mesh<Float>&, typename MeshTypes<Float>::V, const Float::Point_3&);

}  // namespace seam::internal
