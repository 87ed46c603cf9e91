// seam::check_resolved: the independent check of a resolved pair. See seam/resolve.h.
//
// Written apart from src/resolve.cpp on purpose (it shares none of its code): the meshes are
// matched by exact coordinates, the crossing test is seam::check_pair's (checks 1-3), and the
// side tests are CGAL's.
//
// SPDX-License-Identifier: GPL-3.0-or-later
#include <seam/check.h>
#include <seam/errors.h>
#include <seam/internal/message.h>
#include <seam/resolve.h>

#include <CGAL/Side_of_triangle_mesh.h>
#include <CGAL/boost/graph/helpers.h>

#include <algorithm>
#include <array>
#include <functional>
#include <map>
#include <optional>
#include <set>
#include <type_traits>

namespace seam {

namespace {

using internal::say;
using EM = Mesh<Exact>;
using EPoint = Exact::Point_3;

struct Less {
  bool operator()(const EPoint& p, const EPoint& q) const { return CGAL::compare_xyz(p, q) == CGAL::SMALLER; }
};
using Corners = std::array<EPoint, 3>;
struct CornersLess {
  bool operator()(const Corners& x, const Corners& y) const {
    return std::lexicographical_compare(x.begin(), x.end(), y.begin(), y.end(), Less());
  }
};

template <class K> EM to_exact(const Mesh<K>& m) {
  EM out;
  std::map<typename Mesh<K>::Vertex_index, EM::Vertex_index> index;
  for (auto v : m.vertices()) {
    const auto& p = m.point(v);
    if constexpr (std::is_same_v<K, Exact>) index[v] = out.add_vertex(p);
    else index[v] = out.add_vertex(EPoint(p.x(), p.y(), p.z()));
  }
  for (auto f : m.faces()) {
    std::vector<EM::Vertex_index> vs;
    for (auto v : CGAL::vertices_around_face(m.halfedge(f), m)) vs.push_back(index[v]);
    if (out.add_face(vs) == EM::null_face()) throw InternalError("check_resolved: a mesh could not be copied");
  }
  return out;
}

/// The face's corners, rotated so that the smallest comes first (orientation kept).
Corners oriented_corners(const EM& m, EM::Face_index f) {
  Corners c;
  int i = 0;
  for (auto v : CGAL::vertices_around_face(m.halfedge(f), m)) c[i++] = m.point(v);
  const auto first = std::min_element(c.begin(), c.end(), Less()) - c.begin();
  std::rotate(c.begin(), c.begin() + first, c.end());
  return c;
}
Corners reversed(Corners c) {
  std::swap(c[1], c[2]);
  return c;
}

/// Pieces of `m`'s faces not in `shared`, joined across edges that are not edges of `other`;
/// one exact side test per piece against `other`, which must say outside.
void check_pieces_outside(const EM& m, const std::vector<char>& shared, const EM& other, const std::string& name,
                          const std::string& other_name, std::size_t& pieces, std::vector<std::string>& problems,
                          const std::function<bool(EM::Halfedge_index)>& is_shared_edge) {
  std::vector<char> seen(m.number_of_faces(), 0);
  const CGAL::Side_of_triangle_mesh<EM, Exact> side(other);
  for (auto f0 : m.faces()) {
    if (seen[std::size_t(f0)] || shared[std::size_t(f0)]) continue;
    ++pieces;
    std::vector<EM::Face_index> stack{f0};
    seen[std::size_t(f0)] = 1;
    while (!stack.empty()) {
      const auto f = stack.back();
      stack.pop_back();
      for (auto h : CGAL::halfedges_around_face(m.halfedge(f), m)) {
        const auto g = m.face(m.opposite(h));
        if (is_shared_edge(h) || seen[std::size_t(g)] || shared[std::size_t(g)]) continue;
        seen[std::size_t(g)] = 1;
        stack.push_back(g);
      }
    }
    const auto c = oriented_corners(m, f0);
    const EPoint centroid = CGAL::centroid(c[0], c[1], c[2]);
    const auto where = side(centroid);
    if (where != CGAL::ON_UNBOUNDED_SIDE)
      problems.push_back(say(name, ": face ", std::size_t(f0), " (a piece of non-shared faces) lies ",
                             where == CGAL::ON_BOUNDARY ? "on " : "inside ", other_name));
  }
}

}  // namespace

template <class K> ResolvedCheckReport check_resolved(const Mesh<K>& a3_in, const Mesh<K>& b3_in) {
  ResolvedCheckReport r;
  auto& problems = r.problems;
  const EM a = to_exact<K>(a3_in), b = to_exact<K>(b3_in);
  for (const auto* m : {&a, &b}) {
    const char* name = m == &a ? "A3" : "B3";
    if (m->number_of_faces() == 0) problems.push_back(say(name, ": no face"));
    else if (!CGAL::is_closed(*m)) problems.push_back(say(name, ": not closed"));
  }
  if (!problems.empty()) return r;
  // Vertices of both, edges of both, faces of both (by corners).
  std::map<EPoint, EM::Vertex_index, Less> in_b;
  for (auto v : b.vertices()) in_b.emplace(b.point(v), v);
  const auto b_vertex = [&](EM::Vertex_index v) {
    const auto it = in_b.find(a.point(v));
    return it == in_b.end() ? EM::null_vertex() : it->second;
  };
  std::vector<Polyline<Exact>> curves;
  std::set<EPoint, Less> on_edge;
  for (auto e : a.edges()) {
    const auto u = a.vertex(e, 0), w = a.vertex(e, 1);
    const auto bu = b_vertex(u), bw = b_vertex(w);
    if (bu == EM::null_vertex() || bw == EM::null_vertex() || b.halfedge(bu, bw) == EM::null_halfedge()) continue;
    curves.push_back({a.point(u), a.point(w)});
    on_edge.insert(a.point(u));
    on_edge.insert(a.point(w));
  }
  r.shared_edges = curves.size();
  for (auto v : a.vertices())
    if (b_vertex(v) != EM::null_vertex() && !on_edge.count(a.point(v))) curves.push_back({a.point(v)});
  const CheckFocus whole;  // checks 1-3 on the whole meshes
  const PairCheckReport pc = check_pair<Exact>(a, b, a, b, curves, 0.0, &whole);
  for (const auto& p : pc.problems) problems.push_back(p);

  std::map<Corners, EM::Face_index, CornersLess> faces_b;
  for (auto f : b.faces()) faces_b.emplace(oriented_corners(b, f), f);
  std::vector<char> shared_a(a.number_of_faces(), 0), shared_b(b.number_of_faces(), 0);
  for (auto f : a.faces()) {
    const Corners c = oriented_corners(a, f);
    if (const auto it = faces_b.find(c); it != faces_b.end()) {
      problems.push_back(say("A3 face ", std::size_t(f), " is a face of B3 in the same orientation (they overlap behind it)"));
      shared_a[std::size_t(f)] = shared_b[std::size_t(it->second)] = 1;
    }
    Corners rc = reversed(c);
    std::rotate(rc.begin(), std::min_element(rc.begin(), rc.end(), Less()), rc.end());
    if (const auto it = faces_b.find(rc); it != faces_b.end()) {
      shared_a[std::size_t(f)] = shared_b[std::size_t(it->second)] = 1;
      ++r.shared_faces;
    }
  }
  if (!pc.ok()) return r;  // the side tests assume no crossing
  const auto shared_edge_of = [](const EM& m, const EM& other, const std::map<EPoint, EM::Vertex_index, Less>& at) {
    return [&m, &other, &at](EM::Halfedge_index h) {
      const auto u = at.find(m.point(m.source(h))), w = at.find(m.point(m.target(h)));
      return u != at.end() && w != at.end() && other.halfedge(u->second, w->second) != EM::null_halfedge();
    };
  };
  std::map<EPoint, EM::Vertex_index, Less> in_a;
  for (auto v : a.vertices()) in_a.emplace(a.point(v), v);
  check_pieces_outside(a, shared_a, b, "A3", "B3", r.pieces_a, problems, shared_edge_of(a, b, in_b));
  check_pieces_outside(b, shared_b, a, "B3", "A3", r.pieces_b, problems, shared_edge_of(b, a, in_a));
  return r;
}

#define SEAM_INSTANTIATE(K) template ResolvedCheckReport check_resolved<K>(const Mesh<K>&, const Mesh<K>&);
SEAM_INSTANTIATE(Exact)
SEAM_INSTANTIATE(Filtered)
SEAM_INSTANTIATE(Float)
#undef SEAM_INSTANTIATE

}  // namespace seam
