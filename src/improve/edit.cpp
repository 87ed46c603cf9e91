// seam: edits of the quality stage. Every edit replaces a disk of faces by the fan from one point
// over the disk's border: a flip (the fan from a corner of two faces), an insertion in a face or
// on an edge (from the new point), a merge of a vertex into a neighbour (the neighbour's fan over
// the vertex's star), a move of a vertex onto a curve segment (the new curve point's fan over
// the vertex's star and the face beyond the segment).
// SPDX-License-Identifier: GPL-3.0-or-later

#include <seam/errors.h>
#include <seam/internal/improve_state.h>

#include <CGAL/boost/graph/Euler_operations.h>

#include <algorithm>
#include <map>

namespace seam::internal {

namespace {

template <class F> bool contains(const std::vector<F>& faces, F f) {
  return std::find(faces.begin(), faces.end(), f) != faces.end();
}

}  // namespace

template <class K>
bool make_fan(const ImproveState<K>& s, std::size_t m, const std::vector<typename Mesh<K>::Face_index>& region,
              const EditCorner<K>& apex, EditPart<K>& part,
              std::pair<typename Mesh<K>::Vertex_index, typename Mesh<K>::Vertex_index> split) {
  using M = Mesh<K>;
  using V = typename M::Vertex_index;
  using H = typename M::Halfedge_index;
  const M& g = s.mesh(m);
  // The border of the region: halfedges of its faces whose opposite face is not in it.
  std::map<V, H> border_from;  // by source vertex
  std::size_t interior_halfedges = 0;
  for (auto f : region)
    for (H h : CGAL::halfedges_around_face(g.halfedge(f), g)) {
      const auto across = g.face(g.opposite(h));
      if (across != M::null_face() && contains(region, across)) {
        ++interior_halfedges;
        continue;
      }
      if (!border_from.emplace(g.source(h), h).second) return false;  // the border touches itself
    }
  if (border_from.size() < 3) return false;
  // One cycle through every border halfedge.
  std::vector<H> cycle;
  H h = border_from.begin()->second;
  do {
    cycle.push_back(h);
    const auto it = border_from.find(g.target(h));
    if (it == border_from.end() || cycle.size() > border_from.size()) return false;
    h = it->second;
  } while (h != cycle.front());
  if (cycle.size() != border_from.size()) return false;
  // A disk: V - E + F = 1, with the border's vertices and the interior ones.
  std::vector<V> vertices;
  for (auto f : region)
    for (V v : CGAL::vertices_around_face(g.halfedge(f), g))
      if (std::find(vertices.begin(), vertices.end(), v) == vertices.end()) vertices.push_back(v);
  const long edges = long(cycle.size()) + long(interior_halfedges / 2);
  if (long(vertices.size()) - edges + long(region.size()) != 1) return false;
  // Every border vertex keeps a face outside the region (else removing the region removes it).
  for (H b : cycle) {
    bool outside = false;
    for (auto f : CGAL::faces_around_target(b, g))
      if (f != M::null_face() && !contains(region, f)) outside = true;
    if (!outside) return false;
  }
  if (!apex.fresh) {
    std::size_t at = cycle.size();
    for (std::size_t i = 0; i < cycle.size(); ++i)
      if (g.source(cycle[i]) == apex.v) at = i;
    if (at == cycle.size()) return false;
    // The fan's new edges (to the border vertices not next to the apex) must not exist, except
    // inside the region (they go with it).
    const V after = g.target(cycle[at]), before = g.source(cycle[(at + cycle.size() - 1) % cycle.size()]);
    for (H b : cycle) {
      const V y = g.source(b);
      if (y == apex.v || y == after || y == before) continue;
      const H e = g.halfedge(apex.v, y);
      if (e == M::null_halfedge()) continue;
      const auto f0 = g.face(e), f1 = g.face(g.opposite(e));
      if (f0 == M::null_face() || f1 == M::null_face() || !contains(region, f0) || !contains(region, f1)) return false;
    }
  }
  part.mesh = m;
  part.removed = region;
  part.added.clear();
  part.origin.clear();
  for (H b : cycle) {
    const V s0 = g.source(b), t0 = g.target(b);
    if (!apex.fresh && (s0 == apex.v || t0 == apex.v)) continue;
    if ((s0 == split.first && t0 == split.second) || (s0 == split.second && t0 == split.first)) continue;
    part.added.push_back({apex, EditCorner<K>{s0, false, g.point(s0)}, EditCorner<K>{t0, false, g.point(t0)}});
    part.origin.push_back(g.face(b));
  }
  return !part.added.empty();
}

template <class K> void split_curve_links(ImproveState<K>& s, int a, int b, int x) {
  std::vector<int> starts;  // nodes whose segment to the next node is (a, b)
  for (const int n : s.points[std::size_t(a)].nodes) {
    const auto& node = s.nodes[std::size_t(n)];
    if (node.next >= 0 && s.nodes[std::size_t(node.next)].point == b) starts.push_back(n);
    if (node.prev >= 0 && s.nodes[std::size_t(node.prev)].point == b) starts.push_back(node.prev);
  }
  std::sort(starts.begin(), starts.end());
  starts.erase(std::unique(starts.begin(), starts.end()), starts.end());
  if (starts.empty()) throw InternalError("improve: a split of a segment that is not a curve segment");
  s.segment_node.erase({std::min(a, b), std::max(a, b)});
  for (const int start : starts) {
    const int end = s.nodes[std::size_t(start)].next, p = s.nodes[std::size_t(start)].point, q = s.nodes[std::size_t(end)].point;
    const int node = int(s.nodes.size());
    s.nodes.push_back({x, start, end, s.nodes[std::size_t(start)].curve});
    s.points[std::size_t(x)].nodes.push_back(node);
    s.nodes[std::size_t(start)].next = node;
    s.nodes[std::size_t(end)].prev = node;
    s.segment_node[{std::min(p, x), std::max(p, x)}] = start;
    s.segment_node[{std::min(x, q), std::max(x, q)}] = node;
  }
}

namespace {

/// The links along the curves after point u merges into point w: a position of u next to one of
/// w goes (the segment (u, w) with it); any other becomes w's (the curves pass through w there).
template <class K> void link_merge(ImproveState<K>& s, int u, int w) {
  auto key = [](int a, int b) { return std::make_pair(std::min(a, b), std::max(a, b)); };
  const std::vector<int> of_u = s.points[std::size_t(u)].nodes;
  for (const int n : of_u) {
    auto& node = s.nodes[std::size_t(n)];
    const int before = node.prev, after = node.next;
    const int pb = before >= 0 ? s.nodes[std::size_t(before)].point : -1, pa = after >= 0 ? s.nodes[std::size_t(after)].point : -1;
    if (before >= 0) s.segment_node.erase(key(pb, u));
    if (after >= 0) s.segment_node.erase(key(u, pa));
    if (pb == w || pa == w) {  // along the segment (u, w): the position goes
      if (before >= 0) s.nodes[std::size_t(before)].next = after;
      if (after >= 0) s.nodes[std::size_t(after)].prev = before;
      if (before >= 0 && after >= 0 && pb != pa) s.segment_node[key(pb, pa)] = before;
      auto& curve = s.curves[std::size_t(node.curve)];
      if (curve.first == n) curve.first = after >= 0 ? after : before;
      node.prev = node.next = -1;
    } else {  // elsewhere: the position becomes w's
      node.point = w;
      s.points[std::size_t(w)].nodes.push_back(n);
      if (before >= 0) s.segment_node[key(pb, w)] = before;
      if (after >= 0) s.segment_node[key(w, pa)] = n;
    }
  }
  s.points[std::size_t(u)].nodes.clear();
  s.points[std::size_t(u)].removed = true;
}

}  // namespace

template <class K> Applied<K> apply_edit(ImproveState<K>& s, const Edit<K>& edit) {
  using M = Mesh<K>;
  using V = typename M::Vertex_index;
  using F = typename M::Face_index;
  Applied<K> made;
  const FaceGrid::Liveness is_live = [&s](const FaceGrid::Entry& e) { return s.is_live(e); };
  int fresh_id = -1;
  if (edit.has_fresh && edit.fresh_curve_point) {
    fresh_id = int(s.points.size());
    s.points.push_back({edit.fresh_point, std::vector<V>(s.meshes.size(), M::null_vertex()), false, {}});
  }
  for (const auto& part : edit.parts) {
    auto& ms = s.meshes[part.mesh];
    M& g = *ms.mesh;
    std::vector<std::uint32_t> origin;  // the source face of each new face's origin
    for (F f : part.origin) origin.push_back(ms.source[f]);
    if (edit.merged_point >= 0) {
      const V gone = s.points[std::size_t(edit.merged_point)].vertex[part.mesh];
      if (gone != M::null_vertex()) ms.point[gone] = -1;
    }
    for (F f : part.removed) CGAL::Euler::remove_face(g.halfedge(f), g);
    V fresh = M::null_vertex();
    for (std::size_t i = 0; i < part.added.size(); ++i) {
      std::array<V, 3> vs;
      for (int k = 0; k < 3; ++k) {
        const auto& c = part.added[i][std::size_t(k)];
        if (c.fresh) {
          if (fresh == M::null_vertex()) {
            fresh = g.add_vertex(edit.fresh_point);
            ms.point[fresh] = fresh_id;
            ms.made[fresh] = true;
            if (fresh_id >= 0) s.points[std::size_t(fresh_id)].vertex[part.mesh] = fresh;
          }
          vs[std::size_t(k)] = fresh;
        } else {
          vs[std::size_t(k)] = c.v;
        }
      }
      const F f = g.add_face(vs[0], vs[1], vs[2]);
      if (f == M::null_face()) throw InternalError("improve: an edit made the mesh non-manifold");
      ms.band[f] = true;  // every face the stage makes is held to the bound
      ms.source[f] = origin[i];
      ms.is_new[f] = true;
      ms.cause[f] = 0;
      ms.version[f] = ++s.last_version;  // (Surface_mesh resets a recycled face's properties)
      s.grid.insert({std::uint32_t(part.mesh), std::uint32_t(std::size_t(f)), ms.version[f]}, s.face_box(part.mesh, f),
                    &is_live);
      made.faces.emplace_back(part.mesh, f);
    }
    made.fresh.push_back(fresh);
  }
  if (fresh_id >= 0 && edit.split_a >= 0) split_curve_links(s, edit.split_a, edit.split_b, fresh_id);
  if (edit.merged_point >= 0) {
    link_merge(s, edit.merged_point, edit.merged_into);
    for (auto& v : s.points[std::size_t(edit.merged_point)].vertex) v = M::null_vertex();
  }
  return made;
}

#define SEAM_INSTANTIATE(K)                                                                                         \
  template bool make_fan<K>(const ImproveState<K>&, std::size_t, const std::vector<Mesh<K>::Face_index>&,          \
                            const EditCorner<K>&, EditPart<K>&, std::pair<Mesh<K>::Vertex_index, Mesh<K>::Vertex_index>);                                                    \
  template Applied<K> apply_edit<K>(ImproveState<K>&, const Edit<K>&);                                            \
  template void split_curve_links<K>(ImproveState<K>&, int, int, int);
SEAM_INSTANTIATE(Exact)
SEAM_INSTANTIATE(Filtered)
SEAM_INSTANTIATE(Float)
#undef SEAM_INSTANTIATE

}  // namespace seam::internal
