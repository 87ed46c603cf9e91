// seam::textile: all pairs of a unit cell, in parallel. See seam/textile.h.
// SPDX-License-Identifier: GPL-3.0-or-later
#include <seam/check.h>
#include <seam/io.h>
#include <seam/internal/contact_points.h>
#include <seam/internal/curve_pieces.h>
#include <seam/internal/flat_contacts.h>
#include <seam/internal/intersection_curves.h>
#include <seam/internal/message.h>
#include <seam/internal/bbox_diagonal.h>
#include <seam/internal/embed_known_sites.h>
#include <seam/internal/provenance.h>
#include <seam/internal/improve_state.h>
#include <seam/internal/triangle_predicates.h>
#include <seam/internal/snap.h>
#include <seam/internal/verify_output.h>
#include <seam/pair.h>
#include <seam/quality.h>
#include <seam/textile.h>

#include <CGAL/Gmpq.h>
#include <CGAL/boost/graph/Euler_operations.h>
#include <CGAL/box_intersection_d.h>
#include <CGAL/intersections.h>
#include <CGAL/Polygon_mesh_processing/bbox.h>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <exception>
#include <limits>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <sstream>
#include <type_traits>

// Lazy exact numbers (Epeck) are only safe in threads with CGAL's thread support on (atomic
// reference counts, exact values computed under std::call_once); see cgal-notes.md.
#if !defined(CGAL_HAS_THREADS)
#error "seam::textile needs CGAL_HAS_THREADS (build with -pthread; CGAL::CGAL links Threads::Threads)"
#endif

namespace seam {

namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

// ---------------------------------------------------------------- objects that cross threads
//
// Under Epeck a point is a node of a lazy-evaluation DAG: copying it shares the node, and
// evaluating it (CGAL::exact, or a predicate whose interval filter fails) updates the node in
// place. CGAL makes that safe with CGAL_HAS_THREADS, but sharing would still let one thread's
// evaluation tighten another thread's intervals (different filter outcomes, a cache line
// bounced between cores). So nothing lazy crosses a task boundary: the meshes go to the pair
// tasks as plain values (FrozenMesh: doubles, or exact rationals deep-copied), and each pair
// task hands each of its two tows its own copy of the curves, made from the exact coordinates
// (`detached`). Every lazy node is then created, evaluated and destroyed by one task. (One
// exception: inside a pair task, internal::general_position_curves reads the task's two tow
// copies from several TBB workers at once. Their points are leaves made from doubles or exact
// rationals, whose intervals are already as tight as they get, so no worker's evaluation changes
// what another sees; the points it constructs are each made by one worker. Where it gives way
// to CGAL's surface_intersection, the pieces' points are made exact on several workers (the exact
// values, and the intervals they leave, do not depend on the order) and only then classified on
// several workers, by exact predicates.)

using ExactNT = std::decay_t<decltype(CGAL::exact(std::declval<const Exact::FT&>()))>;

/// A copy of an exact rational that shares no memory with it (CGAL::Gmpq is reference counted).
template <class T> T deep_copy(const T& x) {
  if constexpr (std::is_same_v<T, CGAL::Gmpq>) return CGAL::Gmpq(x.mpq());
  else return T(x);  // mpq_class and the other exact types copy their value
}

/// A copy of `p` that shares no lazy node with it: under Epeck a new point built from p's exact
/// coordinates (from doubles when p's interval approximation is a single double, which is then
/// p's exact value). Call it in the thread that owns `p`.
template <class K> typename K::Point_3 detached(const typename K::Point_3& p) {
  if constexpr (std::is_same_v<K, Exact>) {
    const auto& a = CGAL::approx(p);
    if (a.x().is_point() && a.y().is_point() && a.z().is_point())
      return typename K::Point_3(a.x().inf(), a.y().inf(), a.z().inf());
    const auto& e = CGAL::exact(p);
    using FT = typename K::FT;
    return typename K::Point_3(FT(deep_copy(e.x())), FT(deep_copy(e.y())), FT(deep_copy(e.z())));
  } else {
    return p;  // plain doubles
  }
}

template <class K> std::vector<Polyline<K>> detached(const std::vector<Polyline<K>>& curves) {
  std::vector<Polyline<K>> out;
  out.reserve(curves.size());
  for (const auto& c : curves) {
    out.emplace_back();
    out.back().reserve(c.size());
    for (const auto& p : c) out.back().push_back(detached<K>(p));
  }
  return out;
}

/// A mesh as plain values, read concurrently by the pair tasks, each building its own Mesh<K>.
template <class K> struct FrozenMesh {
  std::vector<std::array<double, 3>> doubles;      ///< every coordinate, when each is a double
  std::vector<std::array<ExactNT, 3>> rationals;   ///< otherwise (exact kernel only)
  std::vector<CGAL::Bbox_3> vertex_boxes;           ///< with rationals: each vertex's interval box
  std::vector<std::array<std::uint32_t, 3>> faces;
  CGAL::Bbox_3 bbox;
};

template <class K> FrozenMesh<K> freeze(const Mesh<K>& m) {
  FrozenMesh<K> f;
  bool all_doubles = true;
  f.doubles.reserve(m.number_of_vertices());
  for (auto v : m.vertices()) {
    const auto& p = m.point(v);
    if constexpr (std::is_same_v<K, Exact>) {
      const auto& a = CGAL::approx(p);
      all_doubles = all_doubles && a.x().is_point() && a.y().is_point() && a.z().is_point();
      f.doubles.push_back({a.x().inf(), a.y().inf(), a.z().inf()});
    } else {
      f.doubles.push_back({CGAL::to_double(p.x()), CGAL::to_double(p.y()), CGAL::to_double(p.z())});
    }
    f.bbox += p.bbox();
  }
  if constexpr (std::is_same_v<K, Exact>) {
    if (!all_doubles) {
      f.doubles.clear();
      for (auto v : m.vertices()) {
        const auto& e = CGAL::exact(m.point(v));
        f.rationals.push_back({deep_copy(e.x()), deep_copy(e.y()), deep_copy(e.z())});
        f.vertex_boxes.push_back(m.point(v).bbox());
      }
    }
  }
  for (auto face : m.faces()) {
    std::array<std::uint32_t, 3> t{};
    int k = 0;
    for (auto v : CGAL::vertices_around_face(m.halfedge(face), m)) t[std::min(k++, 2)] = std::uint32_t(std::size_t(v));
    if (k != 3) throw InvalidInput("the mesh is not a triangle mesh");
    f.faces.push_back(t);
  }
  return f;
}

/// The mesh again, with points of its own (call it in the task that uses it).
template <class K> Mesh<K> thaw_faces(const FrozenMesh<K>& f, const std::vector<std::uint32_t>* faces) {
  Mesh<K> m;
  const std::size_t nv = f.doubles.empty() ? f.rationals.size() : f.doubles.size();
  const std::size_t nf = faces ? faces->size() : f.faces.size();
  // The vertices used, in their order (all of them without a selection).
  constexpr std::uint32_t none = std::numeric_limits<std::uint32_t>::max();
  std::vector<std::uint32_t> index(nv, faces ? none : 0);
  if (faces)
    for (std::uint32_t face : *faces)
      for (std::uint32_t v : f.faces[face]) index[v] = 0;
  std::size_t used = 0;
  for (auto& i : index)
    if (i != none) i = std::uint32_t(used++);
  m.reserve(typename Mesh<K>::size_type(used), typename Mesh<K>::size_type(3 * nf / 2 + 3),
            typename Mesh<K>::size_type(nf));
  for (std::size_t v = 0; v < nv; ++v) {
    if (index[v] == none) continue;
    if (!f.doubles.empty()) {
      const auto& p = f.doubles[v];
      m.add_vertex(typename K::Point_3(p[0], p[1], p[2]));
    } else if constexpr (std::is_same_v<K, Exact>) {
      using FT = typename K::FT;
      const auto& p = f.rationals[v];
      m.add_vertex(typename K::Point_3(FT(deep_copy(p[0])), FT(deep_copy(p[1])), FT(deep_copy(p[2]))));
    }
  }
  using V = typename Mesh<K>::Vertex_index;
  for (std::size_t k = 0; k < nf; ++k) {
    const auto& t = f.faces[faces ? (*faces)[k] : k];
    if (m.add_face(V(index[t[0]]), V(index[t[1]]), V(index[t[2]])) == Mesh<K>::null_face()) return Mesh<K>();
  }
  return m;
}

/// Every incoming halfedge of each vertex is reached by circulating around it (one fan per vertex).
template <class K> bool one_fan_per_vertex(const Mesh<K>& m) {
  std::vector<std::size_t> incoming(m.number_of_vertices(), 0), around(m.number_of_vertices(), 0);
  for (auto h : m.halfedges()) ++incoming[std::size_t(m.target(h))];
  for (auto v : m.vertices())
    for (auto h : CGAL::halfedges_around_target(m.halfedge(v), m)) {
      (void)h;
      ++around[std::size_t(v)];
    }
  return incoming == around;
}

/// The mesh again, with points of its own (call it in the task that uses it). With `clip`, only
/// the faces whose bounding box meets it (and their vertices, in their order): every face that
/// can meet a mesh inside `clip`, and so every intersection point with it, and both faces at
/// each edge that does (the edge meets `clip`, so both faces' boxes do). No curve reaches the
/// border this cuts (a border edge belongs to a face that does not meet `clip`). When the
/// selection is not a manifold mesh, the whole mesh.
template <class K> Mesh<K> thaw(const FrozenMesh<K>& f, const CGAL::Bbox_3* clip = nullptr) {
  if (clip) {
    std::vector<std::uint32_t> faces;
    auto box = [&](std::uint32_t v) {
      if (!f.doubles.empty()) {
        const auto& p = f.doubles[v];
        return CGAL::Bbox_3(p[0], p[1], p[2], p[0], p[1], p[2]);
      }
      return f.vertex_boxes[v];
    };
    for (std::size_t k = 0; k < f.faces.size(); ++k) {
      const auto& t = f.faces[k];
      if (CGAL::do_overlap(box(t[0]) + box(t[1]) + box(t[2]), *clip)) faces.push_back(std::uint32_t(k));
    }
    if (faces.size() < f.faces.size()) {
      Mesh<K> m = thaw_faces<K>(f, &faces);
      if (!m.is_empty() && one_fan_per_vertex<K>(m)) return m;
    }
  }
  Mesh<K> m = thaw_faces<K>(f, nullptr);
  if (m.is_empty()) throw InternalError("textile: a copy of a mesh could not be rebuilt");
  return m;
}

// ---------------------------------------------------------------- parallel loops

/// Runs body(i) for i in [0, n), one task per index, in `arena`. An exception thrown by body(i) is
/// kept per index; afterwards the first one in index order is rethrown (deterministic errors).
/// `done(i)` is called after each success, serialised by a mutex.
template <class Body, class Done>
void for_each_index(tbb::task_arena& arena, std::size_t n, Body&& body, Done&& done) {
  std::vector<std::exception_ptr> errors(n);
  std::mutex mutex;
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        for (std::size_t i = r.begin(); i != r.end(); ++i) {
                          try {
                            body(i);
                            std::lock_guard<std::mutex> lock(mutex);
                            done(i);
                          } catch (...) {
                            errors[i] = std::current_exception();
                          }
                        }
                      },
                      tbb::simple_partitioner());
  });
  for (const auto& e : errors)
    if (e) std::rethrow_exception(e);
}

/// The faces of a tow that may hold given points, over one round of insertions: per point, the
/// faces (at the round's start) whose boxes meet its box, and every face cut from them since (each
/// lies inside the triangle it was cut from). Faces are listed in index order, the order of
/// Mesh::faces(), so a search over them finds the face a search over all faces would.
template <class K> class FaceLookup {
 public:
  using F = typename Mesh<K>::Face_index;
  using Box = CGAL::Box_intersection_d::Box_with_info_d<double, 3, std::size_t>;

  FaceLookup(const Mesh<K>& m, const std::vector<typename K::Point_3>& points) : candidates_(points.size()) {
    std::vector<Box> faces, queries;
    for (F f : m.faces()) {
      CGAL::Bbox_3 box;
      for (auto v : CGAL::vertices_around_face(m.halfedge(f), m)) box += m.point(v).bbox();
      faces.emplace_back(box, std::size_t(f));
      root_.push_back(std::size_t(f));
      members_.push_back({std::size_t(f)});
    }
    for (std::size_t i = 0; i < points.size(); ++i) queries.emplace_back(points[i].bbox(), i);
    CGAL::box_intersection_d(queries.begin(), queries.end(), faces.begin(), faces.end(),
                             [&](const Box& q, const Box& f) { candidates_[q.info()].push_back(f.info()); });
  }

  /// The faces that may hold point `i`, in index order.
  std::vector<F> faces_for(std::size_t i) const {
    std::vector<std::size_t> out;
    for (std::size_t f : candidates_[i]) out.insert(out.end(), members_[f].begin(), members_[f].end());
    std::sort(out.begin(), out.end());
    out.erase(std::unique(out.begin(), out.end()), out.end());
    return std::vector<F>(out.begin(), out.end());
  }

  /// Faces [first, first + count) were cut from face `from`.
  void added(std::size_t first, std::size_t count, std::size_t from) {
    const std::size_t r = root_[from];
    root_.resize(std::max(root_.size(), first + count));
    for (std::size_t f = first; f < first + count; ++f) {
      root_[f] = r;
      members_[r].push_back(f);
    }
  }

 private:
  std::vector<std::size_t> root_;                      ///< by face: the face at the start it lies in
  std::vector<std::vector<std::size_t>> members_;      ///< by face at the start: it and its pieces
  std::vector<std::vector<std::size_t>> candidates_;   ///< by point: faces at the start
};

/// Makes `p`, a point of the surface of `m`, a vertex of it: the first face of `faces` (a
/// FaceLookup's, in index order) holding it is cut in three, or the two faces at the edge holding
/// it in two each (exact tests; the surface is unchanged). `before()` is called before the mesh
/// changes, and `added(first, count, from)` of each face cut: faces [first, first + count) are
/// new pieces of face `from`. Returns false when `p` is a vertex already or lies on none of `faces`.
template <class K, class Before, class Added>
bool insert_vertex(Mesh<K>& m, const typename K::Point_3& p, const std::vector<typename Mesh<K>::Face_index>& faces,
                   Before&& before, Added&& added) {
  using F = typename Mesh<K>::Face_index;
  const CGAL::Bbox_3 box = p.bbox();
  for (F f : faces) {
    const auto h = m.halfedge(f);
    const auto &a = m.point(m.source(h)), &b = m.point(m.target(h)), &c = m.point(m.target(m.next(h)));
    if (!CGAL::do_overlap(a.bbox() + b.bbox() + c.bbox(), box)) continue;
    if (!internal::on_triangle<K>(a, b, c, p)) continue;
    if (p == a || p == b || p == c) return false;
    before();
    // On an edge of f?
    for (auto e : CGAL::halfedges_around_face(h, m)) {
      const auto &s = m.point(m.source(e)), &t = m.point(m.target(e));
      if (!CGAL::collinear(s, t, p)) continue;
      const F f2 = m.face(m.opposite(e));
      const auto hnew = CGAL::Euler::split_edge(e, m);  // hnew: source -> new vertex, then e
      m.point(m.target(hnew)) = p;
      std::size_t n = m.number_of_faces();
      CGAL::Euler::split_face(hnew, m.next(e), m);
      added(n, m.number_of_faces() - n, std::size_t(f));
      if (f2 != Mesh<K>::null_face()) {
        const auto o = m.opposite(e);  // target -> new vertex, then opposite(hnew)
        n = m.number_of_faces();
        CGAL::Euler::split_face(o, m.next(m.opposite(hnew)), m);
        added(n, m.number_of_faces() - n, std::size_t(f2));
      }
      return true;
    }
    const std::size_t n = m.number_of_faces();
    const auto hc = CGAL::Euler::add_center_vertex(h, m);
    m.point(m.target(hc)) = p;
    added(n, m.number_of_faces() - n, std::size_t(f));
    return true;
  }
  return false;
}

template <class K> struct PairWork {
  std::size_t a = 0, b = 0;
  std::vector<Polyline<K>> for_a, for_b;  ///< the curves, one copy per consuming tow
  std::vector<typename K::Point_3> contacts;  ///< isolated points of contact (no curve passes)
  std::vector<Polyline<K>> embedded_a, embedded_b;  ///< as embedded into each tow
  std::vector<std::vector<typename Mesh<K>::Vertex_index>> vertices_a, vertices_b;  ///< their vertices there
  TextilePairStats stats;
};

std::string quoted(const std::string& name) { return "'" + name + "'"; }


/// Quality of the new faces of `mesh` with a vertex on the curves whose vertices are given.
template <class K>
CurveFaceQuality curve_face_quality(const Mesh<K>& mesh,
                                    const std::vector<std::vector<typename Mesh<K>::Vertex_index>>& curve_vertices) {
  const auto is_new = mesh.template property_map<typename Mesh<K>::Face_index, bool>(new_face_property);
  std::set<typename Mesh<K>::Face_index> faces;
  for (const auto& vs : curve_vertices)
    for (auto v : vs)
      for (auto f : CGAL::faces_around_target(mesh.halfedge(v), mesh))
        if (f != Mesh<K>::null_face() && (!is_new.second || is_new.first[f])) faces.insert(f);
  CurveFaceQuality q;
  q.min_angle_deg = faces.empty() ? 0.0 : 180.0;
  for (auto f : faces) {
    const auto h = mesh.halfedge(f);
    const double angle = min_angle_deg(to_filtered(mesh.point(mesh.source(h))), to_filtered(mesh.point(mesh.target(h))),
                                       to_filtered(mesh.point(mesh.target(mesh.next(h)))));
    ++q.faces;
    q.below_10 += angle < 10 ? 1 : 0;
    q.below_20 += angle < 20 ? 1 : 0;
    q.min_angle_deg = std::min(q.min_angle_deg, angle);
  }
  return q;
}

template <class K> using CurveVertices = std::vector<std::vector<typename Mesh<K>::Vertex_index>>;

/// The smallest mean edge length of the tows of `pairs` (tow indices into `meshes`): the scale of
/// the quality stage's automatic tolerance and feature size.
template <class K>
double smallest_mean_edge(const std::vector<Mesh<K>>& meshes,
                          const std::vector<std::pair<std::size_t, std::size_t>>& pairs) {
  double smallest = std::numeric_limits<double>::max();
  for (const auto& [a, b] : pairs)
    for (const std::size_t i : {a, b}) smallest = std::min(smallest, mean_edge_length<K>(meshes[i]));
  return smallest;
}

/// The same over the input tows of the pairs with curves (or points of contact).
template <class K> double smallest_mean_edge(const std::vector<Mesh<K>>& inputs, const TextileResult<K>& result) {
  std::vector<std::pair<std::size_t, std::size_t>> pairs;
  for (const auto& pair : result.pairs)
    if (!pair.curves.empty()) pairs.emplace_back(pair.stats.a, pair.stats.b);
  return smallest_mean_edge<K>(inputs, pairs);
}

/// The quality stage's options (step 5), from the textile options and the tows' scale.
ImproveOptions quality_options(const TextileOptions& options, double smallest_mean_edge) {
  ImproveOptions io = options.quality;
  io.min_angle_deg = options.embed.min_angle_deg;
  io.max_area = options.embed.max_area;
  if (io.tolerance < 0) io.tolerance = 0.1 * smallest_mean_edge;
  return io;
}

/// Step 4b (see seam/textile.h): the flat contacts of each pair in order, as seam::pair makes
/// them, refined to the quality stage's bound and feature size when it runs.
template <class K>
void unify_contacts(std::vector<Mesh<K>>& meshes, const std::vector<Mesh<K>>& inputs, const std::vector<std::string>& names,
                    TextileResult<K>& result, std::vector<std::array<CurveVertices<K>, 2>>& pair_vertices,
                    const TextileOptions& options) {
  internal::FlatContactOptions contact;
  if (options.improve && result.stats.intersecting_pairs > 0) {
    const double scale = smallest_mean_edge<K>(inputs, result);
    const ImproveOptions io = quality_options(options, scale);
    contact.min_angle_deg = io.min_angle_deg;
    contact.max_area = io.max_area;
    contact.feature_size = internal::feature_size_of(io, io.tolerance, scale);
  }
  for (std::size_t p = 0; p < result.pairs.size(); ++p) {
    auto& pair = result.pairs[p];
    if (pair.curves.empty()) continue;
    const std::size_t a = pair.stats.a, b = pair.stats.b;
    internal::OtherCurveVertices<K> others;  // the two tows' curves with their other neighbours
    for (std::size_t q = 0; q < result.pairs.size(); ++q)
      for (std::size_t side = 0; side < 2 && q != p; ++side) {
        const std::size_t tow = side == 0 ? result.pairs[q].stats.a : result.pairs[q].stats.b;
        for (auto& vertices : pair_vertices[q][side]) {
          if (tow == a) others.a.push_back(&vertices);
          if (tow == b) others.b.push_back(&vertices);
        }
      }
    internal::FlatContactStats fc;
    try {
      fc = internal::unify_flat_contacts<K>(meshes[a], meshes[b], {pair.curves, pair_vertices[p][0], pair_vertices[p][1]},
                                            contact, others);
    } catch (const InternalError& e) {  // nothing was changed: the pair as it was (step 6 judges it)
      internal::append_note(result.stats.note, "the flat contacts of " + quoted(names[a]) + " and " + quoted(names[b]) +
                                                   " were left as they were (" + e.what() + ")");
      continue;
    }
    pair.stats.contact_patches = fc.patches;
    pair.stats.shared_faces = fc.shared_faces;
    pair.stats.contact_patches_left = fc.patches_left;
    if (fc.border_splits > 0) {
      pair.stats.curve_vertices = 0;
      for (const auto& c : pair.curves) pair.stats.curve_vertices += c.size() - (is_closed(c) ? 1 : 0);
    }
    const std::string of_pair = "the flat contacts of " + quoted(names[a]) + " and " + quoted(names[b]);
    if (fc.patches_left > 0) internal::append_note(result.stats.note, of_pair + ": " + fc.first_left);
    if (!fc.refinement_failed.empty()) internal::append_note(result.stats.note, of_pair + " not refined: " + fc.refinement_failed);
  }
  // The faces at every pair's curves as they are now (step 5 measures them again when it runs).
  for (std::size_t p = 0; p < result.pairs.size(); ++p) {
    auto& pair = result.pairs[p];
    if (pair.curves.empty()) continue;
    pair.stats.quality_a = curve_face_quality<K>(meshes[pair.stats.a], pair_vertices[p][0]);
    pair.stats.quality_b = curve_face_quality<K>(meshes[pair.stats.b], pair_vertices[p][1]);
  }
}

/// Step 5 (see seam/textile.h): the quality stage on every tow at once.
template <class K>
void improve_tows(std::vector<Mesh<K>>& meshes, const std::vector<Mesh<K>>& inputs, TextileResult<K>& result,
                  std::vector<std::array<CurveVertices<K>, 2>>& pair_vertices, const TextileOptions& options) {
  auto& st = result.stats;
  const auto t = Clock::now();
  std::vector<std::vector<double>> input_angles(meshes.size());
  std::vector<internal::ImproveMesh<K>> tows;
  for (std::size_t i = 0; i < meshes.size(); ++i) {
    input_angles[i] = internal::face_min_angles<K>(inputs[i]);
    tows.push_back({&meshes[i], &inputs[i], &input_angles[i]});
  }
  // Every curve of every pair, held by its two tows; where curves of two pairs run along the same
  // segments (a tow crossing a flat contact of two others), cut into pieces that share none.
  std::vector<internal::PairCurveRefs<K>> refs;
  for (std::size_t p = 0; p < result.pairs.size(); ++p)
    refs.push_back({result.pairs[p].stats.a, result.pairs[p].stats.b, &result.pairs[p].curves, &pair_vertices[p][0],
                    &pair_vertices[p][1]});
  internal::CurvePieces<K> pieces;
  try {
    pieces = internal::cut_into_pieces<K>(refs, meshes.size());
  } catch (const InternalError& e) {  // nothing changed yet: the tows go on without the stage
    internal::append_note(st.note, std::string("the quality stage was not run (") + e.what() + ")");
    return;
  }
  ImproveOptions io = quality_options(options, smallest_mean_edge<K>(inputs, result));
  // No new point closer to a vertex than the vertex separation seam check requires of a pair
  // (min_vertex_separation x the diagonal of the two tows), for the widest pair: so for every pair.
  double widest_pair = 0;
  for (const auto& pair : result.pairs)
    if (!pair.curves.empty())
      widest_pair = std::max(widest_pair, internal::bbox_diagonal<K>(inputs[pair.stats.a], inputs[pair.stats.b]));
  io.min_separation = std::max(io.min_separation, min_vertex_separation * widest_pair);
  st.improve_tolerance = io.tolerance;
  st.improve = internal::improve<K>(tows, pieces.shared, io);
  st.improved = true;
  internal::join_pieces<K>(pieces, refs);
  for (std::size_t p = 0; p < result.pairs.size(); ++p) {
    auto& pair = result.pairs[p];
    pair.stats.curve_vertices = 0;
    for (const auto& c : pair.curves) pair.stats.curve_vertices += c.size() - (is_closed(c) ? 1 : 0);
    pair.stats.quality_a = curve_face_quality<K>(meshes[pair.stats.a], pair_vertices[p][0]);
    pair.stats.quality_b = curve_face_quality<K>(meshes[pair.stats.b], pair_vertices[p][1]);
  }
  st.stage_seconds["improve"] = seconds_since(t);
}

/// Step 6: every pair with curves checked as written; the first failure in `problem`.
template <class K>
bool verify_pairs(const std::vector<Mesh<K>>& inputs, std::vector<Mesh<K>>& meshes, const std::vector<std::string>& names,
                  TextileResult<K>& result, double tolerance, std::string& problem) {
  for (auto& pair : result.pairs) {
    const std::size_t a = pair.stats.a, b = pair.stats.b;
    const CGAL::Bbox_3 box = CGAL::Polygon_mesh_processing::bbox(inputs[a]) + CGAL::Polygon_mesh_processing::bbox(inputs[b]);
    const double tol = std::max(tolerance, 1e-9 * internal::bbox_diagonal(box)) * (1 + 1e-9);
    PairCheckReport report;
    try {
      report = internal::check_as_written<K>(inputs[a], inputs[b], meshes[a], meshes[b], pair.curves, tol);
    } catch (const InternalError& e) {
      report.problems.push_back(e.what());
    }
    if (!report.ok()) {
      problem = quoted(names[a]) + " and " + quoted(names[b]) + ": " + report.problems.front();
      return false;
    }
    result.stats.verify_tolerance = std::max(result.stats.verify_tolerance, tol);
  }
  return true;
}

/// Steps 5 and 6, with the fallback of step 6.
template <class K>
void improve_and_verify(std::vector<Mesh<K>>& meshes, const std::vector<Mesh<K>>& inputs,
                        const std::vector<std::string>& names, TextileResult<K>& result,
                        std::vector<std::array<CurveVertices<K>, 2>>& pair_vertices, const std::vector<double>& snap_tol,
                        const TextileOptions& options) {
  auto& st = result.stats;
  // The snapping's and the closing's moves, and how far the closing may move the intersection.
  const double snapped = (snap_tol.empty() ? 0.0 : *std::max_element(snap_tol.begin(), snap_tol.end())) +
                         st.max_close_move;
  const double closed = st.close_tolerance;
  const bool improve = options.improve && st.intersecting_pairs > 0;
  std::optional<std::pair<std::vector<Mesh<K>>, std::vector<TextilePair<K>>>> before;
  std::string improve_failed;
  if (improve) {
    if (options.verify_output) before.emplace(meshes, result.pairs);
    try {
      improve_tows<K>(meshes, inputs, result, pair_vertices, options);
    } catch (const InternalError& e) {  // verified as without it, below
      if (!before) throw;
      improve_failed = e.what();
    }
  }
  if (!options.verify_output) return;
  const auto t = Clock::now();
  std::string problem = improve_failed;
  st.verified = improve_failed.empty() && verify_pairs<K>(inputs, meshes, names, result,
                                                          snapped + std::max(st.improve_tolerance, closed), problem);
  if (!st.verified && before) {
    const std::string improved_problem = problem;
    meshes = std::move(before->first);
    result.pairs = std::move(before->second);
    st.verify_tolerance = 0;
    st.verified = verify_pairs<K>(inputs, meshes, names, result, snapped + closed, problem);
    if (st.verified)
      internal::append_note(st.note, (improve_failed.empty() ? "the quality stage's result failed seam check's tests ("
                                                              : "the quality stage failed (") +
                                         improved_problem + "): the tows before it are given");
    else problem = improved_problem + "; without the quality stage: " + problem;
  }
  st.stage_seconds["verify"] = seconds_since(t);
  if (!st.verified) throw InternalError("textile: the outputs fail seam check's tests, so none is given (" + problem + ")");
}
/// One run of seam::textile: the stages in order, each a method, sharing the tows, their plain
/// copies and the per-pair work.
template <class K> class TextileRun {
 public:
  using Point = typename K::Point_3;
  using Box = CGAL::Box_intersection_d::Box_with_info_d<double, 3, std::size_t>;

  TextileRun(std::vector<Mesh<K>>& meshes, const std::vector<std::string>& names, const TextileOptions& options)
      : meshes_(meshes),
        names_(names),
        options_(options),
        t_start_(Clock::now()),
        t_stage_(t_start_),
        arena_(options.threads > 0 ? options.threads : tbb::task_arena::automatic),
        snap_tol_(meshes.size(), 0.0),
        snapped_(meshes.size(), 0),
        snaps_refused_(meshes.size(), 0),
        provenance_(meshes.size()),
        pairs_of_(meshes.size()) {}

  TextileResult<K> run() {
    TextileStats& st = result_.stats;
    st.tows = meshes_.size();
    st.threads = arena_.max_concurrency();
    timed("prepare", [&] { prepare(); });
    timed("boxes", [&] { find_candidate_pairs(); });
    timed("pairs", [&] {
      std::vector<std::size_t> all_pairs(candidates_.size());
      for (std::size_t p = 0; p < all_pairs.size(); ++p) all_pairs[p] = p;
      compute_pairs(all_pairs, "pairs");
    });
    find_pairs_of();
    timed("snap", [&] { snap(); });
    timed("close", [&] { close_thin_features(); });
    timed("triples", [&] { make_triple_points_vertices(); });
    timed("tows", [&] { embed_tows(); });
    std::vector<std::array<std::vector<std::vector<typename Mesh<K>::Vertex_index>>, 2>> pair_vertices;
    timed("compare", [&] { pair_vertices = compare_pairs(); });
    timed("contact_points", [&] { make_contact_points_vertices(pair_vertices); });
    std::vector<FrozenMesh<K>>().swap(frozen_);
    timed("flat_contacts", [&] { unify_contacts<K>(meshes_, inputs_, names_, result_, pair_vertices, options_); });
    improve_and_verify<K>(meshes_, inputs_, names_, result_, pair_vertices, snap_tol_, options_);
    return std::move(result_);
  }

 private:
  template <class Stage> void timed(const char* name, Stage&& stage) {
    const auto t = Clock::now();
    stage();
    result_.stats.stage_seconds[name] = seconds_since(t);
  }

  void report(const char* stage, std::size_t done, std::size_t total) {
    if (!options_.progress) return;
    std::lock_guard<std::mutex> lock(progress_mutex_);
    options_.progress(TextileProgress{stage, done, total, seconds_since(t_start_), seconds_since(t_stage_)});
  }

  /// Plain copies of the meshes for the pair tasks, and the input tows for steps 5 and 6 (built
  /// from the plain copies: no lazy value is shared with the tows the tasks change).
  void prepare() {
    frozen_.resize(meshes_.size());
    for (std::size_t i = 0; i < meshes_.size(); ++i) {
      if (meshes_[i].has_garbage()) meshes_[i].collect_garbage();
      frozen_[i] = freeze<K>(meshes_[i]);
    }
    if (options_.improve || options_.verify_output)
      for (const auto& f : frozen_) inputs_.push_back(thaw<K>(f));
  }

  /// Candidate pairs: overlapping bounding boxes (closed boxes: touching counts).
  void find_candidate_pairs() {
    std::vector<Box> boxes;
    for (std::size_t i = 0; i < meshes_.size(); ++i) boxes.emplace_back(frozen_[i].bbox, i);
    CGAL::box_self_intersection_d(boxes.begin(), boxes.end(), [&](const Box& x, const Box& y) {
      candidates_.emplace_back(std::min(x.info(), y.info()), std::max(x.info(), y.info()));
    });
    std::sort(candidates_.begin(), candidates_.end());
    candidates_.erase(std::unique(candidates_.begin(), candidates_.end()), candidates_.end());
    result_.stats.candidate_pairs = candidates_.size();
    work_.resize(candidates_.size());
  }

  /// The intersection curves of the candidate pairs `which`, concurrently.
  void compute_pairs(const std::vector<std::size_t>& which, const char* stage) {
    std::size_t done = 0;
    t_stage_ = Clock::now();
    for_each_index(
        arena_, which.size(), [&](std::size_t k) { compute_pair(which[k]); },
        [&](std::size_t) { report(stage, ++done, which.size()); });
  }

  void compute_pair(std::size_t p) {
    auto& w = work_[p];
    w = PairWork<K>();
    w.a = candidates_[p].first;
    w.b = candidates_[p].second;
    const auto tp = Clock::now();
    std::vector<Polyline<K>> curves;
    {
      // Each tow cut to the faces that can meet the other (bounding boxes): the same curves, a
      // fraction of the work.
      const Mesh<K> a = thaw<K>(frozen_[w.a], &frozen_[w.b].bbox), b = thaw<K>(frozen_[w.b], &frozen_[w.a].bbox);
      w.stats.copy_seconds += seconds_since(tp);
      auto found = internal::compute_intersection_curves<K>(a, b);
      curves = std::move(found.curves);
      w.stats.touching_only = curves.empty() && found.touching_points > 0;
      for (const auto& c : found.contacts) w.contacts.push_back(detached<K>(c));
    }
    w.stats.a = w.a;
    w.stats.b = w.b;
    w.stats.curves = curves.size();
    for (const auto& c : curves) {
      w.stats.closed_curves += is_closed(c) ? 1 : 0;
      w.stats.curve_vertices += is_closed(c) ? c.size() - 1 : c.size();
    }
    w.for_a = detached<K>(curves);
    w.for_b = detached<K>(curves);
    w.stats.intersect_seconds += seconds_since(tp);
  }

  /// Each tow's pairs (with curves), in pair order.
  void find_pairs_of() {
    for (auto& v : pairs_of_) v.clear();
    for (std::size_t p = 0; p < work_.size(); ++p)
      if (!work_[p].for_a.empty()) {
        pairs_of_[work_[p].a].push_back(p);
        pairs_of_[work_[p].b].push_back(p);
      }
  }
  std::vector<Polyline<K>>& curves_for(std::size_t p, std::size_t tow) {
    return work_[p].a == tow ? work_[p].for_a : work_[p].for_b;
  }
  std::size_t other(std::size_t p, std::size_t tow) const { return work_[p].a == tow ? work_[p].b : work_[p].a; }

  /// The curves of the pairs touching a changed tow computed again.
  void recompute_pairs_of(const std::vector<char>& changed, const char* stage) {
    std::vector<std::size_t> again;
    for (std::size_t tow = 0; tow < meshes_.size(); ++tow)
      if (changed[tow]) frozen_[tow] = freeze<K>(meshes_[tow]);
    for (std::size_t p = 0; p < candidates_.size(); ++p)
      if (changed[candidates_[p].first] || changed[candidates_[p].second]) again.push_back(p);
    if (again.empty()) return;
    compute_pairs(again, stage);
    find_pairs_of();
  }

  /// Snapping: each tow against all its curves at once, then every curve of a moved tow again.
  /// Rounded kernels: no automatic snapping (a snapped vertex lies exactly on the other tow, a
  /// degeneracy only the exact kernel copes with; their curve points are doubles already).
  void snap() {
    const auto& embed = options_.embed;
    if (!(embed.snap_tol > 0 || (embed.snap_tol < 0 && kernel_traits<K>::exact_constructions))) return;
    for (std::size_t tow = 0; tow < meshes_.size(); ++tow) {
      if (embed.snap_tol > 0) {
        snap_tol_[tow] = embed.snap_tol;
        continue;
      }
      double d = internal::bbox_diagonal(frozen_[tow].bbox);
      for (std::size_t p : pairs_of_[tow]) d = std::min(d, internal::bbox_diagonal(frozen_[other(p, tow)].bbox));
      snap_tol_[tow] = 1e-10 * d;
    }
    for_each_index(
        arena_, meshes_.size(),
        [&](std::size_t tow) {
          if (pairs_of_[tow].empty()) return;
          std::vector<Polyline<K>> curves;
          for (std::size_t p : pairs_of_[tow]) {
            const auto& mine = curves_for(p, tow);
            curves.insert(curves.end(), mine.begin(), mine.end());
          }
          const auto r = internal::snap_vertices_to_segments<K>(meshes_[tow], curves, snap_tol_[tow]);
          snapped_[tow] = r.snapped;
          snaps_refused_[tow] = r.refused;
        },
        [](std::size_t) {});
    std::vector<char> changed(meshes_.size(), 0);
    for (std::size_t tow = 0; tow < meshes_.size(); ++tow) changed[tow] = snapped_[tow] > 0;
    recompute_pairs_of(changed, "pairs (after snapping)");
  }

  /// Step 2c: features thinner than the vertex separation closed, as seam::pair's stage 1 does
  /// (internal::crowded_curve_points). A curve point with a vertex or another curve point closer
  /// than the pair's separation (min_vertex_separation x the diagonal of its two tows) would be
  /// a pair of vertices too close once embedded (check 5; a volume mesher takes them for one),
  /// and a crossing that thin cannot be written in doubles. The curve points of every pair of
  /// either tow count (a curve of the tow with a third one passing that close is as thin). The
  /// vertices of both tows within the separation of such a point move onto the pair's curve
  /// (exactly), unless the move would tilt a flat contact or take a part of the pair's
  /// intersection farther than close_tolerance() (see snap_vertices_to_segments); then every pair
  /// of a moved tow is computed again. In rounds: a round takes the pairs with such points whose
  /// tows no other pair of the round has (their curves are those of the tows as they are), each
  /// pair at most once, so the rounds end. Exact kernel only, as the snapping above (a vertex
  /// closed lies exactly on the other tow).
  void close_thin_features() {
    if (!kernel_traits<K>::exact_constructions) return;
    auto& st = result_.stats;
    const double tolerance = close_tolerance();
    std::vector<char> done(work_.size(), 0);
    for (bool any = true; any;) {
      any = false;
      std::vector<char> changed(meshes_.size(), 0), busy(meshes_.size(), 0);
      for (std::size_t p = 0; p < work_.size(); ++p) {
        const auto& w = work_[p];
        if (done[p] || (w.for_a.empty() && w.contacts.empty()) || busy[w.a] || busy[w.b]) continue;
        const double separation =
            min_vertex_separation * internal::bbox_diagonal(frozen_[w.a].bbox + frozen_[w.b].bbox);
        // The pair's isolated points of contact count as curves of one point: a vertex that close
        // to one moves onto it (else the two would be a pair of vertices too close once made one).
        std::vector<Polyline<K>> with_contacts = curves_of_tows(w.a, w.b);
        for (const auto& q : work_)
          if (q.a == w.a || q.b == w.a || q.a == w.b || q.b == w.b)
            for (const auto& c : q.contacts) with_contacts.push_back({c});
        const auto crowded = internal::crowded_curve_points<K>(with_contacts, meshes_[w.a], meshes_[w.b], separation);
        if (crowded.empty()) continue;
        done[p] = busy[w.a] = busy[w.b] = 1;
        any = true;  // (another round for the pairs this one skipped as busy; each pair runs once)
        for (const auto& [tow, partner] : {std::pair{w.a, w.b}, std::pair{w.b, w.a}}) {
          std::vector<Polyline<K>> targets = curves_for(p, tow);
          for (const auto& c : work_[p].contacts) targets.push_back({detached<K>(c)});  // (each tow its own copy)
          const auto r = internal::snap_vertices_to_segments<K>(meshes_[tow], targets, separation, false, true,
                                                               &meshes_[partner], &crowded, tolerance);
          st.vertices_closed += r.snapped;
          st.max_close_move = std::max(st.max_close_move, r.max_move);
          changed[tow] = changed[tow] || r.snapped > 0;
        }
      }
      recompute_pairs_of(changed, "pairs (after closing)");
    }
    if (st.vertices_closed > 0) st.close_tolerance = tolerance;
  }

  /// The curves of every pair of tow a or b, each pair once (its copy for a, or else for b).
  std::vector<Polyline<K>> curves_of_tows(std::size_t a, std::size_t b) {
    std::vector<Polyline<K>> all;
    for (const std::size_t tow : {a, b})
      for (const std::size_t p : pairs_of_[tow]) {
        if (tow == b && (work_[p].a == a || work_[p].b == a)) continue;  // (a pair of a and b: taken with a)
        const auto& mine = curves_for(p, tow);
        all.insert(all.end(), mine.begin(), mine.end());
      }
    return all;
  }

  /// How far step 2c may move a part of a pair's intersection: the quality stage's tolerance
  /// (quality_options: automatic, a tenth of the smallest mean edge length of the tows in a pair
  /// with curves), whether or not that stage runs.
  double close_tolerance() const {
    std::vector<std::pair<std::size_t, std::size_t>> pairs;
    for (const auto& w : work_)
      if (!w.for_a.empty() || !w.contacts.empty()) pairs.emplace_back(w.a, w.b);
    if (pairs.empty()) return 0;
    return quality_options(options_, smallest_mean_edge<K>(inputs_.empty() ? meshes_ : inputs_, pairs)).tolerance;
  }

  /// Where the curves of two pairs of one tow meet (segments of each that intersect).
  struct Meeting {
    bool found = false, point = false;
    bool along = false;  // an end of an overlap along a segment: made a vertex of this tow only
    std::size_t p = 0, q = 0;  // the two pairs whose curves meet
    Point at;
    Point middle;  // along: the middle of the overlap
  };

  /// The three tows of a meeting on `tow`: that tow, then the other tow of each pair.
  std::array<std::size_t, 3> tows_of(std::size_t tow, const Meeting& m) const {
    return {tow, other(m.p, tow), other(m.q, tow)};
  }

  [[noreturn]] void refuse(std::size_t tow, const Meeting& m, const char* why) const {
    const std::size_t j = other(m.p, tow), k = other(m.q, tow);
    std::set<std::size_t> three{tow, j, k};
    std::ostringstream msg;
    msg << "tows";
    std::size_t n = 0;
    for (std::size_t x : three) msg << (n++ == 0 ? " " : n == 3 ? " and " : ", ") << quoted(names_[x]);
    const auto at = to_filtered(m.at);
    msg << " overlap in one place (triple overlap): the curves of " << quoted(names_[tow]) << " with "
        << quoted(names_[j]) << " and with " << quoted(names_[k]) << " meet on " << quoted(names_[tow]) << " near ("
        << at.x() << ", " << at.y() << ", " << at.z() << "); " << why;
    throw InvalidInput(msg.str());
  }

  /// The meetings of the curves of different pairs on `tow` (a meeting along a segment ends the
  /// list: it is refused).
  std::vector<Meeting> meetings_on(std::size_t tow) {
    std::vector<Meeting> meetings;
    std::vector<std::size_t> touching;  // the pairs of this tow with isolated points of contact
    for (std::size_t p = 0; p < work_.size(); ++p)
      if ((work_[p].a == tow || work_[p].b == tow) && !work_[p].contacts.empty()) touching.push_back(p);
    if (pairs_of_[tow].empty() || pairs_of_[tow].size() + touching.size() < 2) return meetings;
    struct Seg {
      std::size_t pair;
      const Point *p, *q;
    };
    std::vector<Seg> segs;
    for (std::size_t p : pairs_of_[tow])
      for (const auto& c : curves_for(p, tow))
        for (std::size_t i = 0; i + 1 < c.size(); ++i) segs.push_back({p, &c[i], &c[i + 1]});
    std::vector<Box> sboxes;
    sboxes.reserve(segs.size());
    for (std::size_t s = 0; s < segs.size(); ++s) sboxes.emplace_back(segs[s].p->bbox() + segs[s].q->bbox(), s);
    std::vector<std::pair<std::size_t, std::size_t>> hits;
    // Whether a point is (exactly) a vertex of this tow: its vertices sorted, when first asked.
    auto less = [](const Point& x, const Point& y) { return CGAL::compare_xyz(x, y) == CGAL::SMALLER; };
    std::vector<Point> vertices;
    auto is_vertex = [&](const Point& x) {
      if (vertices.empty()) {
        for (auto v : meshes_[tow].vertices()) vertices.push_back(meshes_[tow].point(v));
        std::sort(vertices.begin(), vertices.end(), less);
      }
      return std::binary_search(vertices.begin(), vertices.end(), x, less);
    };
    CGAL::box_self_intersection_d(sboxes.begin(), sboxes.end(), [&](const Box& x, const Box& y) {
      const Seg &u = segs[x.info()], &v = segs[y.info()];
      if (u.pair == v.pair) return;
      if (!CGAL::do_intersect(typename K::Segment_3(*u.p, *u.q), typename K::Segment_3(*v.p, *v.q))) return;
      // Allowed: two curves through a common end point that is a vertex of this tow (a triple
      // point made a vertex below), not overlapping.
      const Point* common = *u.p == *v.p || *u.p == *v.q ? u.p : *u.q == *v.p || *u.q == *v.q ? u.q : nullptr;
      const bool collinear = CGAL::collinear(*u.p, *u.q, *v.p) && CGAL::collinear(*u.p, *u.q, *v.q);
      if (common && is_vertex(*common)) {
        const Point& u_end = common == u.p ? *u.q : *u.p;
        const Point& v_end = *common == *v.p ? *v.q : *v.p;
        const bool overlap = collinear && (typename K::Segment_3(*v.p, *v.q).has_on(u_end) ||
                                           typename K::Segment_3(*u.p, *u.q).has_on(v_end));
        if (!overlap) return;
      }
      // Allowed too: one segment of both curves, between two vertices of this tow (where the tow
      // crosses an area over which the other two coincide; made so below).
      const bool same = (*u.p == *v.p && *u.q == *v.q) || (*u.p == *v.q && *u.q == *v.p);
      if (same && is_vertex(*u.p) && is_vertex(*u.q)) return;
      hits.emplace_back(std::min(x.info(), y.info()), std::max(x.info(), y.info()));
    });
    std::sort(hits.begin(), hits.end());  // deterministic, whatever the order found
    // A point where two tows touch inside a curve segment of one of them with a third: it lies on
    // the three surfaces too (step 4a would split that segment in one tow only).
    for (const std::size_t p : touching)
      for (const Point& c : work_[p].contacts)
        for (const Seg& u : segs)
          if (u.pair != p && CGAL::do_overlap(c.bbox(), u.p->bbox() + u.q->bbox()) && c != *u.p && c != *u.q &&
              typename K::Segment_3(*u.p, *u.q).has_on(c)) {
            Meeting m;
            m.found = m.point = true;
            m.p = std::min(p, u.pair);
            m.q = std::max(p, u.pair);
            m.at = detached<K>(c);
            meetings.push_back(m);
          }
    for (const auto& [x, y] : hits) {
      const Seg &u = segs[x], &v = segs[y];
      Meeting m;
      m.found = true;
      m.p = std::min(u.pair, v.pair);
      m.q = std::max(u.pair, v.pair);
      m.at = *u.p;
      const typename K::Segment_3 su(*u.p, *u.q), sv(*v.p, *v.q);
      const auto i = CGAL::intersection(su, sv);
      if (i)
        if (const Point* point = boost::get<Point>(&*i)) {
          m.point = true;
          m.at = detached<K>(*point);
        }
      if (!m.point && kernel_traits<K>::exact_constructions) {
        // An overlap along a segment: the two curves run together over an area where the two
        // other tows coincide (their surfaces are one there, so every point of either curve on
        // it lies on the three surfaces). Every end of the two segments on the overlap becomes a
        // vertex of this tow; the curves, computed again, then both pass through all of them.
        // (Where this tow crosses a planar contact, its new edges from such a point meet the
        // common plane at that point only, and one round does it; where the contact bends inside
        // one of its faces, or the tow lies in the plane, more rounds may follow: at most 4.)
        m.point = m.along = true;
        if (const auto* overlap = i ? boost::get<typename K::Segment_3>(&*i) : nullptr)
          m.middle = detached<K>(CGAL::midpoint(overlap->source(), overlap->target()));
        bool pushed = false;
        for (const Point* end : {u.p, u.q, v.p, v.q})
          if (su.has_on(*end) && sv.has_on(*end) && !is_vertex(*end)) {
            m.at = detached<K>(*end);
            meetings.push_back(m);
            pushed = true;
          }
        if (pushed) continue;
        m.point = m.along = false;  // every end a vertex already, and still two different segments: refused
      }
      meetings.push_back(m);
      if (!m.point) break;  // refused
    }
    return meetings;
  }

  /// Whether `at` lies on a curve (or is a point of contact) of tows `j` and `k`. A meeting point
  /// of two curves on a third tow lies on both surfaces; where it lies on no curve of theirs (as
  /// inside an area over which they coincide, a flat contact), no curve of theirs needs it as a
  /// vertex, and it is a point of their curves with the third tow, which their embeddings make
  /// vertices. In a flat contact a vertex of one would only cut the other's coplanar faces at new
  /// points.
  bool on_curve_of(std::size_t j, std::size_t k, const Point& at) {
    const CGAL::Bbox_3 box = at.bbox();
    for (std::size_t r = 0; r < work_.size(); ++r) {
      if (std::minmax(work_[r].a, work_[r].b) != std::minmax(j, k)) continue;
      for (const auto& c : curves_for(r, j)) {
        if (c.size() == 1 && c.front() == at) return true;
        for (std::size_t i = 0; i + 1 < c.size(); ++i)
          if (CGAL::do_overlap(box, c[i].bbox() + c[i + 1].bbox()) && typename K::Segment_3(c[i], c[i + 1]).has_on(at))
            return true;
      }
      for (const Point& c : work_[r].contacts)
        if (c == at) return true;
    }
    return false;
  }

  /// Triple overlaps: where the curves of two neighbours meet on a tow, three tows overlap in one
  /// place. Under the exact kernel the meeting point becomes a vertex of all three tows (it lies
  /// exactly on the three surfaces, so inserting it changes no surface), and their curves are
  /// then computed again: they all pass through that vertex, which every embedding shares
  /// (inside a flat contact of the two others, a vertex of this tow only: see on_curve_of). Where
  /// the curves overlap along a segment, the ends on the overlap become vertices of this tow
  /// (meetings_on). Under the rounded kernels the run stops naming the three tows.
  void make_triple_points_vertices() {
    std::vector<std::pair<std::size_t, Meeting>> flat_points;  // (tow, meeting) made a vertex of that tow only
    for (int round = 0;; ++round) {
      std::vector<std::vector<Meeting>> meetings(meshes_.size());
      for_each_index(
          arena_, meshes_.size(), [&](std::size_t tow) { meetings[tow] = meetings_on(tow); }, [](std::size_t) {});
      std::vector<char> modified(meshes_.size(), 0);
      // Per tow, the points that may become its vertices in this round (each meeting's point, in
      // each of its three tows), and a lookup of the faces that may hold them, made before the
      // tow's first insertion of the round.
      std::vector<std::vector<Point>> queries(meshes_.size());
      std::vector<std::vector<std::array<std::size_t, 3>>> query_of(meshes_.size());
      for (std::size_t tow = 0; tow < meshes_.size(); ++tow)
        for (const Meeting& m : meetings[tow]) {
          auto& q = query_of[tow].emplace_back();
          const auto three_tows = tows_of(tow, m);
          for (std::size_t k = 0; k < 3; ++k) {
            q[k] = queries[three_tows[k]].size();
            queries[three_tows[k]].push_back(m.at);
          }
        }
      std::vector<std::unique_ptr<FaceLookup<K>>> lookups(meshes_.size());
      bool any = false;
      for (std::size_t tow = 0; tow < meshes_.size(); ++tow)
        for (std::size_t i = 0; i < meetings[tow].size(); ++i) {
          const Meeting& m = meetings[tow][i];
          any = true;
          if (!kernel_traits<K>::exact_constructions)
            refuse(tow, m, "only the exact kernel makes such a point a vertex of the three tows: use --kernel exact");
          if (!m.point)
            refuse(tow, m,
                   "the curves overlap along a segment there as two different segments between vertices of this "
                   "tow: seam textile cannot embed that");
          if (round >= 4)
            refuse(tow, m,
                   m.along ? "the curves still run together after 4 rounds of making their points vertices (as where "
                             "this tow coincides with the other two over an area): seam textile cannot embed that"
                           : "making the meeting points vertices of the three tows did not end");
          // An overlap along a curve of the other two as well: three curves along one segment
          // (the three tows coincide over an area there, or meet along a line). This tow may then
          // lie in their common plane, and its new vertices would cut their faces at new points.
          if (m.along && on_curve_of(other(m.p, tow), other(m.q, tow), m.middle))
            refuse(tow, m,
                   "the curves of the three pairs run along one segment there (as where the three tows coincide "
                   "over an area): seam textile cannot embed that");
          bool inserted = false, known = false;
          const bool three = !m.along && on_curve_of(other(m.p, tow), other(m.q, tow), m.at);
          const auto three_tows = tows_of(tow, m);
          for (std::size_t k = 0; k < 3; ++k) {
            const std::size_t x = three_tows[k];
            if (!three && x != tow) continue;
            const auto point = detached<K>(m.at);
            if (!lookups[x]) lookups[x] = std::make_unique<FaceLookup<K>>(meshes_[x], queries[x]);
            FaceLookup<K>& lookup = *lookups[x];
            auto before = [&] { provenance_[x].start<K>(meshes_[x]); };
            auto added = [&](std::size_t first, std::size_t count, std::size_t from) {
              provenance_[x].added(first, first + count, from);
              lookup.added(first, count, from);
            };
            if (insert_vertex<K>(meshes_[x], point, lookup.faces_for(query_of[tow][i][k]), before, added)) {
              modified[x] = inserted = true;
            } else {
              known = known || modified[x];  // made a vertex in this round already (seen from another tow)
            }
          }
          if (!inserted && !known) refuse(tow, m, "seam textile could not make that point a vertex of the three tows");
          if (inserted) ++(three ? result_.stats.triple_points : result_.stats.flat_crossing_points);
          if (inserted && !three) flat_points.push_back({tow, m});
        }
      if (!any) break;
      recompute_pairs_of(modified, "pairs (triple points)");
    }
    refuse_crowded_flat_crossings(flat_points);
  }

  /// Points made vertices of one crossing tow only (a flat crossing) come from edges of two tows
  /// that coincide there; where those edges cross it almost at one place, two such points lie
  /// closer than the vertex separation (seam check's, for the pairs of the meeting), which no
  /// later step moves apart: the run stops naming the three tows (as the meeting they came from).
  void refuse_crowded_flat_crossings(const std::vector<std::pair<std::size_t, Meeting>>& flat_points) {
    std::vector<std::vector<std::pair<std::size_t, Meeting>>> by_tow(meshes_.size());
    for (const auto& fp : flat_points) by_tow[fp.first].push_back(fp);
    for (std::size_t tow = 0; tow < meshes_.size(); ++tow) {
      if (by_tow[tow].empty()) continue;
      const Mesh<K>& mesh = meshes_[tow];
      std::vector<std::pair<std::array<double, 3>, typename Mesh<K>::Vertex_index>> vertices;
      for (auto v : mesh.vertices()) {
        const auto q = to_filtered(mesh.point(v));
        vertices.push_back({{q.x(), q.y(), q.z()}, v});
      }
      std::sort(vertices.begin(), vertices.end(),
                [](const auto& x, const auto& y) { return x.first[0] < y.first[0]; });
      for (const auto& [t, m] : by_tow[tow]) {
        const double separation =
            min_vertex_separation *
            std::max(internal::bbox_diagonal(frozen_[tow].bbox + frozen_[other(m.p, tow)].bbox),
                     internal::bbox_diagonal(frozen_[tow].bbox + frozen_[other(m.q, tow)].bbox));
        const auto a = to_filtered(m.at);
        auto it = std::lower_bound(vertices.begin(), vertices.end(), a.x() - separation,
                                   [](const auto& x, double value) { return x.first[0] < value; });
        for (; it != vertices.end() && it->first[0] <= a.x() + separation; ++it) {
          const double dx = it->first[0] - a.x(), dy = it->first[1] - a.y(), dz = it->first[2] - a.z();
          if (dx * dx + dy * dy + dz * dz >= separation * separation || mesh.point(it->second) == m.at) continue;
          refuse(tow, m,
                 internal::say("the curves run together there, and two of their points (where edges of the other "
                               "two cross it) lie ", std::sqrt(dx * dx + dy * dy + dz * dz),
                               " apart, closer than the vertex separation ", separation,
                               ": seam textile cannot embed that")
                     .c_str());
        }
      }
    }
  }

  /// Tows: each receives all its curves in one embedding, concurrently.
  void embed_tows() {
    t_stage_ = Clock::now();
    EmbedOptions eo = options_.embed;
    eo.snap_tol = 0;
    eo.keep_all_nodes = true;  // every curve point lies on the surface and is a crossing point
    eo.curve_tol = 0;
    eo.max_distance = std::numeric_limits<double>::max();
    result_.tows.resize(meshes_.size());
    std::size_t tows_done = 0;
    if (eo.max_area > 0) {
      // Under an area bound every Steiner point is kept: one tow after the other, each point kept
      // at least the vertex separation (of the whole cell: at least each pair's) from every vertex
      // of every tow, every curve point and the Steiner points before it (see seam::pair).
      CGAL::Bbox_3 cell;
      for (const auto& m : meshes_) cell += CGAL::Polygon_mesh_processing::bbox(m);
      internal::KeepAway away(min_vertex_separation * internal::bbox_diagonal(cell));
      for (const auto& m : meshes_) away.add_vertices<K>(m);
      for (std::size_t p = 0; p < work_.size(); ++p)
        for (const std::size_t tow : {work_[p].a, work_[p].b}) away.add_points<K>(curves_for(p, tow));
      // ... and from the surfaces of the tows it meets (see KeepAway::set_surfaces).
      std::vector<std::unique_ptr<internal::InputSurface>> surfaces;
      for (const auto& m : meshes_) surfaces.push_back(internal::input_surface<K>(m));
      for (std::size_t tow = 0; tow < meshes_.size(); ++tow) {
        std::vector<const internal::InputSurface*> partners;
        for (const std::size_t p : pairs_of_[tow]) partners.push_back(surfaces[other(p, tow)].get());
        away.set_surfaces(partners);
        embed_tow(tow, eo, &away);
        report("tows", ++tows_done, meshes_.size());
      }
      return;
    }
    for_each_index(
        arena_, meshes_.size(), [&](std::size_t tow) { embed_tow(tow, eo, nullptr); },
        [&](std::size_t) { report("tows", ++tows_done, meshes_.size()); });
  }

  void embed_tow(std::size_t tow, const EmbedOptions& eo, internal::KeepAway* keep_away) {
    std::vector<Polyline<K>> curves;
    std::vector<std::size_t> first_curve;  // per pair of this tow, index of its first curve
    for (std::size_t p : pairs_of_[tow]) {
      first_curve.push_back(curves.size());
      auto& mine = curves_for(p, tow);
      curves.insert(curves.end(), mine.begin(), mine.end());
    }
    first_curve.push_back(curves.size());
    Mesh<K>& mesh = meshes_[tow];
    EmbedResult<K> r;
    try {
      r = keep_away ? internal::embed_with_known_sites<K>(mesh, curves, eo, nullptr, keep_away) : embed<K>(mesh, curves, eo);
    } catch (const InvalidInput& e) {
      throw InvalidInput("tow " + quoted(names_[tow]) + ": " + e.what());
    } catch (const InternalError& e) {
      // Under a rounded kernel, curves of two neighbours that meet within rounding are not
      // detected above and make the re-triangulation fail here.
      throw InternalError("tow " + quoted(names_[tow]) + ": " + e.what() +
                          (pairs_of_[tow].size() > 1 && !kernel_traits<K>::exact_constructions
                               ? " (the curves of two neighbours may meet: use --kernel exact)"
                               : ""));
    }
    if (!provenance_[tow].origin.empty()) provenance_[tow].template apply<K>(mesh, r.stats);
    if (r.curves.size() != curves.size() || r.curve_vertices.size() != curves.size())
      throw InternalError("textile: " + names_[tow] + ": the embedding returned a different number of curves");
    for (auto& c : r.curves)
      for (auto& p : c) make_exact(p);  // written by two tows: the same tight approximation in both
    for (std::size_t k = 0; k < pairs_of_[tow].size(); ++k) {
      auto& w = work_[pairs_of_[tow][k]];
      std::vector<Polyline<K>> embedded(r.curves.begin() + std::ptrdiff_t(first_curve[k]),
                                        r.curves.begin() + std::ptrdiff_t(first_curve[k + 1]));
      std::vector<std::vector<typename Mesh<K>::Vertex_index>> vertices(
          r.curve_vertices.begin() + std::ptrdiff_t(first_curve[k]),
          r.curve_vertices.begin() + std::ptrdiff_t(first_curve[k + 1]));
      const CurveFaceQuality q = curve_face_quality<K>(mesh, vertices);
      (w.a == tow ? w.vertices_a : w.vertices_b) = std::move(vertices);
      if (w.a == tow) {
        w.embedded_a = std::move(embedded);
        w.stats.quality_a = q;
      } else {
        w.embedded_b = std::move(embedded);
        w.stats.quality_b = q;
      }
    }
    result_.tows[tow] = r.stats;
    result_.tows[tow].snap_tol = snap_tol_[tow];
    result_.tows[tow].vertices_snapped = snapped_[tow];
    result_.tows[tow].snaps_refused = snaps_refused_[tow];
    // The curves handed to this tow are no longer needed: free them in the thread that used them.
    for (std::size_t p : pairs_of_[tow]) std::vector<Polyline<K>>().swap(curves_for(p, tow));
  }

  /// Both tows of every pair received the identical curves; the pairs with curves (or touching)
  /// go to the result, and each one's curve vertices in its two tows are returned.
  std::vector<std::array<std::vector<std::vector<typename Mesh<K>::Vertex_index>>, 2>> compare_pairs() {
    std::vector<std::array<std::vector<std::vector<typename Mesh<K>::Vertex_index>>, 2>> pair_vertices;
    for (auto& w : work_) {
      if (w.stats.curves == 0 && !w.stats.touching_only) continue;
      if (w.embedded_a != w.embedded_b) {
        std::ostringstream msg;
        msg << "textile: the curves of " << names_[w.a] << " and " << names_[w.b]
            << " were embedded differently into the two tows";
        throw InternalError(msg.str());
      }
      TextilePair<K> pair;
      pair.curves = std::move(w.embedded_a);
      pair.stats = w.stats;
      if (pair.stats.curves > 0) ++result_.stats.intersecting_pairs;
      if (pair.stats.touching_only) ++result_.stats.touching_pairs;
      result_.pairs.push_back(std::move(pair));
      pair_vertices.push_back({std::move(w.vertices_a), std::move(w.vertices_b)});
      contacts_.push_back(std::move(w.contacts));
    }
    return pair_vertices;
  }

  /// Step 4a: each pair's isolated points of contact (a vertex of one tow on the other, and no
  /// curve through it) made a vertex of both tows and a curve of one point, as seam::pair does
  /// (internal/contact_points.h): the outputs then meet in a common vertex there, which seam check
  /// requires. The surfaces are unchanged (each point lies exactly on both). A point that lies on
  /// no face exactly (rounded kernels) is left out with a note; the verification then names it.
  void make_contact_points_vertices(std::vector<std::array<CurveVertices<K>, 2>>& pair_vertices) {
    for (std::size_t p = 0; p < result_.pairs.size(); ++p) {
      const auto& contacts = contacts_[p];
      if (contacts.empty()) continue;
      auto& pair = result_.pairs[p];
      const std::size_t a = pair.stats.a, b = pair.stats.b;
      std::vector<typename Mesh<K>::Vertex_index> va, vb;
      if (!internal::insert_points<K>(meshes_[a], meshes_[b], contacts, va, vb)) {
        internal::append_note(result_.stats.note, internal::say("the ", contacts.size(), " points of contact of ",
                                                                quoted(names_[a]), " and ", quoted(names_[b]),
                                                                " lie on no face exactly: not made vertices"));
        continue;
      }
      for (std::size_t i = 0; i < contacts.size(); ++i) {
        pair.curves.push_back({contacts[i]});
        pair_vertices[p][0].push_back({va[i]});
        pair_vertices[p][1].push_back({vb[i]});
      }
      pair.stats.contact_points = contacts.size();
      pair.stats.curve_vertices += contacts.size();
    }
    std::vector<std::vector<typename K::Point_3>>().swap(contacts_);
  }

  std::vector<Mesh<K>>& meshes_;
  const std::vector<std::string>& names_;
  const TextileOptions& options_;
  const Clock::time_point t_start_;
  Clock::time_point t_stage_;
  std::mutex progress_mutex_;
  tbb::task_arena arena_;
  std::vector<FrozenMesh<K>> frozen_;
  std::vector<Mesh<K>> inputs_;  ///< the input tows, for the quality stage and the verification
  std::vector<std::pair<std::size_t, std::size_t>> candidates_;
  std::vector<PairWork<K>> work_;  ///< per candidate pair
  std::vector<std::vector<typename K::Point_3>> contacts_;  ///< per result pair, until step 4a
  std::vector<double> snap_tol_;
  std::vector<std::size_t> snapped_, snaps_refused_;
  std::vector<internal::FaceProvenance> provenance_;  ///< of the faces cut at triple points
  std::vector<std::vector<std::size_t>> pairs_of_;
  TextileResult<K> result_;
};

}  // namespace

template <class K>
TextileResult<K> textile(std::vector<Mesh<K>>& meshes, const std::vector<std::string>& names,
                         const TextileOptions& options) {
  if (names.size() != meshes.size()) throw InvalidInput("textile: one name per mesh is needed");
  validate_options(options.embed);
  if (options.threads < 0) throw InvalidInput("--threads: must be >= 0 (0: every core)");
  for (std::size_t i = 0; i < meshes.size(); ++i)
    if (!CGAL::is_triangle_mesh(meshes[i]) || meshes[i].is_empty())
      throw InvalidInput(names[i] + ": not a triangle mesh");
  for (std::size_t i = 0; i < meshes.size(); ++i) check_coordinate_range<K>(meshes[i], names[i]);
  return TextileRun<K>(meshes, names, options).run();
}

#define SEAM_INSTANTIATE(K)                                                                                 \
  template TextileResult<K> textile<K>(std::vector<Mesh<K>>&, const std::vector<std::string>&,            \
                                       const TextileOptions&);
SEAM_INSTANTIATE(Exact)
SEAM_INSTANTIATE(Filtered)
SEAM_INSTANTIATE(Float)
#undef SEAM_INSTANTIATE

}  // namespace seam
