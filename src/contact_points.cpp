// seam: isolated points of contact made vertices. See seam/internal/contact_points.h.
// SPDX-License-Identifier: GPL-3.0-or-later
#include <seam/internal/contact_points.h>
#include <seam/internal/triangle_predicates.h>

#include <CGAL/boost/graph/Euler_operations.h>

#include <cstdint>
#include <optional>

namespace seam::internal {

namespace {

/// The insertion into one mesh, which is not given back: empty when a point lies on no face (the points
/// before it are inserted then).
template <class K>
std::vector<typename MeshTypes<K>::V> insert_points_in_place(Mesh<K>& mesh, const std::vector<typename K::Point_3>& points) {
  using T = MeshTypes<K>;
  using V = typename T::V;
  using H = typename T::H;
  using F = typename T::F;
  auto source = mesh.template property_map<F, std::uint32_t>(source_face_property);
  auto is_new = mesh.template property_map<F, bool>(new_face_property);
  std::vector<V> result;
  for (const auto& p : points) {
    const CGAL::Bbox_3 box = p.bbox();
    std::optional<V> found;
    for (F f : mesh.faces()) {
      const H h0 = mesh.halfedge(f);
      std::array<H, 3> hs = {h0, mesh.next(h0), mesh.next(mesh.next(h0))};
      CGAL::Bbox_3 fb;
      for (H h : hs) fb += mesh.point(mesh.target(h)).bbox();
      if (!CGAL::do_overlap(fb, box)) continue;
      const auto &a = mesh.point(mesh.source(hs[0])), &b = mesh.point(mesh.target(hs[0])),
                 &c = mesh.point(mesh.target(hs[1]));
      if (!on_triangle<K>(a, b, c, p)) continue;
      for (H h : hs)
        if (mesh.point(mesh.target(h)) == p) found = mesh.target(h);
      if (found) break;
      const std::uint32_t s = source.second ? source.first[f] : std::uint32_t(std::size_t(f));
      // On an edge: split it, then both faces on it (in their planes).
      std::optional<H> on_edge;
      for (H h : hs)
        if (CGAL::collinear(mesh.point(mesh.source(h)), mesh.point(mesh.target(h)), p)) on_edge = h;
      std::vector<std::pair<F, std::uint32_t>> sides;
      V v;
      if (on_edge) {
        const H h = *on_edge, o = mesh.opposite(h);
        const F g = mesh.face(o);
        const std::uint32_t sg = g == Mesh<K>::null_face() ? 0 : source.second ? source.first[g] : std::uint32_t(std::size_t(g));
        const H hv = CGAL::Euler::split_edge(h, mesh);  // target(hv) is the new vertex
        v = mesh.target(hv);
        mesh.point(v) = p;
        // Each face around v that is a quad: split it from v to its far corner.
        std::vector<H> quads;
        for (H x : CGAL::halfedges_around_target(hv, mesh))
          if (!mesh.is_border(x) && CGAL::halfedges_around_face(x, mesh).size() == 4) quads.push_back(x);
        for (H x : quads) {
          const std::uint32_t sx = mesh.face(x) == f ? s : sg;
          const H y = CGAL::Euler::split_face(x, mesh.next(mesh.next(x)), mesh);
          sides.emplace_back(mesh.face(y), sx);
          sides.emplace_back(mesh.face(mesh.opposite(y)), sx);
        }
      } else {
        const H hv = CGAL::Euler::add_center_vertex(h0, mesh);
        v = mesh.target(hv);
        mesh.point(v) = p;
        for (H x : CGAL::halfedges_around_target(hv, mesh)) sides.emplace_back(mesh.face(x), s);
      }
      for (const auto& [g, sx] : sides) {
        if (g == Mesh<K>::null_face()) continue;
        if (source.second) source.first[g] = sx;
        if (is_new.second) is_new.first[g] = true;
      }
      found = v;
      break;
    }
    if (!found) return {};
    result.push_back(*found);
  }
  return result;
}

}  // namespace

template <class K>
bool insert_points(Mesh<K>& a, Mesh<K>& b, const std::vector<typename K::Point_3>& points,
                   std::vector<typename MeshTypes<K>::V>& in_a, std::vector<typename MeshTypes<K>::V>& in_b) {
  if (points.empty()) return true;
  Mesh<K> a_before = a, b_before = b;
  in_a = insert_points_in_place<K>(a, points);
  in_b = in_a.empty() ? in_a : insert_points_in_place<K>(b, points);
  if (in_a.size() == points.size() && in_b.size() == points.size()) return true;
  a = std::move(a_before);
  b = std::move(b_before);
  in_a.clear();
  in_b.clear();
  return false;
}

#define SEAM_INSTANTIATE(K)                                                                               \
  template bool insert_points<K>(Mesh<K>&, Mesh<K>&, const std::vector<K::Point_3>&, std::vector<MeshTypes<K>::V>&, \
                                 std::vector<MeshTypes<K>::V>&);
SEAM_INSTANTIATE(Exact)
SEAM_INSTANTIATE(Filtered)
SEAM_INSTANTIATE(Float)
#undef SEAM_INSTANTIATE

}  // namespace seam::internal
