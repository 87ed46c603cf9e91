// seam: better triangles next to the shared curves of a pair. See seam/internal/improve.h.
// SPDX-License-Identifier: GPL-3.0-or-later
#include <seam/internal/collapse.h>
#include <seam/internal/improve.h>
#include <seam/internal/local_edits.h>
#include <seam/internal/remesh_band.h>
#include <seam/quality.h>

#include <CGAL/AABB_traits.h>
#include <CGAL/AABB_tree.h>
#include <CGAL/AABB_triangle_primitive.h>
#include <CGAL/boost/graph/Euler_operations.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <set>

namespace seam::internal {

template <class K>
std::vector<std::vector<std::size_t>> choose_curve_points(const std::vector<Polyline<K>>& curves, double spacing,
                                                          double max_chord_deviation) {
  std::vector<std::vector<std::size_t>> kept(curves.size());
  // A point at more than one curve position (where curves meet, or a curve passes twice) is one
  // vertex for all of them: it is kept (collapsing it for one position would remove it from the
  // others).
  auto less = [](const typename K::Point_3& x, const typename K::Point_3& y) {
    return CGAL::compare_xyz(x, y) == CGAL::SMALLER;
  };
  std::map<typename K::Point_3, int, decltype(less)> positions(less);
  for (const auto& pts : curves)
    for (std::size_t i = 0; i < (is_closed(pts) ? pts.size() - 1 : pts.size()); ++i) ++positions[pts[i]];
  for (std::size_t c = 0; c < curves.size(); ++c) {
    const auto& pts = curves[c];
    const bool closed = is_closed(pts);
    const std::size_t n = closed ? pts.size() - 1 : pts.size();
    auto dist = [&](std::size_t i, std::size_t j) {
      return std::sqrt(CGAL::to_double(CGAL::squared_distance(to_filtered(pts[i]), to_filtered(pts[j]))));
    };
    // The chord from point `from` to point `to` passes within max_chord_deviation of the points
    // between them (the coarsened curve stays that close to the surfaces).
    auto chord_close = [&](std::size_t from, std::size_t to) {
      if (max_chord_deviation <= 0) return true;
      const Filtered::Segment_3 chord(to_filtered(pts[from]), to_filtered(pts[to]));
      for (std::size_t j = (from + 1) % n; j != to; j = (j + 1) % n)
        if (CGAL::squared_distance(to_filtered(pts[j]), chord) > max_chord_deviation * max_chord_deviation) return false;
      return true;
    };
    std::vector<std::size_t>& k = kept[c];
    k.push_back(0);
    for (std::size_t i = 1; i < n; ++i) {
      // Keep i when skipping it would make the chord from the last kept point too long.
      const std::size_t next = (i + 1) % pts.size();
      const bool last_open = !closed && i + 1 == n;
      if (last_open || dist(k.back(), next >= n ? 0 : next) > 1.2 * spacing || dist(k.back(), i) >= spacing ||
          !chord_close(k.back(), next >= n ? 0 : next))
        k.push_back(i);
    }
    // A closed curve needs a closing chord that is not too short, and at least three points.
    if (closed && k.size() > 3 && dist(k.back(), 0) < 0.5 * spacing) k.pop_back();
    if (closed && k.size() < 3) {
      k.clear();
      for (std::size_t i = 0; i < n; ++i) k.push_back(i);
    }
    for (std::size_t i = 0; i < n; ++i)
      if (positions[pts[i]] > 1) k.push_back(i);
    std::sort(k.begin(), k.end());
    k.erase(std::unique(k.begin(), k.end()), k.end());
  }
  return kept;
}

template <class K>
bool coarsen_and_remesh_near_curves(Mesh<K>& mesh, std::vector<std::vector<typename MeshTypes<K>::V>>& curve_vertices,
                                    const std::vector<std::vector<std::size_t>>& kept,
                                    const std::vector<std::vector<char>>& frozen, double target_edge_length,
                                    std::vector<std::vector<std::size_t>>& refused) {
  using M = Mesh<K>;
  using V = typename M::Vertex_index;
  using E = typename M::Edge_index;
  using F = typename M::Face_index;
  M work = mesh;
  // Each vertex's index before the garbage collection of step 3 (the curves refer to those).
  auto index_before = work.template add_property_map<V, std::uint32_t>("v:seam_index_before").first;
  auto vfrozen = work.template add_property_map<V, bool>("v:seam_frozen", false).first;
  auto vfrozen_faces = work.template add_property_map<V, bool>("v:seam_frozen_faces", false).first;
  auto changed = work.template add_property_map<F, bool>("f:seam_changed", false).first;

  // Sharp edges (faces on either side more than 60 degrees apart, doubles: the crest of a
  // lenticular tow, say): the remeshing keeps them (step 2), so that no remeshed face cuts across
  // a crease of the surface. Found before step 1, whose collapses may fold the surface: a fold is
  // not a crease, the remeshing removes it.
  auto sharp = work.template add_property_map<E, bool>("e:seam_sharp", false).first;
  for (E e : work.edges()) {
    if (work.is_border(e)) continue;
    const auto h = work.halfedge(e);
    const auto normal = [&](typename M::Halfedge_index g) {
      const auto p = to_filtered(work.point(work.source(g))), q = to_filtered(work.point(work.target(g))),
                 r = to_filtered(work.point(work.target(work.next(g))));
      return CGAL::cross_product(q - p, r - p);
    };
    sharp[e] = more_apart_than(normal(h), normal(work.opposite(h)), std::cos(60.0 * M_PI / 180));
  }

  // Shared faces (a flat contact's common triangulation: internal/flat_contacts.h) are left as
  // they are, with their corners, so that both meshes keep them identical.
  const FrozenFaces<K> shared_faces(work);

  // 1. Collapse the dropped curve vertices onto the kept ones, along the curve.
  std::vector<std::vector<V>> coarse(curve_vertices.size());
  refused.assign(curve_vertices.size(), {});
  for (std::size_t c = 0; c < curve_vertices.size(); ++c) {
    const auto& vs = curve_vertices[c];
    const bool closed = vs.size() > 2 && vs.front() == vs.back();
    const std::size_t n = closed ? vs.size() - 1 : vs.size();
    std::vector<char> keep(n, 0);
    for (std::size_t i : kept[c]) keep[i] = 1;
    const bool any_frozen = c < frozen.size() && frozen[c].size() >= n;
    for (std::size_t i = 0; i < n && any_frozen; ++i)
      if (frozen[c][i]) {
        if (!keep[i]) return false;  // a frozen position must be kept
        vfrozen[vs[i]] = true;
        if (frozen[c][i] == 2) vfrozen_faces[vs[i]] = true;
      }
    // Positions at a shared face (a flat contact's common triangulation, the same in both
    // meshes) stay: a collapse there would change the shared faces.
    for (std::size_t i = 0; i < n; ++i)
      if (shared_faces.around(work, vs[i])) keep[i] = 1;
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
      // (A vertex removed by an earlier collapse, which the choice of kept points rules out,
      // would make the search for their edge circulate forever: refused instead.)
      const auto h = work.is_removed(handle[i]) || work.is_removed(handle[last])
                         ? M::null_halfedge()
                         : work.halfedge(handle[i], handle[last]);
      // No test of the geometry here: a collapse that folds the surface is undone by the
      // remeshing, or the caller's check finds the fold and freezes the curve there.
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
      for (F f : CGAL::faces_around_target(work.halfedge(r), work))  // (a shared face keeps its corners' points)
        if (f != M::null_face() && !shared_faces.face(f)) changed[f] = true;
    }
    for (std::size_t i = 0; i < n; ++i)
      if (keep[i] || std::find(refused[c].begin(), refused[c].end(), i) != refused[c].end()) coarse[c].push_back(handle[i]);
    if (closed) coarse[c].push_back(coarse[c].front());
  }
  for (const auto& r : refused)
    if (!r.empty()) return false;  // the caller keeps these points too and tries again

  for (const auto& vs : coarse)
    for (V v : vs)
      if (work.is_removed(v)) return false;  // see the choice of kept points

  // 2. Mark the curve: vertices fixed, edges constrained.
  auto vfixed = work.template add_property_map<V, bool>("v:seam_fixed", false).first;
  auto econs = work.template add_property_map<E, bool>("e:seam_constrained", false).first;
  for (std::size_t c = 0; c < coarse.size(); ++c)
    for (std::size_t i = 0; i < coarse[c].size(); ++i) {
      const V v = coarse[c][i];
      vfixed[v] = true;
      if (i + 1 < coarse[c].size()) {
        const auto h = work.halfedge(v, coarse[c][i + 1]);
        if (h == M::null_halfedge()) return false;  // the coarse curve is not made of edges
        econs[work.edge(h)] = true;
      }
    }

  // Sharp edges of the surface, as step 1 found them, are constrained too where step 1 left their
  // faces alone: the remeshing neither splits, collapses nor flips them, nor moves their ends.
  // (A collapse next to the border removes a face: an edge of it may be on the border now.)
  for (E e : work.edges())
    if (sharp[e] && !work.is_border(e)) {
      const auto h = work.halfedge(e);
      if (!changed[work.face(h)] && !changed[work.face(work.opposite(h))]) econs[e] = true;
    }

  // 3. Remesh the band on double coordinates; points not moved keep their exact coordinates.
  using DK = BandKernel;
  BandMesh dmesh;
  auto to_band = [](const Filtered::Point_3& p) { return DK::Point_3(p.x(), p.y(), p.z()); };
  for (V v : work.vertices()) index_before[v] = std::uint32_t(std::size_t(v));
  const std::size_t vertices_before = work.number_of_vertices() + work.number_of_removed_vertices();
  work.collect_garbage();
  // after garbage collection the properties moved with their vertices and faces
  auto vfixed2 = work.template property_map<V, bool>("v:seam_fixed").first;
  auto econs2 = work.template property_map<E, bool>("e:seam_constrained").first;
  auto index_before2 = work.template property_map<V, std::uint32_t>("v:seam_index_before").first;
  auto vfrozen2 = work.template property_map<V, bool>("v:seam_frozen").first;
  std::vector<char> in_band_face(work.number_of_faces(), 0);
  auto vfrozen_faces2 = work.template property_map<V, bool>("v:seam_frozen_faces").first;
  // Vertices within one ring of a frozen curve vertex: their faces stay as embedded (out of the
  // band); near_frozen_faces, those of curve vertices frozen with their faces: these faces are
  // frozen for the steps after the remeshing too (frozen_face_property).
  std::set<V> near_frozen, near_frozen_faces;
  {
    // recompute the band after garbage collection: faces with a vertex within one ring of a curve
    // vertex, and none within one ring of a frozen one
    std::set<V> near;
    auto insert_with_ring = [&](std::set<V>& set, V v) {
      set.insert(v);
      for (V w : CGAL::vertices_around_target(work.halfedge(v), work)) set.insert(w);
    };
    for (V v : work.vertices())
      if (vfixed2[v]) {
        insert_with_ring(vfrozen2[v] ? near_frozen : near, v);
        if (vfrozen_faces2[v]) insert_with_ring(near_frozen_faces, v);
      }
    for (F f : work.faces()) {
      bool is_near = false, is_frozen = false;
      for (V v : CGAL::vertices_around_face(work.halfedge(f), work)) {
        is_near = is_near || near.count(v);
        is_frozen = is_frozen || near_frozen.count(v);
      }
      in_band_face[std::size_t(f)] = is_near && !is_frozen;
    }
  }
  // (after the garbage collection: the property moved with its faces)
  const auto [shared2, has_shared] = work.template property_map<F, bool>(shared_face_property);
  if (has_shared)
    for (F f : work.faces())
      if (shared2[f]) in_band_face[std::size_t(f)] = 0;
  for (V v : work.vertices()) dmesh.add_vertex(to_band(to_filtered(work.point(v))));
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
  if (has_shared)  // shared faces' corners and edges stay as they are
    for (F f : work.faces())
      if (shared2[f])
        for (auto h : CGAL::halfedges_around_face(work.halfedge(f), work)) {
          vfixed2[work.target(h)] = true;
          econs2[work.edge(h)] = true;
        }
  for (V v : work.vertices()) d_fixed[DV(std::uint32_t(std::size_t(v)))] = vfixed2[v];
  for (E e : work.edges()) {
    if (!econs2[e]) continue;
    const auto h = work.halfedge(e);
    const auto dh = dmesh.halfedge(DV(std::uint32_t(std::size_t(work.source(h)))), DV(std::uint32_t(std::size_t(work.target(h)))));
    d_cons[dmesh.edge(dh)] = true;
  }
  // Faces that are flat or tiny once rounded to doubles (features of a few units in the last
  // place: CGAL's remeshing divides by their areas; edges below 1e-12 of the target length) stay
  // out, with the faces around them. (A larger bound, 1e-6, kept more faces out and left 2.4%
  // of the new faces below 10 degrees on the 72 test crossovers instead of 1.9%.)
  {
    std::vector<char> tiny_vertex(dmesh.number_of_vertices(), 0);
    const double min_length2 = CGAL::square(1e-12 * target_edge_length);
    for (DF f : dmesh.faces()) {
      const auto h = dmesh.halfedge(f);
      const auto &p = dmesh.point(dmesh.source(h)), &q = dmesh.point(dmesh.target(h)),
                 &r = dmesh.point(dmesh.target(dmesh.next(h)));
      const bool tiny = CGAL::collinear(p, q, r) || CGAL::squared_distance(p, q) < min_length2 ||
                        CGAL::squared_distance(q, r) < min_length2 || CGAL::squared_distance(r, p) < min_length2 ||
                        CGAL::cross_product(q - p, r - p).squared_length() < CGAL::square(min_length2);
      if (tiny)
        for (DV v : CGAL::vertices_around_face(h, dmesh)) tiny_vertex[std::size_t(v)] = 1;
    }
    for (DF f : dmesh.faces())
      for (DV v : CGAL::vertices_around_face(dmesh.halfedge(f), dmesh))
        for (DV w : CGAL::vertices_around_target(dmesh.halfedge(v), dmesh))
          if (tiny_vertex[std::size_t(w)]) in_band_face[std::size_t(f)] = 0;
  }
  std::vector<DF> band_faces;
  for (F f : work.faces())
    if (in_band_face[std::size_t(f)]) band_faces.push_back(DF(std::uint32_t(std::size_t(f))));
  if (band_faces.empty()) return false;
  // Long edges on the band's border stay as they are (see remesh_band.cpp). Raising the target
  // so that they are short enough was tried: on the benchmark's 77k/64k pair (long edges along
  // the tows) it left 26% of the new faces below 20 degrees instead of 10%.
  remesh_band(dmesh, band_faces, target_edge_length);
  dmesh.collect_garbage();
  auto d_orig2 = dmesh.property_map<DV, std::int64_t>("v:orig").first;

  // 4. Back to the kernel: an original vertex that did not move keeps its exact coordinates.
  M out;
  std::vector<V> map(dmesh.number_of_vertices());
  std::vector<char> moved(dmesh.number_of_vertices(), 1);
  for (DV dv : dmesh.vertices()) {
    const std::int64_t o = d_orig2[dv];
    typename K::Point_3 p(dmesh.point(dv).x(), dmesh.point(dv).y(), dmesh.point(dv).z());
    if (o >= 0 && to_band(to_filtered(work.point(V(std::uint32_t(o))))) == dmesh.point(dv)) {
      p = work.point(V(std::uint32_t(o)));
      moved[std::size_t(dv)] = 0;
    }
    map[std::size_t(dv)] = out.add_vertex(p);
  }
  auto source = out.template add_property_map<F, std::uint32_t>(source_face_property, 0).first;
  auto is_new = out.template add_property_map<F, bool>(new_face_property, false).first;
  std::optional<typename M::template Property_map<F, bool>> frozen_face;
  if (!near_frozen_faces.empty())
    frozen_face = out.template add_property_map<F, bool>(frozen_face_property, false).first;
  std::optional<typename M::template Property_map<F, bool>> shared_face;
  if (has_shared) shared_face = out.template add_property_map<F, bool>(shared_face_property, false).first;
  const auto [old_source, has_source] = work.template property_map<F, std::uint32_t>(source_face_property);
  const auto [old_new, has_new] = work.template property_map<F, bool>(new_face_property);
  // Faces outside the band are unchanged (same vertex triples, no corner moved, not reshaped by a
  // collapse of step 1): they carry their provenance.
  auto changed2 = work.template property_map<F, bool>("f:seam_changed").first;
  std::map<std::array<std::int64_t, 3>, F> old_faces;
  for (F f : work.faces()) {
    if (changed2[f]) continue;
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
    bool corner_moved = false, near_a_frozen_vertex = false;
    for (DV dv : CGAL::vertices_around_face(dmesh.halfedge(df), dmesh)) {
      vs.push_back(map[std::size_t(dv)]);
      key[i++] = d_orig2[dv];
      corner_moved = corner_moved || moved[std::size_t(dv)];
      near_a_frozen_vertex =
          near_a_frozen_vertex || (d_orig2[dv] >= 0 && near_frozen_faces.count(V(std::uint32_t(d_orig2[dv]))));
    }
    const F nf = out.add_face(vs);
    if (nf == M::null_face()) return false;
    if (frozen_face) (*frozen_face)[nf] = near_a_frozen_vertex;
    std::rotate(key.begin(), std::min_element(key.begin(), key.end()), key.end());
    auto it = old_faces.find(key);
    if (it != old_faces.end() && !corner_moved) {
      source[nf] = has_source ? old_source[it->second] : std::uint32_t(std::size_t(it->second));
      is_new[nf] = has_new && old_new[it->second];
      if (shared_face) (*shared_face)[nf] = shared2[it->second];
    } else {
      source[nf] = std::numeric_limits<std::uint32_t>::max();  // remeshed: no single input face
      is_new[nf] = true;
    }
  }
  // The curves, as vertices of the output: coarse[c][i] (an index before the garbage collection)
  // through the work mesh's vertex and the band mesh's to the output's. A vertex on two curves, or
  // twice on one (curves that touch), is found for each. (The remesher keeps fixed vertices.)
  std::vector<V> output_of_before(vertices_before, M::null_vertex());
  for (DV dv : dmesh.vertices()) {
    const std::int64_t o = d_orig2[dv];
    if (o >= 0) output_of_before[index_before2[V(std::uint32_t(o))]] = map[std::size_t(dv)];
  }
  std::vector<std::vector<V>> result(coarse.size());
  for (std::size_t c = 0; c < coarse.size(); ++c)
    for (V v : coarse[c]) {
      const V o = std::size_t(v) < output_of_before.size() ? output_of_before[std::size_t(v)] : M::null_vertex();
      if (o == M::null_vertex()) return false;
      result[c].push_back(o);
    }
  mesh = std::move(out);
  curve_vertices = std::move(result);
  return true;
}

struct SurfaceDistance::Tree {
  using Primitive = CGAL::AABB_triangle_primitive<Filtered, std::vector<Filtered::Triangle_3>::const_iterator>;
  std::vector<Filtered::Triangle_3> triangles;
  CGAL::AABB_tree<CGAL::AABB_traits<Filtered, Primitive>> tree;
};

template <class K> std::vector<Filtered::Triangle_3> triangles_of(const Mesh<K>& mesh) {
  std::vector<Filtered::Triangle_3> result;
  result.reserve(mesh.number_of_faces());
  for (auto f : mesh.faces()) {
    const auto h = mesh.halfedge(f);
    result.emplace_back(to_filtered(mesh.point(mesh.source(h))), to_filtered(mesh.point(mesh.target(h))),
                        to_filtered(mesh.point(mesh.target(mesh.next(h)))));
  }
  return result;
}

SurfaceDistance::SurfaceDistance(std::vector<Filtered::Triangle_3> triangles) : tree_(std::make_unique<Tree>()) {
  tree_->triangles = std::move(triangles);
  tree_->tree.insert(tree_->triangles.begin(), tree_->triangles.end());
  tree_->tree.build();
  if (!tree_->triangles.empty()) tree_->tree.accelerate_distance_queries();
}

SurfaceDistance::~SurfaceDistance() = default;

double SurfaceDistance::distance(const Filtered::Point_3& p) const {
  return tree_->triangles.empty() ? std::numeric_limits<double>::infinity() : std::sqrt(tree_->tree.squared_distance(p));
}

Filtered::Point_3 SurfaceDistance::closest_point(const Filtered::Point_3& p) const {
  return tree_->triangles.empty() ? p : tree_->tree.closest_point(p);
}

double SurfaceDistance::sampled_distance(const Filtered::Point_3& p, const Filtered::Point_3& q,
                                         const Filtered::Point_3& r) const {
  double worst = 0;
  for (const auto& x : {p, q, r, CGAL::midpoint(p, q), CGAL::midpoint(q, r), CGAL::midpoint(r, p), CGAL::centroid(p, q, r)})
    worst = std::max(worst, distance(x));
  return worst;
}

template <class K>
std::vector<std::size_t> remeshed_faces_off_surface(const Mesh<K>& mesh, const SurfaceDistance& surface, double tol,
                                                    double& max_distance) {
  using F = typename Mesh<K>::Face_index;
  max_distance = 0;
  std::vector<std::size_t> result;
  const auto [source, has_source] = mesh.template property_map<F, std::uint32_t>(source_face_property);
  if (!has_source) return result;
  for (F f : mesh.faces()) {
    if (source[f] != remeshed_face) continue;
    const auto h = mesh.halfedge(f);
    const auto p = to_filtered(mesh.point(mesh.source(h))), q = to_filtered(mesh.point(mesh.target(h))),
               r = to_filtered(mesh.point(mesh.target(mesh.next(h))));
    const double worst = surface.sampled_distance(p, q, r);
    max_distance = std::max(max_distance, worst);
    if (worst > tol) result.push_back(std::size_t(f));
  }
  return result;
}

template <class K>
std::size_t split_edges_off_surface(Mesh<K>& mesh, const std::vector<std::vector<typename MeshTypes<K>::V>>& curve_vertices,
                                    const SurfaceDistance& surface, double tol, int rounds) {
  using M = Mesh<K>;
  using V = typename M::Vertex_index;
  using E = typename M::Edge_index;
  using F = typename M::Face_index;
  auto source = mesh.template property_map<F, std::uint32_t>(source_face_property).first;
  auto is_new = mesh.template property_map<F, bool>(new_face_property).first;
  const FrozenFaces<K> frozen(mesh);
  const auto curve_edges = curve_edge_set(curve_vertices);
  auto point = [&](V v) { return to_filtered(mesh.point(v)); };

  std::size_t splits = 0;
  for (int round = 0; round < rounds; ++round) {
    std::set<E> to_split;
    for (F f : mesh.faces()) {
      // (Faces around a curve vertex kept next to a frozen stretch can be remeshed and frozen.)
      if (source[f] != remeshed_face || frozen.face(f)) continue;
      const auto h0 = mesh.halfedge(f);
      double worst = tol, longest = -1;
      E chosen = M::null_edge(), longest_edge = M::null_edge();
      for (auto h : CGAL::halfedges_around_face(h0, mesh)) {
        const V a = mesh.source(h), b = mesh.target(h);
        if (curve_edges.count({std::min(a, b), std::max(a, b)})) continue;  // shared: left as it is
        if (frozen.face(mesh.face(mesh.opposite(h)))) continue;            // frozen: left as it is
        const double d = surface.distance(CGAL::midpoint(point(a), point(b)));
        if (d > worst) worst = d, chosen = mesh.edge(h);
        const double l = CGAL::squared_distance(point(a), point(b));
        if (l > longest) longest = l, longest_edge = mesh.edge(h);
      }
      if (chosen == M::null_edge() && longest_edge != M::null_edge() &&
          surface.distance(CGAL::centroid(point(mesh.source(h0)), point(mesh.target(h0)), point(mesh.target(mesh.next(h0))))) > tol)
        chosen = longest_edge;
      if (chosen != M::null_edge()) to_split.insert(chosen);
    }
    if (to_split.empty()) break;
    for (E e : to_split) {
      const auto h = mesh.halfedge(e);
      const auto middle = surface.closest_point(CGAL::midpoint(point(mesh.source(h)), point(mesh.target(h))));
      // hn (source -> new vertex) is followed by h (new vertex -> target), in h's face.
      const auto hn = CGAL::Euler::split_edge(h, mesh);
      mesh.point(mesh.target(hn)) = typename K::Point_3(middle.x(), middle.y(), middle.z());
      // Each face of the edge is now a quadrangle: connect the new vertex to its opposite corner.
      const std::array<std::pair<typename M::Halfedge_index, typename M::Halfedge_index>, 2> sides = {
          std::make_pair(hn, mesh.next(h)), std::make_pair(mesh.opposite(h), mesh.next(mesh.opposite(hn)))};
      for (const auto& [into_new, into_corner] : sides) {
        if (mesh.is_border(into_new)) continue;
        const auto hs = CGAL::Euler::split_face(into_new, into_corner, mesh);
        for (F g : {mesh.face(hs), mesh.face(mesh.opposite(hs))}) {
          source[g] = remeshed_face;
          is_new[g] = true;
        }
      }
      ++splits;
    }
  }
  return splits;
}

template <class K>
std::size_t flip_to_improve_angles(Mesh<K>& mesh, const std::vector<std::vector<typename MeshTypes<K>::V>>& curve_vertices,
                                   const SurfaceDistance& surface, double tol, int rounds) {
  using M = Mesh<K>;
  using V = typename M::Vertex_index;
  using F = typename M::Face_index;
  using FP = Filtered::Point_3;
  FaceMarks<K> marks(mesh);
  auto& source = marks.source;
  auto& is_new = marks.is_new;
  const auto curve_edges = curve_edge_set(curve_vertices);
  auto point = [&](V v) { return to_filtered(mesh.point(v)); };
  // The new faces turn by less than 30 degrees from the ones they replace. (Cross products, not
  // CGAL::normal, whose precondition fails on a flat triangle: a zero vector here never passes.)
  auto close_normals = [](const FP& a, const FP& b, const FP& c, const FP& d, const FP& e, const FP& f) {
    return turns_less_than_30_degrees(CGAL::cross_product(b - a, c - a), CGAL::cross_product(e - d, f - d));
  };
  std::size_t flips = 0;
  for (int round = 0; round < rounds; ++round) {
    std::size_t flipped = 0;
    for (auto e : mesh.edges()) {
      if (mesh.is_border(e)) continue;
      const auto h = mesh.halfedge(e), o = mesh.opposite(h);
      const F fh = mesh.face(h), fo = mesh.face(o);
      if (!marks.changeable(fh) || !marks.changeable(fo)) continue;
      const V p = mesh.source(h), q = mesh.target(h), r = mesh.target(mesh.next(h)), t = mesh.target(mesh.next(o));
      if (curve_edges.count({std::min(p, q), std::max(p, q)})) continue;  // shared: left as it is
      if (r == t || mesh.halfedge(r, t) != M::null_halfedge()) continue;  // the other diagonal exists
      const FP P = point(p), Q = point(q), R = point(r), T = point(t);
      // Faces (p, q, r) and (q, p, t) become (q, r, t) and (r, p, t).
      const double before = std::min(min_angle_deg(P, Q, R), min_angle_deg(Q, P, T));
      const double after = std::min(min_angle_deg(Q, R, T), min_angle_deg(R, P, T));
      if (!(after > before + 1.0)) continue;
      // A wide cap (its largest angle 150 degrees or more: CGAL's remeshing leaves some on
      // straight lines of the input, with a largest angle near 180; three curve vertices make one
      // where the curve bends) has a normal that says little about the surface: only the other
      // face is compared. (A cap of three curve vertices at 162 degrees failed the comparison
      // with its own normal by half a degree; the new faces were within 8 degrees of the face
      // across and on the input surface.)
      const bool wide_pqr = is_cap(P, Q, R, 150), wide_qpt = is_cap(Q, P, T, 150);
      if (wide_pqr && wide_qpt) continue;
      // Not over a sharp edge, though (faces more than 60 degrees apart): the remeshing keeps
      // those, and a cap's apex may lie on the other side of one. (A flat cap, within a degree of
      // 180, has no meaningful normal to tell.)
      const bool flat = is_cap(P, Q, R, 179) || is_cap(Q, P, T, 179);
      const auto n_pqr = CGAL::cross_product(Q - P, R - P), n_qpt = CGAL::cross_product(P - Q, T - Q);
      if ((wide_pqr || wide_qpt) && !flat && !less_apart_than(n_pqr, n_qpt, 0.5)) continue;
      if ((!wide_pqr && (!close_normals(P, Q, R, Q, R, T) || !close_normals(P, Q, R, R, P, T))) ||
          (!wide_qpt && (!close_normals(Q, P, T, Q, R, T) || !close_normals(Q, P, T, R, P, T))))
        continue;
      if (surface.distance(CGAL::midpoint(R, T)) > tol) continue;
      // Two new faces of one input face, in one plane, stay in it (exact coplanarity: merges and
      // collapses can tilt faces that keep their source); otherwise remeshed.
      const std::uint32_t flipped_source =
          source[fh] == source[fo] && CGAL::coplanar(mesh.point(p), mesh.point(q), mesh.point(r), mesh.point(t))
              ? source[fh]
              : remeshed_face;
      CGAL::Euler::flip_edge(h, mesh);
      for (F g : {mesh.face(h), mesh.face(o)}) {
        source[g] = flipped_source;
        is_new[g] = true;
      }
      ++flipped;
    }
    flips += flipped;
    if (flipped == 0) break;
  }
  return flips;
}

template <class K>
std::size_t smooth_remeshed_vertices(Mesh<K>& mesh, const std::vector<std::vector<typename MeshTypes<K>::V>>& curve_vertices,
                                     const SurfaceDistance& surface, double tol, int rounds) {
  using M = Mesh<K>;
  using V = typename M::Vertex_index;
  using F = typename M::Face_index;
  using FP = Filtered::Point_3;
  auto source = mesh.template property_map<F, std::uint32_t>(source_face_property).first;
  const FrozenFaces<K> frozen(mesh);
  std::set<V> on_curve;
  for (const auto& vs : curve_vertices) on_curve.insert(vs.begin(), vs.end());
  auto point = [&](V v) { return to_filtered(mesh.point(v)); };
  std::size_t moves = 0;
  for (int round = 0; round < rounds; ++round) {
    std::size_t moved = 0;
    for (V v : mesh.vertices()) {
      if (on_curve.count(v) || mesh.is_border(v) || frozen.around(mesh, v)) continue;
      // Only vertices all of whose faces are remeshed (not the band's border).
      bool inside = true;
      std::vector<V> ring;
      for (auto h : CGAL::halfedges_around_target(mesh.halfedge(v), mesh)) {
        if (source[mesh.face(h)] != remeshed_face) inside = false;
        ring.push_back(mesh.source(h));
      }
      if (!inside || ring.size() < 3) continue;
      // The fan's faces (v, ring[i + 1], ring[i])... as (ring[i], v, next) in halfedge order.
      auto worst_angle = [&](const FP& at) {
        double worst = 180;
        for (auto h : CGAL::halfedges_around_target(mesh.halfedge(v), mesh))
          worst = std::min(worst, min_angle_deg(point(mesh.source(h)), at, point(mesh.target(mesh.next(h)))));
        return worst;
      };
      double x = 0, y = 0, z = 0;
      for (V w : ring) {
        const FP p = point(w);
        x += p.x(), y += p.y(), z += p.z();
      }
      const double n = double(ring.size());
      const FP target = surface.closest_point(FP(x / n, y / n, z / n));
      const FP here = point(v);
      if (!(worst_angle(target) > worst_angle(here) + 1.0)) continue;
      // The fan's faces keep their orientation (turn by less than 30 degrees) and stay near the
      // surface (their centroids within tol).
      bool ok = true;
      for (auto h : CGAL::halfedges_around_target(mesh.halfedge(v), mesh)) {
        const FP a = point(mesh.source(h)), c = point(mesh.target(mesh.next(h)));
        if (!turns_less_than_30_degrees(CGAL::cross_product(here - a, c - a), CGAL::cross_product(target - a, c - a)) ||
            surface.distance(CGAL::centroid(a, target, c)) > tol ||
            surface.distance(CGAL::midpoint(a, target)) > tol) {
          ok = false;
          break;
        }
      }
      if (!ok) continue;
      mesh.point(v) = typename K::Point_3(target.x(), target.y(), target.z());
      ++moved;
    }
    moves += moved;
    if (moved == 0) break;
  }
  return moves;
}

#define SEAM_INSTANTIATE(K)                                                                                          \
  template std::vector<std::vector<std::size_t>> choose_curve_points<K>(const std::vector<Polyline<K>>&, double, double);   \
  template bool coarsen_and_remesh_near_curves<K>(Mesh<K>&, std::vector<std::vector<typename MeshTypes<K>::V>>&,   \
                                                  const std::vector<std::vector<std::size_t>>&,                    \
                                                  const std::vector<std::vector<char>>&, double,                   \
                                                  std::vector<std::vector<std::size_t>>&);                         \
  template std::vector<Filtered::Triangle_3> triangles_of<K>(const Mesh<K>&);                                         \
  template std::vector<std::size_t> remeshed_faces_off_surface<K>(const Mesh<K>&, const SurfaceDistance&, double,   \
                                                                  double&);                                         \
  template std::size_t split_edges_off_surface<K>(Mesh<K>&, const std::vector<std::vector<typename MeshTypes<K>::V>>&, \
                                                  const SurfaceDistance&, double, int);                             \
  template std::size_t flip_to_improve_angles<K>(Mesh<K>&, const std::vector<std::vector<typename MeshTypes<K>::V>>&, \
                                                 const SurfaceDistance&, double, int);                              \
  template std::size_t smooth_remeshed_vertices<K>(Mesh<K>&, const std::vector<std::vector<typename MeshTypes<K>::V>>&, \
                                                   const SurfaceDistance&, double, int);
SEAM_INSTANTIATE(Exact)
SEAM_INSTANTIATE(Filtered)
SEAM_INSTANTIATE(Float)
#undef SEAM_INSTANTIATE

}  // namespace seam::internal
