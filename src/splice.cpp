// seam, pipeline step 6: splicing. See seam/internal/splice.h.
// SPDX-License-Identifier: GPL-3.0-or-later
#include <seam/internal/splice.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <unordered_map>
#include <vector>
#include <sstream>

namespace seam::internal {

/// Adds oriented triangles to a mesh that has its vertices and no face yet, face i = triangles[i],
/// in time linear in their number. Surface_mesh::add_face looks for an existing halfedge by
/// walking around a vertex, so a vertex of degree d costs O(d^2): a curve zig-zagging 100,000
/// times through one face gives a corner such a fan. Returns triangles.size() on success, else
/// the index of the first triangle that makes the surface non-manifold (nothing is then usable).
template <class K> std::size_t add_triangles(Mesh<K>& m, const std::vector<std::array<typename MeshTypes<K>::V, 3>>& triangles) {
  using V = typename MeshTypes<K>::V;
  using H = typename MeshTypes<K>::H;
  using F = typename MeshTypes<K>::F;
  const std::size_t nv = m.number_of_vertices();
  std::unordered_map<std::uint64_t, H> edge;  // key min * nv + max -> halfedge min -> max
  edge.reserve(3 * triangles.size() / 2 + 1);
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    const auto& tri = triangles[t];
    std::array<H, 3> h;
    for (int k = 0; k < 3; ++k) {
      const V u = tri[k], v = tri[(k + 1) % 3];
      if (u == v || std::size_t(u) >= nv || std::size_t(v) >= nv) return t;
      const V lo = std::min(u, v), hi = std::max(u, v);
      const std::uint64_t key = std::uint64_t(std::size_t(lo)) * nv + std::size_t(hi);
      auto found = edge.find(key);
      if (found == edge.end()) {
        found = edge.emplace(key, m.add_edge(lo, hi)).first;  // halfedge lo -> hi (target hi)
        m.set_face(found->second, m.null_face());
        m.set_face(m.opposite(found->second), m.null_face());
      }
      h[k] = m.target(found->second) == v ? found->second : m.opposite(found->second);
      if (m.face(h[k]) != m.null_face()) return t;  // the edge already has a face on this side
    }
    const F f = m.add_face();
    for (int k = 0; k < 3; ++k) {
      m.set_face(h[k], f);
      m.set_next(h[k], h[(k + 1) % 3]);
      m.set_halfedge(tri[(k + 1) % 3], h[k]);
    }
    m.set_halfedge(f, h[2]);  // as Surface_mesh::add_face: the face starts at tri[0]
  }
  // Border halfedges: each follows the border halfedge leaving its target; a vertex on the
  // border points to its incoming border halfedge (Surface_mesh's convention).
  std::vector<H> border_out(nv, H()), border_in(nv, H());
  for (auto e : m.edges())
    for (int i = 0; i < 2; ++i) {
      const H b = m.halfedge(e, i);
      if (m.face(b) != m.null_face()) continue;
      const std::size_t s = std::size_t(m.source(b)), d = std::size_t(m.target(b));
      if (border_out[s] != H() || border_in[d] != H()) return triangles.size() - 1;  // non-manifold vertex
      border_out[s] = b;
      border_in[d] = b;
    }
  for (std::size_t v = 0; v < nv; ++v) {
    if (border_in[v] == H()) continue;
    m.set_next(border_in[v], border_out[v]);
    m.set_halfedge(V(static_cast<typename V::size_type>(v)), border_in[v]);
  }
  // Every vertex's faces must form one fan: the halfedges around it are all its incoming ones.
  std::vector<std::size_t> incoming(nv, 0);
  for (auto h : m.halfedges()) ++incoming[std::size_t(m.target(h))];
  for (auto v : m.vertices()) {
    if (m.halfedge(v) == m.null_halfedge()) continue;  // isolated
    std::size_t around = 0;
    for (auto h : CGAL::halfedges_around_target(m.halfedge(v), m)) {
      (void)h;
      if (++around > incoming[std::size_t(v)]) break;
    }
    if (around != incoming[std::size_t(v)]) return triangles.size() - 1;
  }
  return triangles.size();
}

template <class K>
Mesh<K> splice_patches(const Mesh<K>& mesh, const std::vector<typename K::Point_3>& new_points,
                       const std::map<typename MeshTypes<K>::F, FacePatch<K>>& patches) {
  using V = typename MeshTypes<K>::V;
  Mesh<K> out;
  std::size_t steiner_count = 0;
  for (const auto& [f, patch] : patches) steiner_count += patch.steiner_points.size();
  std::size_t new_faces = 0;
  for (const auto& [f, patch] : patches) new_faces += patch.triangles.size();
  const std::size_t nv = mesh.number_of_vertices() + new_points.size() + steiner_count;
  const std::size_t nf = mesh.number_of_faces() - patches.size() + new_faces;
  out.reserve(nv, 3 * nf / 2 + 3, nf);

  for (V v : mesh.vertices()) out.add_vertex(mesh.point(v));
  for (const auto& p : new_points) out.add_vertex(p);
  auto source = out.template add_property_map<typename Mesh<K>::Face_index, std::uint32_t>(source_face_property, 0).first;
  auto is_new = out.template add_property_map<typename Mesh<K>::Face_index, bool>(new_face_property, false).first;

  // The faces in output order, then built in one pass (see add_triangles).
  std::vector<std::array<V, 3>> triangles;
  std::vector<std::uint32_t> from;
  std::vector<char> added;
  triangles.reserve(nf);
  from.reserve(nf);
  added.reserve(nf);
  auto it = patches.begin();
  for (auto f : mesh.faces()) {
    if (it != patches.end() && it->first == f) {
      const FacePatch<K>& patch = it->second;
      const std::size_t base = out.number_of_vertices();
      for (const auto& p : patch.steiner_points) out.add_vertex(p);
      for (const auto& tri : patch.triangles) {
        std::array<V, 3> vs;
        for (int i = 0; i < 3; ++i)
          vs[i] = V(static_cast<typename V::size_type>(tri[i] >= 0 ? std::size_t(tri[i]) : base + std::size_t(-tri[i] - 1)));
        triangles.push_back(vs);
        from.push_back(std::uint32_t(std::size_t(f)));
        added.push_back(1);
      }
      ++it;
      continue;
    }
    std::array<V, 3> vs;
    int i = 0;
    for (V v : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) vs[i++] = v;
    triangles.push_back(vs);
    from.push_back(std::uint32_t(std::size_t(f)));
    added.push_back(0);
  }
  const std::size_t bad = add_triangles<K>(out, triangles);
  if (bad != triangles.size()) {
    std::ostringstream msg;
    msg << "splice: a new face from input face " << from[bad] << " does not fit into the mesh";
    throw InternalError(msg.str());
  }
  for (std::size_t i = 0; i < triangles.size(); ++i) {
    const typename Mesh<K>::Face_index f(static_cast<typename V::size_type>(i));
    source[f] = from[i];
    is_new[f] = added[i] != 0;
  }
  return out;
}

template std::size_t add_triangles<Exact>(Mesh<Exact>&, const std::vector<std::array<MeshTypes<Exact>::V, 3>>&);
template std::size_t add_triangles<Filtered>(Mesh<Filtered>&, const std::vector<std::array<MeshTypes<Filtered>::V, 3>>&);
template std::size_t add_triangles<Float>(Mesh<Float>&, const std::vector<std::array<MeshTypes<Float>::V, 3>>&);
template Mesh<Exact> splice_patches<Exact>(const Mesh<Exact>&, const std::vector<Exact::Point_3>&,
                                           const std::map<MeshTypes<Exact>::F, FacePatch<Exact>>&);
template Mesh<Filtered> splice_patches<Filtered>(const Mesh<Filtered>&, const std::vector<Filtered::Point_3>&,
                                                 const std::map<MeshTypes<Filtered>::F, FacePatch<Filtered>>&);
template Mesh<Float> splice_patches<Float>(const Mesh<Float>&, const std::vector<Float::Point_3>&,
                                           const std::map<MeshTypes<Float>::F, FacePatch<Float>>&);

}  // namespace seam::internal
