// seam::resolve: the overlap of two conforming tows given to one of them. See seam/resolve.h.
//
// Steps 1-4 run on exact-kernel meshes (the inputs themselves under Exact, copies with the same
// vertex and face indices otherwise); step 5 builds the loser's new mesh in K from the inputs'
// own points, so no coordinate is ever rounded or constructed.
//
// SPDX-License-Identifier: GPL-3.0-or-later
#include <seam/check.h>
#include <seam/errors.h>
#include <seam/internal/message.h>
#include <seam/resolve.h>

#include <CGAL/Side_of_triangle_mesh.h>
#include <CGAL/boost/graph/helpers.h>

#include <array>
#include <chrono>
#include <map>
#include <optional>
#include <type_traits>
#include <utility>
#include <vector>

namespace seam {

const char* keeper_name(Keeper k) {
  switch (k) {
    case Keeper::a: return "a";
    case Keeper::b: return "b";
    case Keeper::automatic: break;
  }
  return "auto";
}

namespace {

using internal::say;
using EM = Mesh<Exact>;
using EV = EM::Vertex_index;
using EF = EM::Face_index;
using EPoint = Exact::Point_3;
/// The exact number type behind Epeck (GMP or Boost rationals): sums of volumes without lazy trees.
using ExactNT = std::decay_t<decltype(CGAL::exact(std::declval<const Exact::FT&>()))>;
using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

template <class P> std::string point_text(const P& p) {
  return say("(", CGAL::to_double(p.x()), ", ", CGAL::to_double(p.y()), ", ", CGAL::to_double(p.z()), ")");
}

struct PointLess {
  bool operator()(const EPoint& p, const EPoint& q) const { return CGAL::compare_xyz(p, q) == CGAL::SMALLER; }
};

/// The three vertices of face f, in its orientation.
std::array<EV, 3> corners(const EM& m, EF f) {
  const auto h = m.halfedge(f);
  return {m.source(h), m.target(h), m.target(m.next(h))};
}

/// A copy of `mesh` in the exact kernel with the same vertex and face indices (`mesh` has no
/// garbage). Its points are doubles (Filtered, Float), so the conversion is exact.
template <class K> EM exact_copy(const Mesh<K>& mesh) {
  EM out;
  out.reserve(mesh.number_of_vertices(), mesh.number_of_edges(), mesh.number_of_faces());
  for (auto v : mesh.vertices()) {
    const auto& p = mesh.point(v);
    out.add_vertex(EPoint(p.x(), p.y(), p.z()));
  }
  for (auto f : mesh.faces()) {
    const auto h = mesh.halfedge(f);
    const EV u(std::size_t(mesh.source(h))), v(std::size_t(mesh.target(h))),
        w(std::size_t(mesh.target(mesh.next(h))));
    const EF g = out.add_face(u, v, w);
    if (g != EF(std::size_t(f))) throw InternalError("resolve: a mesh could not be copied");
    out.set_halfedge(g, out.halfedge(u, v));  // the same first corner as in `mesh`
  }
  return out;
}

/// How mesh M meets the other mesh O: vertices at the same point, edges and faces of both.
struct Sharing {
  std::vector<EV> other;             ///< per vertex of M: O's vertex at the same point, or null
  std::vector<char> edge;            ///< per edge of M: an edge of O too
  std::vector<signed char> face;     ///< per face of M: 0, +1 a face of O in the same orientation, -1 opposite
  std::size_t edges = 0, faces = 0, same_faces = 0;
};

Sharing find_sharing(const EM& m, const EM& o) {
  std::map<EPoint, EV, PointLess> at;
  for (auto v : o.vertices()) at.emplace(o.point(v), v);
  Sharing s;
  s.other.assign(m.number_of_vertices(), EM::null_vertex());
  for (auto v : m.vertices()) {
    const auto it = at.find(m.point(v));
    if (it != at.end()) s.other[std::size_t(v)] = it->second;
  }
  s.edge.assign(m.number_of_edges(), 0);
  for (auto e : m.edges()) {
    const EV u = s.other[std::size_t(m.vertex(e, 0))], w = s.other[std::size_t(m.vertex(e, 1))];
    if (u != EM::null_vertex() && w != EM::null_vertex() && u != w && o.halfedge(u, w) != EM::null_halfedge()) {
      s.edge[std::size_t(e)] = 1;
      ++s.edges;
    }
  }
  s.face.assign(m.number_of_faces(), 0);
  for (auto f : m.faces()) {
    const auto c = corners(m, f);
    const EV u = s.other[std::size_t(c[0])], v = s.other[std::size_t(c[1])], w = s.other[std::size_t(c[2])];
    if (u == EM::null_vertex() || v == EM::null_vertex() || w == EM::null_vertex()) continue;
    const auto third = [&](EV x, EV y) {  // the third vertex of O's face on the halfedge x -> y
      const auto h = o.halfedge(x, y);
      return h == EM::null_halfedge() || o.is_border(h) ? EM::null_vertex() : o.target(o.next(h));
    };
    signed char& sf = s.face[std::size_t(f)];
    if (third(u, v) == w) sf = 1;
    else if (third(v, u) == w) sf = -1;
    if (sf != 0) ++s.faces;
    if (sf > 0) ++s.same_faces;
  }
  return s;
}

/// Step 2: per face of M its patch (-1 for a shared face): the components of the non-shared
/// faces joined across non-shared edges. Returns the number of patches; `first` gets one face of each.
std::size_t find_patches(const EM& m, const Sharing& s, std::vector<int>& patch, std::vector<EF>& first) {
  patch.assign(m.number_of_faces(), -1);
  std::vector<char> seen(m.number_of_faces(), 0);
  std::vector<EF> stack;
  for (auto f0 : m.faces()) {
    if (seen[std::size_t(f0)] || s.face[std::size_t(f0)] != 0) continue;
    const int id = int(first.size());
    first.push_back(f0);
    seen[std::size_t(f0)] = 1;
    stack.push_back(f0);
    while (!stack.empty()) {
      const EF f = stack.back();
      stack.pop_back();
      patch[std::size_t(f)] = id;
      for (auto h : CGAL::halfedges_around_face(m.halfedge(f), m)) {
        if (s.edge[std::size_t(m.edge(h))]) continue;
        const EF g = m.face(m.opposite(h));
        if (g == EM::null_face() || seen[std::size_t(g)]) continue;
        seen[std::size_t(g)] = 1;
        stack.push_back(g);
      }
    }
  }
  return first.size();
}

/// One mesh's classification against the other: per face, -1 shared, else whether inside.
struct Classified {
  Sharing sharing;
  std::vector<int> patch;
  std::vector<char> patch_inside;
  std::size_t patches = 0, patches_inside = 0;
  bool inside(EF f) const { return patch[std::size_t(f)] >= 0 && patch_inside[std::size_t(patch[std::size_t(f)])]; }
  bool outside(EF f) const { return patch[std::size_t(f)] >= 0 && !patch_inside[std::size_t(patch[std::size_t(f)])]; }
};

/// Steps 2-3 for M against the closed mesh O, given how they share (find_sharing(m, o)).
Classified classify(const EM& m, const EM& o, Sharing sharing, const std::string& name_m, const std::string& name_o) {
  Classified c;
  c.sharing = std::move(sharing);
  std::vector<EF> first;
  c.patches = find_patches(m, c.sharing, c.patch, first);
  c.patch_inside.assign(c.patches, 0);
  if (c.patches == 0) return c;
  const CGAL::Side_of_triangle_mesh<EM, Exact> side(o);
  for (std::size_t i = 0; i < c.patches; ++i) {
    const auto k = corners(m, first[i]);
    EPoint centroid = CGAL::centroid(m.point(k[0]), m.point(k[1]), m.point(k[2]));
    CGAL::exact(centroid);
    const CGAL::Bounded_side where = side(centroid);
    if (where == CGAL::ON_BOUNDARY)
      throw InvalidInput(say(name_m, ", ", name_o, ": not conforming: the centroid ", point_text(centroid),
                             " of face ", std::size_t(first[i]), " of ", name_m, " lies on ", name_o,
                             " (a contact that is not shared; run seam pair first)"));
    c.patch_inside[i] = where == CGAL::ON_BOUNDED_SIDE;
    if (c.patch_inside[i]) ++c.patches_inside;
  }
  return c;
}

/// Signed volume sums (6 x volume) of the face groups of one mesh, exact.
struct VolumeSums {
  ExactNT all = 0, inside = 0, outside = 0, shared_same = 0, shared_opposite = 0;
};

VolumeSums volume_sums(const EM& m, const Classified& c) {
  std::vector<Exact::Exact_kernel::Point_3> p;
  p.reserve(m.number_of_vertices());
  for (auto v : m.vertices()) p.push_back(CGAL::exact(m.point(v)));
  VolumeSums s;
  for (auto f : m.faces()) {
    const auto k = corners(m, f);
    const auto &a = p[std::size_t(k[0])], &b = p[std::size_t(k[1])], &d = p[std::size_t(k[2])];
    const ExactNT det = a.x() * (b.y() * d.z() - b.z() * d.y()) - a.y() * (b.x() * d.z() - b.z() * d.x()) +
                        a.z() * (b.x() * d.y() - b.y() * d.x());
    s.all += det;
    const signed char shared = c.sharing.face[std::size_t(f)];
    if (shared > 0) s.shared_same += det;
    else if (shared < 0) s.shared_opposite += det;
    else if (c.inside(f)) s.inside += det;
    else s.outside += det;
  }
  return s;
}

double volume(const ExactNT& six_times) { return CGAL::to_double(six_times / ExactNT(6)); }

/// Step 5's result: the loser's new faces as vertex references into the loser (0) or the keeper (1).
struct VertexRef {
  int mesh;
  std::size_t index;
};
using RefTriangle = std::array<VertexRef, 3>;

struct LoserFaces {
  std::vector<RefTriangle> triangles;
  std::size_t contact = 0, removed = 0, added = 0;
};

LoserFaces loser_faces(const EM& loser, const Classified& cl, const EM& keeper, const Classified& ck) {
  LoserFaces out;
  for (auto f : loser.faces()) {
    const signed char shared = cl.sharing.face[std::size_t(f)];
    if (shared > 0 || cl.inside(f)) {
      ++out.removed;
      continue;
    }
    if (shared < 0) ++out.contact;
    const auto k = corners(loser, f);
    out.triangles.push_back(
        {VertexRef{0, std::size_t(k[0])}, VertexRef{0, std::size_t(k[1])}, VertexRef{0, std::size_t(k[2])}});
  }
  for (auto f : keeper.faces()) {
    if (!ck.inside(f)) continue;
    ++out.contact;
    ++out.added;
    const auto k = corners(keeper, f);
    RefTriangle t;
    for (int i = 0; i < 3; ++i) {  // reversed: corners 0, 2, 1; shared vertices are the loser's
      const EV v = k[i == 0 ? 0 : 3 - i];
      const EV w = ck.sharing.other[std::size_t(v)];
      t[i] = w != EM::null_vertex() ? VertexRef{0, std::size_t(w)} : VertexRef{1, std::size_t(v)};
    }
    out.triangles.push_back(t);
  }
  return out;
}

/// Where the triangles (vertex indices) fail to be a closed oriented 2-manifold: an edge not in
/// exactly two triangles in opposite directions, or a vertex whose triangles form more than one
/// fan. Returns the index of a vertex where it fails and the reason, or an empty reason.
std::pair<std::size_t, std::string> manifold_problem(const std::vector<std::array<std::size_t, 3>>& triangles,
                                                     std::size_t vertices) {
  std::map<std::pair<std::size_t, std::size_t>, int> directed;
  for (const auto& t : triangles)
    for (int i = 0; i < 3; ++i)
      if (++directed[{t[i], t[(i + 1) % 3]}] > 1) return {t[i], "an edge is used twice in the same direction"};
  for (const auto& [e, n] : directed)
    if (!directed.count({e.second, e.first})) return {e.first, "an edge has only one face (a hole)"};
  // Each vertex's link: next[a] = b for each triangle (v, a, b); one cycle per fan.
  std::vector<std::vector<std::pair<std::size_t, std::size_t>>> link(vertices);
  for (const auto& t : triangles)
    for (int i = 0; i < 3; ++i) link[t[i]].emplace_back(t[(i + 1) % 3], t[(i + 2) % 3]);
  for (std::size_t v = 0; v < vertices; ++v) {
    if (link[v].empty()) continue;
    std::map<std::size_t, std::size_t> next(link[v].begin(), link[v].end());
    std::size_t steps = 0, x = link[v].front().first;
    do {
      const auto it = next.find(x);
      if (it == next.end()) return {v, "the faces around a vertex do not close"};
      x = it->second;
      ++steps;
    } while (x != link[v].front().first && steps <= link[v].size());
    if (steps != link[v].size()) return {v, "two fans of faces meet at a single vertex (a pinch)"};
  }
  return {0, ""};
}

/// Step 1: A and B conforming: seam::check_pair's checks 1-3 with the shared edges (and the
/// shared vertices on no shared edge) as the curves.
void validate(const EM& a, const EM& b, const Sharing& sa, const ResolveOptions& o) {
  std::vector<Polyline<Exact>> curves;
  std::vector<char> on_edge(a.number_of_vertices(), 0);
  for (auto e : a.edges()) {
    if (!sa.edge[std::size_t(e)]) continue;
    const EV u = a.vertex(e, 0), v = a.vertex(e, 1);
    curves.push_back({a.point(u), a.point(v)});
    on_edge[std::size_t(u)] = on_edge[std::size_t(v)] = 1;
  }
  for (auto v : a.vertices())
    if (sa.other[std::size_t(v)] != EM::null_vertex() && !on_edge[std::size_t(v)]) curves.push_back({a.point(v)});
  const CheckFocus whole;  // empty: checks 1-3 on the whole meshes, no more
  const PairCheckReport r = check_pair<Exact>(a, b, a, b, curves, 0.0, &whole);
  if (r.ok()) return;
  std::string first = r.problems.front();
  throw InvalidInput(say(o.name_a, ", ", o.name_b, ": not conforming, the curves are not embedded in both (",
                         r.problems.size(), " problem(s); first, with A2 = ", o.name_a, " and B2 = ", o.name_b, ": ",
                         first, "); resolve needs the outputs of seam pair"));
}

/// The mesh without removed elements: `m` itself, or a compacted copy in `holder`.
template <class K> const Mesh<K>& compacted(const Mesh<K>& m, std::optional<Mesh<K>>& holder) {
  if (!m.has_garbage()) return m;
  holder.emplace(m);
  holder->collect_garbage();
  return *holder;
}

/// The mesh in the exact kernel with the same indices: `m` itself under Exact.
template <class K> const EM& exact_view(const Mesh<K>& m, std::optional<EM>& holder) {
  if constexpr (std::is_same_v<K, Exact>) {
    return m;
  } else {
    holder.emplace(exact_copy<K>(m));
    return *holder;
  }
}

template <class K> void require_closed(const Mesh<K>& m, const std::string& name) {
  if (m.number_of_faces() == 0) throw InvalidInput(name + ": no face");
  if (!CGAL::is_triangle_mesh(m)) throw InvalidInput(name + ": not a triangle mesh");
  if (!CGAL::is_closed(m)) throw InvalidInput(name + ": not closed (resolve needs closed tows: it compares volumes)");
}

/// Step 5: the loser's new mesh from the triangles (points of the loser and the keeper, as they are).
template <class K>
Mesh<K> build_loser(const Mesh<K>& loser, const Mesh<K>& keeper, const std::vector<RefTriangle>& triangles,
                    const std::string& name_loser, const std::string& name_keeper) {
  using V = typename Mesh<K>::Vertex_index;
  constexpr std::size_t none = std::size_t(-1);
  std::array<std::vector<std::size_t>, 2> index{std::vector<std::size_t>(loser.number_of_vertices(), none),
                                                std::vector<std::size_t>(keeper.number_of_vertices(), none)};
  for (const auto& t : triangles)
    for (const auto& r : t) index[r.mesh][r.index] = 0;
  std::vector<typename K::Point_3> points;  // the loser's vertices in order, then the keeper's
  for (int m = 0; m < 2; ++m)
    for (std::size_t i = 0; i < index[m].size(); ++i)
      if (index[m][i] != none) {
        index[m][i] = points.size();
        points.push_back((m == 0 ? loser : keeper).point(V(i)));
      }
  std::vector<std::array<std::size_t, 3>> tris;
  tris.reserve(triangles.size());
  for (const auto& t : triangles)
    tris.push_back({index[t[0].mesh][t[0].index], index[t[1].mesh][t[1].index], index[t[2].mesh][t[2].index]});
  const auto [where, why] = manifold_problem(tris, points.size());
  if (!why.empty())
    throw InvalidInput(say(name_loser, ", ", name_keeper, ": giving the overlap to ", name_keeper, " would leave ",
                           name_loser, " not a closed 2-manifold at ", point_text(points[where]), ": ", why));
  Mesh<K> out;
  out.reserve(points.size(), 3 * tris.size() / 2, tris.size());
  for (const auto& p : points) out.add_vertex(p);
  for (const auto& t : tris)
    if (out.add_face(V(t[0]), V(t[1]), V(t[2])) == Mesh<K>::null_face())
      throw InternalError("resolve: a face of " + name_loser + " could not be added");
  return out;
}

}  // namespace

template <class K> ResolveStats resolve(Mesh<K>& a_in, Mesh<K>& b_in, const ResolveOptions& options) {
  ResolveStats st;
  const std::string &name_a = options.name_a, &name_b = options.name_b;
  std::optional<Mesh<K>> hold_a, hold_b;
  const Mesh<K>& a = compacted<K>(a_in, hold_a);
  const Mesh<K>& b = compacted<K>(b_in, hold_b);
  require_closed<K>(a, name_a);
  require_closed<K>(b, name_b);
  auto t = Clock::now();
  std::optional<EM> exact_a, exact_b;
  const EM& ea = exact_view<K>(a, exact_a);
  const EM& eb = exact_view<K>(b, exact_b);
  Sharing sa = find_sharing(ea, eb), sb = find_sharing(eb, ea);
  if (options.validate_input) validate(ea, eb, sa, options);
  st.stage_seconds["validate"] = seconds_since(t);

  t = Clock::now();
  st.shared_edges = sa.edges;
  st.shared_faces = sa.faces;
  st.shared_faces_same_orientation = sa.same_faces;
  const Classified ca = classify(ea, eb, std::move(sa), name_a, name_b);
  const Classified cb = classify(eb, ea, std::move(sb), name_b, name_a);
  st.patches_a = ca.patches;
  st.patches_b = cb.patches;
  st.patches_a_inside = ca.patches_inside;
  st.patches_b_inside = cb.patches_inside;
  st.stage_seconds["classify"] = seconds_since(t);

  t = Clock::now();
  const VolumeSums va = volume_sums(ea, ca), vb = volume_sums(eb, cb);
  const ExactNT overlap = va.inside + vb.inside + va.shared_same;
  // The shared faces are the same triangles in both (a check of the sharing found).
  if (va.shared_same != vb.shared_same || va.shared_opposite != -vb.shared_opposite)
    throw InternalError("resolve: the shared faces of " + name_a + " and " + name_b + " differ in volume");
  st.volume_a_before = volume(va.all);
  st.volume_b_before = volume(vb.all);
  st.overlap_volume = volume(overlap);
  st.stage_seconds["volumes"] = seconds_since(t);

  t = Clock::now();
  st.keeper = options.keeper == Keeper::b || (options.keeper == Keeper::automatic && vb.all < va.all) ? Keeper::b : Keeper::a;
  st.volume_a_after = st.volume_a_before;
  st.volume_b_after = st.volume_b_before;
  st.contact_faces = ca.sharing.faces - ca.sharing.same_faces;
  if (CGAL::is_zero(overlap)) {
    st.note = st.contact_faces > 0 ? "the tows touch without overlapping: both unchanged"
                                   : "the tows do not overlap: both unchanged";
    st.stage_seconds["build"] = seconds_since(t);
    return st;
  }
  // The keepers to try: the one asked for; under auto the smaller tow, then the other (when the
  // loser would vanish, or not be a 2-manifold: where the tows touch along an edge inside the
  // overlap, say).
  std::vector<Keeper> order{st.keeper};
  if (options.keeper == Keeper::automatic) order.push_back(st.keeper == Keeper::a ? Keeper::b : Keeper::a);
  std::string refused;
  for (const Keeper keeper : order) {
    const bool a_keeps = keeper == Keeper::a;
    const std::string &loser = a_keeps ? name_b : name_a, &kept = a_keeps ? name_a : name_b;
    const LoserFaces faces = a_keeps ? loser_faces(eb, cb, ea, ca) : loser_faces(ea, ca, eb, cb);
    try {
      if (faces.triangles.empty())
        throw InvalidInput(say(loser, ", ", kept, ": ", loser, " lies inside ", kept, ": giving the overlap to ", kept,
                               " leaves nothing of ", loser));
      Mesh<K> result = a_keeps ? build_loser<K>(b, a, faces.triangles, name_b, name_a)
                               : build_loser<K>(a, b, faces.triangles, name_a, name_b);
      if (!refused.empty()) st.note = refused + "; so " + kept + " keeps it";
      st.keeper = keeper;
      st.contact_faces = faces.contact;
      st.faces_removed = faces.removed;
      st.faces_added = faces.added;
      if (a_keeps) st.volume_b_after = volume(vb.outside + vb.shared_opposite - va.inside);
      else st.volume_a_after = volume(va.outside + va.shared_opposite - vb.inside);
      (a_keeps ? b_in : a_in) = std::move(result);
      st.stage_seconds["build"] = seconds_since(t);
      return st;
    } catch (const InvalidInput& e) {
      refused += (refused.empty() ? "" : "; ") + std::string(e.what());
    }
  }
  if (options.keeper != Keeper::automatic) refused += " (the other keeper, or auto, may work)";
  throw InvalidInput(refused);
}

#define SEAM_INSTANTIATE(K) template ResolveStats resolve<K>(Mesh<K>&, Mesh<K>&, const ResolveOptions&);
SEAM_INSTANTIATE(Exact)
SEAM_INSTANTIATE(Filtered)
SEAM_INSTANTIATE(Float)
#undef SEAM_INSTANTIATE

}  // namespace seam
