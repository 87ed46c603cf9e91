// seam: better triangles next to the shared curves of a pair. See seam/internal/improve.h.
// SPDX-License-Identifier: GPL-3.0-or-later
#include <seam/internal/improve.h>

#include <CGAL/Polygon_mesh_processing/remesh.h>
#include <CGAL/boost/graph/Euler_operations.h>

#include <cmath>
#include <cstdint>
#include <set>

namespace seam::internal {

template <class K>
std::vector<std::vector<std::size_t>> choose_curve_points(const std::vector<Polyline<K>>& curves, double spacing) {
  std::vector<std::vector<std::size_t>> kept(curves.size());
  for (std::size_t c = 0; c < curves.size(); ++c) {
    const auto& pts = curves[c];
    const bool closed = is_closed(pts);
    const std::size_t n = closed ? pts.size() - 1 : pts.size();
    auto dist = [&](std::size_t i, std::size_t j) {
      return std::sqrt(CGAL::to_double(CGAL::squared_distance(to_filtered(pts[i]), to_filtered(pts[j]))));
    };
    std::vector<std::size_t>& k = kept[c];
    k.push_back(0);
    for (std::size_t i = 1; i < n; ++i) {
      // Keep i when skipping it would make the chord from the last kept point too long.
      const std::size_t next = (i + 1) % pts.size();
      const bool last_open = !closed && i + 1 == n;
      if (last_open || dist(k.back(), next >= n ? 0 : next) > 1.2 * spacing || dist(k.back(), i) >= spacing) k.push_back(i);
    }
    // A closed curve needs a closing chord that is not too short, and at least three points.
    if (closed && k.size() > 3 && dist(k.back(), 0) < 0.5 * spacing) k.pop_back();
    if (closed && k.size() < 3) {
      k.clear();
      for (std::size_t i = 0; i < n; ++i) k.push_back(i);
    }
  }
  return kept;
}

template <class K>
bool coarsen_and_remesh_near_curves(Mesh<K>& mesh, std::vector<std::vector<typename MeshTypes<K>::V>>& curve_vertices,
                                    const std::vector<std::vector<std::size_t>>& kept, double target_edge_length,
                                    std::vector<std::vector<std::size_t>>& refused) {
  using M = Mesh<K>;
  using V = typename M::Vertex_index;
  using E = typename M::Edge_index;
  using F = typename M::Face_index;
  M work = mesh;
  auto curve_id = work.template add_property_map<V, std::int64_t>("v:seam_curve_point", -1).first;

  // 1. Collapse the dropped curve vertices onto the kept ones, along the curve.
  std::vector<std::vector<V>> coarse(curve_vertices.size());
  refused.assign(curve_vertices.size(), {});
  for (std::size_t c = 0; c < curve_vertices.size(); ++c) {
    const auto& vs = curve_vertices[c];
    const bool closed = vs.size() > 2 && vs.front() == vs.back();
    const std::size_t n = closed ? vs.size() - 1 : vs.size();
    std::vector<char> keep(n, 0);
    for (std::size_t i : kept[c]) keep[i] = 1;
    // handle[i]: the vertex now standing for curve position i (a collapse may keep either end).
    std::vector<V> handle(vs.begin(), vs.begin() + n);
    std::size_t last = 0;
    for (std::size_t i = 1; i < n; ++i) {
      if (keep[i]) {
        last = i;
        continue;
      }
      // Collapse position i into the last kept position (their edge exists: earlier collapses
      // merged the points in between into it).
      const auto h = work.halfedge(handle[i], handle[last]);
      if (h == M::null_halfedge() || !CGAL::Euler::does_satisfy_link_condition(work.edge(h), work)) {
        // This point cannot go without breaking the surface: it stays, in both meshes.
        refused[c].push_back(i);
        last = i;
        continue;
      }
      const auto point = work.point(handle[last]);
      const V r = CGAL::Euler::collapse_edge(work.edge(h), work);
      work.point(r) = point;
      handle[last] = r;
    }
    for (std::size_t i = 0; i < n; ++i)
      if (keep[i] || std::find(refused[c].begin(), refused[c].end(), i) != refused[c].end()) coarse[c].push_back(handle[i]);
    if (closed) coarse[c].push_back(coarse[c].front());
  }
  for (const auto& r : refused)
    if (!r.empty()) return false;  // the caller keeps these points too and tries again

  // 2. Mark the curve: vertices fixed, edges constrained.
  auto vfixed = work.template add_property_map<V, bool>("v:seam_fixed", false).first;
  auto econs = work.template add_property_map<E, bool>("e:seam_constrained", false).first;
  std::set<F> band;
  for (std::size_t c = 0; c < coarse.size(); ++c)
    for (std::size_t i = 0; i < coarse[c].size(); ++i) {
      const V v = coarse[c][i];
      vfixed[v] = true;
      if (curve_id[v] < 0) curve_id[v] = std::int64_t((c << 32) | i);  // a closing repeat keeps the first id
      if (i + 1 < coarse[c].size()) {
        const auto h = work.halfedge(v, coarse[c][i + 1]);
        if (h == M::null_halfedge()) return false;  // the coarse curve is not made of edges
        econs[work.edge(h)] = true;
      }
      for (F f : CGAL::faces_around_target(work.halfedge(v), work))
        if (f != M::null_face()) band.insert(f);
    }
  // Two rings of faces around the curve.
  {
    std::set<V> ring;
    for (F f : band)
      for (V v : CGAL::vertices_around_face(work.halfedge(f), work)) ring.insert(v);
    for (V v : ring)
      for (F f : CGAL::faces_around_target(work.halfedge(v), work))
        if (f != M::null_face()) band.insert(f);
  }

  // 3. Remesh the band on double coordinates; points not moved keep their exact coordinates.
  using DK = CGAL::Exact_predicates_inexact_constructions_kernel;
  CGAL::Surface_mesh<DK::Point_3> dmesh;
  work.collect_garbage();
  // after garbage collection the properties moved with their vertices and faces
  auto vfixed2 = work.template property_map<V, bool>("v:seam_fixed").first;
  auto econs2 = work.template property_map<E, bool>("e:seam_constrained").first;
  auto curve_id2 = work.template property_map<V, std::int64_t>("v:seam_curve_point").first;
  std::vector<char> in_band_face(work.number_of_faces(), 0);
  {
    // recompute the band after garbage collection: faces with a vertex within one ring of the curve
    std::set<V> near;
    for (V v : work.vertices())
      if (vfixed2[v]) {
        near.insert(v);
        for (V w : CGAL::vertices_around_target(work.halfedge(v), work)) near.insert(w);
      }
    for (F f : work.faces())
      for (V v : CGAL::vertices_around_face(work.halfedge(f), work))
        if (near.count(v)) in_band_face[std::size_t(f)] = 1;
  }
  for (V v : work.vertices()) dmesh.add_vertex(to_filtered(work.point(v)));
  for (F f : work.faces()) {
    std::vector<typename CGAL::Surface_mesh<DK::Point_3>::Vertex_index> vs;
    for (V v : CGAL::vertices_around_face(work.halfedge(f), work)) vs.emplace_back(std::uint32_t(std::size_t(v)));
    if (dmesh.add_face(vs) == CGAL::Surface_mesh<DK::Point_3>::null_face()) return false;
  }
  using DV = CGAL::Surface_mesh<DK::Point_3>::Vertex_index;
  using DE = CGAL::Surface_mesh<DK::Point_3>::Edge_index;
  using DF = CGAL::Surface_mesh<DK::Point_3>::Face_index;
  auto d_fixed = dmesh.add_property_map<DV, bool>("v:fixed", false).first;
  auto d_cons = dmesh.add_property_map<DE, bool>("e:constrained", false).first;
  auto d_orig = dmesh.add_property_map<DV, std::int64_t>("v:orig", -1).first;
  for (V v : work.vertices()) {
    d_fixed[DV(std::uint32_t(std::size_t(v)))] = vfixed2[v];
    d_orig[DV(std::uint32_t(std::size_t(v)))] = std::int64_t(std::size_t(v));
  }
  for (E e : work.edges()) {
    if (!econs2[e]) continue;
    const auto h = work.halfedge(e);
    const auto dh = dmesh.halfedge(DV(std::uint32_t(std::size_t(work.source(h)))), DV(std::uint32_t(std::size_t(work.target(h)))));
    d_cons[dmesh.edge(dh)] = true;
  }
  std::vector<DF> band_faces;
  for (F f : work.faces())
    if (in_band_face[std::size_t(f)]) band_faces.push_back(DF(std::uint32_t(std::size_t(f))));
  namespace PMP = CGAL::Polygon_mesh_processing;
  PMP::isotropic_remeshing(band_faces, target_edge_length, dmesh,
                           CGAL::parameters::number_of_iterations(3)
                               .edge_is_constrained_map(d_cons)
                               .vertex_is_constrained_map(d_fixed)
                               .collapse_constraints(false));
  dmesh.collect_garbage();
  auto d_orig2 = dmesh.property_map<DV, std::int64_t>("v:orig").first;

  // 4. Back to the kernel: an original vertex that did not move keeps its exact coordinates.
  M out;
  std::vector<V> map(dmesh.number_of_vertices());
  for (DV dv : dmesh.vertices()) {
    const std::int64_t o = d_orig2[dv];
    typename K::Point_3 p(dmesh.point(dv).x(), dmesh.point(dv).y(), dmesh.point(dv).z());
    if (o >= 0 && to_filtered(work.point(V(std::uint32_t(o)))) == dmesh.point(dv)) p = work.point(V(std::uint32_t(o)));
    map[std::size_t(dv)] = out.add_vertex(p);
  }
  auto source = out.template add_property_map<F, std::uint32_t>(source_face_property, 0).first;
  auto is_new = out.template add_property_map<F, bool>(new_face_property, false).first;
  const auto [old_source, has_source] = work.template property_map<F, std::uint32_t>(source_face_property);
  const auto [old_new, has_new] = work.template property_map<F, bool>(new_face_property);
  // Faces outside the band are unchanged (same vertex triples): carry their provenance.
  std::map<std::array<std::int64_t, 3>, F> old_faces;
  for (F f : work.faces()) {
    std::array<std::int64_t, 3> key;
    int i = 0;
    for (V v : CGAL::vertices_around_face(work.halfedge(f), work)) key[i++] = std::int64_t(std::size_t(v));
    std::rotate(key.begin(), std::min_element(key.begin(), key.end()), key.end());
    old_faces[key] = f;
  }
  for (DF df : dmesh.faces()) {
    std::vector<V> vs;
    std::array<std::int64_t, 3> key;
    int i = 0;
    for (DV dv : CGAL::vertices_around_face(dmesh.halfedge(df), dmesh)) {
      vs.push_back(map[std::size_t(dv)]);
      key[i++] = d_orig2[dv];
    }
    const F nf = out.add_face(vs);
    if (nf == M::null_face()) return false;
    std::rotate(key.begin(), std::min_element(key.begin(), key.end()), key.end());
    auto it = old_faces.find(key);
    if (it != old_faces.end() && std::find(key.begin(), key.end(), -1) == key.end()) {
      source[nf] = has_source ? old_source[it->second] : std::uint32_t(std::size_t(it->second));
      is_new[nf] = has_new && old_new[it->second];
    } else {
      source[nf] = std::numeric_limits<std::uint32_t>::max();  // remeshed: no single input face
      is_new[nf] = true;
    }
  }
  // The curves, as vertices of the output.
  std::map<std::int64_t, V> by_curve_id;
  for (DV dv : dmesh.vertices()) {
    const std::int64_t o = d_orig2[dv];
    if (o >= 0 && curve_id2[V(std::uint32_t(o))] >= 0) by_curve_id[curve_id2[V(std::uint32_t(o))]] = map[std::size_t(dv)];
  }
  std::vector<std::vector<V>> result(coarse.size());
  for (std::size_t c = 0; c < coarse.size(); ++c)
    for (std::size_t i = 0; i < coarse[c].size(); ++i) {
      const bool closing = i + 1 == coarse[c].size() && i > 0 && coarse[c][i] == coarse[c].front();
      auto it = by_curve_id.find(std::int64_t((c << 32) | (closing ? 0 : i)));
      if (it == by_curve_id.end()) return false;
      result[c].push_back(it->second);
    }
  mesh = std::move(out);
  curve_vertices = std::move(result);
  return true;
}

#define SEAM_INSTANTIATE(K)                                                                                          \
  template std::vector<std::vector<std::size_t>> choose_curve_points<K>(const std::vector<Polyline<K>>&, double);   \
  template bool coarsen_and_remesh_near_curves<K>(Mesh<K>&, std::vector<std::vector<typename MeshTypes<K>::V>>&,   \
                                                  const std::vector<std::vector<std::size_t>>&, double,            \
                                                  std::vector<std::vector<std::size_t>>&);
SEAM_INSTANTIATE(Exact)
SEAM_INSTANTIATE(Filtered)
SEAM_INSTANTIATE(Float)
#undef SEAM_INSTANTIATE

}  // namespace seam::internal
