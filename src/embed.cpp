// seam::embed: the pipeline, step by step. See seam/embed.h.
// SPDX-License-Identifier: GPL-3.0-or-later
#include <seam/io.h>
#include <seam/embed.h>
#include <seam/internal/coarsen.h>
#include <seam/internal/embed_known_sites.h>
#include <seam/internal/snap.h>
#include <seam/internal/splice.h>
#include <seam/internal/trace.h>
#include <seam/internal/new_face_figures.h>
#include <seam/quality.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <optional>
#include <set>
#include <sstream>
#include <tuple>

namespace seam {

template <class K> double mean_edge_length(const Mesh<K>& mesh) {
  double sum = 0;
  std::size_t count = 0;
  // On the coordinates rounded to doubles (a length scale for tolerances; under the exact kernel
  // the exact squared distance would build an expression per edge).
  for (auto e : mesh.edges()) {
    sum += std::sqrt(CGAL::squared_distance(to_filtered(mesh.point(mesh.vertex(e, 0))), to_filtered(mesh.point(mesh.vertex(e, 1)))));
    ++count;
  }
  return count ? sum / double(count) : 0.0;
}

void validate_options(const EmbedOptions& o) {
  const auto bad = [](const char* option, double value, const char* expected) {
    std::ostringstream msg;
    msg << option << " " << value << ": out of range (" << expected << ")";
    throw InvalidInput(msg.str());
  };
  if (!std::isfinite(o.snap_tol)) bad("--snap-tol", o.snap_tol, "must be finite");
  if (!std::isfinite(o.max_distance)) bad("--max-distance", o.max_distance, "must be finite");
  if (!(o.curve_tol >= 0) || !std::isfinite(o.curve_tol)) bad("--curve-tol", o.curve_tol, "must be finite, >= 0");
  if (!(o.min_angle_deg >= 0 && o.min_angle_deg <= 60)) bad("--min-angle", o.min_angle_deg, "degrees, 0 to 60");
  if (!(o.max_area >= 0) || !std::isfinite(o.max_area)) bad("--max-area", o.max_area, "must be finite, >= 0");
}

namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

/// Largest distance between the input curves and the embedded (coarsened) ones, measured
/// locally, both ways (rounded; a measurement for the report): each input node against the
/// embedded segment that replaced it, each embedded point against the input segment(s) it lies
/// between. Linear in the number of traced points: a global nearest-segment search degenerates
/// to quadratic time when the curve passes through the same faces many times (a zig-zag).
template <class K>
double polyline_deviation(const std::vector<Polyline<K>>& input, const std::vector<internal::TracedCurve<K>>& traced,
                          const internal::CoarsenOutput<K>& coarse) {
  using DK = CGAL::Exact_predicates_inexact_constructions_kernel;
  double worst = 0;
  const auto& cps = coarse.points.points;
  for (std::size_t c = 0; c < traced.size() && c < coarse.curves.size() && c < input.size(); ++c) {
    const auto& tc = traced[c];
    const auto& cc = coarse.curves[c];
    const auto& in = input[c];
    const std::size_t n = tc.points.size(), m = cc.traced_index.size();
    if (n == 0 || m == 0 || tc.input_node.size() != n) continue;
    auto node = [&](std::size_t i) -> std::optional<DK::Point_3> {
      const long k = tc.input_node[i];
      if (k < 0 || std::size_t(k) >= in.size()) return std::nullopt;
      return to_filtered(in[std::size_t(k)]);
    };
    auto dist = [](const DK::Point_3& p, const DK::Point_3& a, const DK::Point_3& b) {
      return std::sqrt(a == b ? CGAL::squared_distance(p, a) : CGAL::squared_distance(p, DK::Segment_3(a, b)));
    };
    // Input nodes against the embedded segment that replaced them.
    const std::size_t segments = cc.closed ? m : m - 1;
    for (std::size_t j = 0; j < segments; ++j) {
      const std::size_t ta = cc.traced_index[j], tb = cc.traced_index[(j + 1) % m];
      const auto a = to_filtered(cps[cc.ids[j]].p), b = to_filtered(cps[cc.ids[(j + 1) % m]].p);
      for (std::size_t i = ta;; i = (i + 1) % n) {
        if (const auto p = node(i)) worst = std::max(worst, dist(*p, a, b));
        if (i == tb) break;
      }
    }
    if (m == 1) {
      if (const auto p = node(cc.traced_index[0])) worst = std::max(worst, dist(*p, to_filtered(cps[cc.ids[0]].p), to_filtered(cps[cc.ids[0]].p)));
    }
    // Embedded points against the input segment between the nodes before and after them.
    std::vector<long> before(n, -1), after(n, -1);
    for (std::size_t pass = 0, i = 0; pass < (cc.closed ? 2u : 1u); ++pass)
      for (i = 0; i < n; ++i) {
        if (tc.input_node[i] >= 0) before[i] = long(i);
        else if (i > 0 && before[i - 1] >= 0) before[i] = before[i - 1];
        else if (i == 0 && cc.closed && before[n - 1] >= 0) before[i] = before[n - 1];
      }
    for (std::size_t pass = 0; pass < (cc.closed ? 2u : 1u); ++pass)
      for (std::size_t r = 0; r < n; ++r) {
        const std::size_t i = n - 1 - r;
        if (tc.input_node[i] >= 0) after[i] = long(i);
        else if (i + 1 < n && after[i + 1] >= 0) after[i] = after[i + 1];
        else if (i + 1 == n && cc.closed && after[0] >= 0) after[i] = after[0];
      }
    for (std::size_t j = 0; j < m; ++j) {
      const std::size_t t = cc.traced_index[j];
      if (before[t] < 0 || after[t] < 0) continue;
      const auto p = to_filtered(cps[cc.ids[j]].p);
      const auto a = node(std::size_t(before[t])), b = node(std::size_t(after[t]));
      double d = dist(p, *a, *b);
      if (before[t] == after[t]) {  // an input node itself: the input segments on either side
        const long k = tc.input_node[t];
        if (k > 0) d = std::min(d, dist(p, to_filtered(in[std::size_t(k - 1)]), *a));
        if (std::size_t(k) + 1 < in.size()) d = std::min(d, dist(p, *a, to_filtered(in[std::size_t(k + 1)])));
      }
      worst = std::max(worst, d);
    }
  }
  return worst;
}

using namespace internal;  // (the steps' types: MeshTypes, Where, CoarsenOutput, FacePatch, ...)

/// Step 5's input, per element of the mesh: the coarsened curve points (ids into the coarse
/// points) inside each edge (ordered from the source of its halfedge 0) and inside each face, and
/// the curve segments inside each face; each point's vertex index in the output (`out_id`: a
/// mesh vertex's own, or nv + its position in `new_points`).
template <class K> struct FaceConstraintsByElement {
  using T = MeshTypes<K>;
  std::vector<std::size_t> out_id;
  std::vector<typename K::Point_3> new_points;
  std::map<typename T::E, std::vector<std::size_t>> edge_points;
  std::map<typename T::F, std::vector<std::size_t>> face_points;
  std::map<typename T::F, std::vector<std::pair<std::size_t, std::size_t>>> face_segments;
  std::set<typename T::F> crossed;  ///< the faces to re-triangulate
};

template <class K>
FaceConstraintsByElement<K> constraints_by_element(const Mesh<K>& mesh, const CoarsenOutput<K>& coarse,
                                                   EmbedStats& st) {
  using F = typename MeshTypes<K>::F;
  FaceConstraintsByElement<K> g;
  const std::size_t nv = mesh.number_of_vertices();
  const auto& cps = coarse.points.points;
  g.out_id.resize(cps.size());
  for (std::size_t i = 0; i < cps.size(); ++i) {
    const auto& sp = cps[i];
    if (sp.where == Where::vertex) {
      g.out_id[i] = std::size_t(sp.v);
      ++st.curve_vertices_at_mesh_vertices;
      continue;
    }
    g.out_id[i] = nv + g.new_points.size();
    g.new_points.push_back(sp.p);
    if (sp.where == Where::edge) {
      g.edge_points[sp.e].push_back(i);
      ++st.crossing_points;
    } else {
      g.face_points[sp.f].push_back(i);
    }
  }
  // Along each edge, order the points from the source of its halfedge 0 (exact comparison).
  for (auto& [e, ids] : g.edge_points) {
    const auto& s = mesh.point(mesh.source(mesh.halfedge(e, 0)));
    std::sort(ids.begin(), ids.end(), [&](std::size_t x, std::size_t y) {
      return CGAL::compare_distance_to_point(s, cps[x].p, cps[y].p) == CGAL::SMALLER;
    });
  }
  std::set<std::tuple<std::size_t, std::size_t, std::size_t>> segments_seen;  // a face may hold 100,000
  for (const auto& cc : coarse.curves) {
    const std::size_t ns = cc.segment_face.size();
    for (std::size_t j = 0; j < ns; ++j) {
      const F f = cc.segment_face[j];
      if (f == Mesh<K>::null_face()) continue;
      std::size_t a = cc.ids[j], b = cc.ids[(j + 1) % cc.ids.size()];
      if (a > b) std::swap(a, b);
      if (segments_seen.emplace(std::size_t(f), a, b).second) g.face_segments[f].emplace_back(a, b);
    }
  }
  for (const auto& [e, ids] : g.edge_points)
    for (int i = 0; i < 2; ++i)
      if (!mesh.is_border(mesh.halfedge(e, i))) g.crossed.insert(mesh.face(mesh.halfedge(e, i)));
  for (const auto& [f, ids] : g.face_points) g.crossed.insert(f);
  for (const auto& [f, segs] : g.face_segments) g.crossed.insert(f);
  st.faces_crossed = g.crossed.size();
  return g;
}

/// Step 5: each crossed face re-triangulated with its split edges and the curve segments inside
/// it as constraints. `source_min_angle` receives each crossed face's smallest angle.
template <class K>
std::map<typename MeshTypes<K>::F, FacePatch<K>>
retriangulate_crossed_faces(const Mesh<K>& mesh, const FaceConstraintsByElement<K>& g, const CoarsenOutput<K>& coarse,
                            const EmbedOptions& options, EmbedStats& st, std::vector<double>& source_min_angle,
                            KeepAway* keep_away) {
  using F = typename MeshTypes<K>::F;
  const auto& cps = coarse.points.points;
  RetriangulateOptions ropt;
  ropt.min_angle_deg = options.min_angle_deg;
  ropt.max_area = options.max_area;
  ropt.max_steiner = options.max_steiner_per_face;
  ropt.keep_away = keep_away;
  std::map<F, FacePatch<K>> patches;
  st.min_angle_deg_input = 180;
  for (F f : g.crossed) {
    FaceConstraints<K> fc;
    auto h = mesh.halfedge(f);
    for (int i = 0; i < 3; ++i, h = mesh.next(h)) {
      const auto s = mesh.source(h);
      fc.corner_ids[i] = std::size_t(s);
      fc.corners[i] = mesh.point(s);
      auto it = g.edge_points.find(mesh.edge(h));
      if (it != g.edge_points.end()) {
        std::vector<std::size_t> ids = it->second;
        if (mesh.halfedge(mesh.edge(h), 0) != h) std::reverse(ids.begin(), ids.end());
        for (std::size_t id : ids) fc.edge_points[i].emplace_back(g.out_id[id], cps[id].p);
      }
    }
    if (auto it = g.face_points.find(f); it != g.face_points.end())
      for (std::size_t id : it->second) fc.interior_points.emplace_back(g.out_id[id], cps[id].p);
    if (auto it = g.face_segments.find(f); it != g.face_segments.end())
      for (auto [a, b] : it->second) fc.segments.emplace_back(g.out_id[a], g.out_id[b]);
    try {
      patches.emplace(f, retriangulate_face<K>(fc, ropt));
    } catch (const InvalidInput& e) {
      std::ostringstream msg;
      msg << e.what() << " (input face " << std::size_t(f)
          << "): the curves, projected onto the surface, cross there; curves that do not cross may "
             "still, where they lie farther from the surface than its features are apart (a sharp rim)";
      throw InvalidInput(msg.str());
    }
    source_min_angle[std::size_t(f)] = min_angle_deg(fc.corners[0], fc.corners[1], fc.corners[2]);
    st.min_angle_deg_input = std::min(st.min_angle_deg_input, source_min_angle[std::size_t(f)]);
  }
  if (g.crossed.empty()) st.min_angle_deg_input = 0;
  for (const auto& [f, patch] : patches) {
    st.steiner_points += patch.steiner_points.size();
    st.faces_added += patch.triangles.size();
    st.faces_refinement_fallback += patch.refinement_undone ? 1 : 0;
  }
  return patches;
}

/// Input edges joining two curve vertices that are mesh vertices (segments along an edge).
template <class K>
std::map<std::pair<typename MeshTypes<K>::V, typename MeshTypes<K>::V>, typename MeshTypes<K>::E>
input_edges_along_curves(const Mesh<K>& mesh, const CoarsenOutput<K>& coarse) {
  const auto& cps = coarse.points.points;
  std::map<std::pair<typename MeshTypes<K>::V, typename MeshTypes<K>::V>, typename MeshTypes<K>::E> result;
  for (const auto& cc : coarse.curves)
    for (std::size_t j = 0; j < cc.segment_face.size(); ++j) {
      if (cc.segment_face[j] != Mesh<K>::null_face()) continue;
      const auto& a = cps[cc.ids[j]];
      const auto& b = cps[cc.ids[(j + 1) % cc.ids.size()]];
      if (a.where != Where::vertex || b.where != Where::vertex) continue;
      const auto h = mesh.halfedge(a.v, b.v);
      if (h == Mesh<K>::null_halfedge()) throw InternalError("a curve segment along an edge has no edge");
      result[{a.v, b.v}] = mesh.edge(h);
    }
  return result;
}

/// The embedded curves, as vertices of the spliced mesh (along an input edge, through the curve
/// points on it), into `result.curve_vertices` and `result.curves`.
template <class K>
void record_embedded_curves(const Mesh<K>& mesh, const CoarsenOutput<K>& coarse, const FaceConstraintsByElement<K>& g,
                            const std::map<std::pair<typename MeshTypes<K>::V, typename MeshTypes<K>::V>,
                                           typename MeshTypes<K>::E>& input_edge_between,
                            EmbedResult<K>& result) {
  using V = typename MeshTypes<K>::V;
  using E = typename MeshTypes<K>::E;
  const auto& cps = coarse.points.points;
  for (const auto& cc : coarse.curves) {
    std::vector<V> vs;
    const std::size_t nseg = cc.segment_face.size();
    for (std::size_t j = 0; j < cc.ids.size(); ++j) {
      vs.push_back(V(static_cast<typename V::size_type>(g.out_id[cc.ids[j]])));
      if (j >= nseg || cc.segment_face[j] != Mesh<K>::null_face()) continue;
      // A segment along an input edge: insert the points of that edge that lie between its ends.
      const auto& a = cps[cc.ids[j]];
      const auto& b = cps[cc.ids[(j + 1) % cc.ids.size()]];
      const E along = a.where == Where::edge   ? a.e
                       : b.where == Where::edge ? b.e
                                                : input_edge_between.at(std::make_pair(a.v, b.v));
      std::vector<std::size_t> between;
      if (auto it = g.edge_points.find(along); it != g.edge_points.end())
        for (std::size_t id : it->second)
          if (CGAL::collinear_are_strictly_ordered_along_line(a.p, cps[id].p, b.p)) between.push_back(id);
      std::sort(between.begin(), between.end(), [&](std::size_t x, std::size_t y) {
        return CGAL::compare_distance_to_point(a.p, cps[x].p, cps[y].p) == CGAL::SMALLER;
      });
      for (std::size_t id : between) vs.push_back(V(static_cast<typename V::size_type>(g.out_id[id])));
    }
    if (cc.closed && !vs.empty()) vs.push_back(vs.front());
    Polyline<K> pl;
    for (V v : vs) pl.push_back(mesh.point(v));
    result.stats.curve_nodes_out += cc.closed ? vs.size() - 1 : vs.size();
    result.curve_vertices.push_back(std::move(vs));
    result.curves.push_back(std::move(pl));
  }
}

/// The preconditions of embed (a triangle mesh, valid options, curves of 2 points or more) and
/// the input's figures in `st`. Returns false when the mesh had garbage (collected: indices moved).
template <class K>
bool check_and_measure_input(Mesh<K>& mesh, const std::vector<Polyline<K>>& curves, const EmbedOptions& options,
                             EmbedStats& st) {
  if (!CGAL::is_triangle_mesh(mesh) || mesh.is_empty()) throw InvalidInput("the mesh is not a triangle mesh");
  const bool had_garbage = mesh.has_garbage();
  if (had_garbage) mesh.collect_garbage();
  validate_options(options);
  for (std::size_t c = 0; c < curves.size(); ++c) {
    if (curves[c].size() < 2) {
      std::ostringstream msg;
      msg << "curve " << c << " has fewer than 2 points";
      throw InvalidInput(msg.str());
    }
  }
  st.input_vertices = mesh.number_of_vertices();
  st.input_faces = mesh.number_of_faces();
  st.mean_edge_length = mean_edge_length<K>(mesh);
  st.snap_tol = options.snap_tol < 0 ? 0.1 * st.mean_edge_length : options.snap_tol;
  st.max_distance = options.max_distance < 0 ? 1.0 * st.mean_edge_length : options.max_distance;
  st.curves = curves.size();
  for (const auto& c : curves) st.curve_nodes_in += is_closed(c) ? c.size() - 1 : c.size();
  return !had_garbage;
}

}  // namespace

namespace internal {

template <class K>
EmbedResult<K> embed_with_known_sites(Mesh<K>& mesh, const std::vector<Polyline<K>>& curves,
                                      const EmbedOptions& options, const KnownSites<K>* known,
                                      KeepAway* keep_away) {
  EmbedResult<K> result;
  EmbedStats& st = result.stats;
  st.kernel = kernel_name(kernel_traits<K>::kind);
  if (!check_and_measure_input<K>(mesh, curves, options, st)) known = nullptr;  // the indices it holds changed

  // ---- 1. snap
  auto t = Clock::now();
  const auto snap = snap_vertices<K>(mesh, curves, st.snap_tol);
  st.vertices_snapped = snap.snapped;
  st.snaps_refused = snap.refused;
  st.max_snap_move = snap.max_move;
  st.stage_seconds["snap"] = seconds_since(t);
  if (snap.snapped > 0) known = nullptr;  // vertices moved: the known sites may no longer hold

  // ---- 2, 3. locate and cross
  TraceReport trace_report;
  const auto traced = trace_curves<K>(mesh, curves, st.max_distance, trace_report, options.keep_all_nodes, 0.0, known,
                                      /*defer_projections=*/true);
  st.stage_seconds["locate"] = trace_report.locate_seconds;
  st.stage_seconds["cross"] = trace_report.cross_seconds;

  // ---- 4. coarsen
  t = Clock::now();
  CoarsenOutput<K> coarse = coarsen_curves<K>(mesh, traced, options.curve_tol, options.keep_all_nodes);
  st.stage_seconds["coarsen"] = seconds_since(t);

  // ---- 5. re-triangulate: gather each face's constraints, then triangulate it
  t = Clock::now();
  const auto constraints = constraints_by_element<K>(mesh, coarse, st);
  std::vector<double> source_min_angle(st.input_faces, 180.0);
  auto patches = retriangulate_crossed_faces<K>(mesh, constraints, coarse, options, st, source_min_angle, keep_away);
  st.stage_seconds["retriangulate"] = seconds_since(t);
  const auto input_edge_between = input_edges_along_curves<K>(mesh, coarse);

  // ---- 6. splice
  t = Clock::now();
  Mesh<K> out = splice_patches<K>(mesh, constraints.new_points, patches);
  mesh = std::move(out);
  st.output_vertices = mesh.number_of_vertices();
  st.output_faces = mesh.number_of_faces();
  st.stage_seconds["splice"] = seconds_since(t);
  record_embedded_curves<K>(mesh, coarse, constraints, input_edge_between, result);

  // ---- quality of the new faces and distance to the input curves (rounded measurements)
  const auto quality = new_face_quality<K>(mesh, &source_min_angle, options.max_area);
  record_new_face_figures(quality, st);
  st.new_faces_below_10_unforced = quality.below_10_unforced;
  st.max_curve_deviation = polyline_deviation<K>(curves, traced, coarse);
  return result;
}

}  // namespace internal

template <class K>
EmbedResult<K> embed(Mesh<K>& mesh, const std::vector<Polyline<K>>& curves, const EmbedOptions& options) {
  check_coordinate_range<K>(mesh, "the mesh");
  check_coordinate_range<K>(curves, "the curves");
  return internal::embed_with_known_sites<K>(mesh, curves, options, nullptr);
}

#define SEAM_INSTANTIATE(K)                                                                                \
  template EmbedResult<K> embed<K>(Mesh<K>&, const std::vector<Polyline<K>>&, const EmbedOptions&);       \
  template EmbedResult<K> internal::embed_with_known_sites<K>(Mesh<K>&, const std::vector<Polyline<K>>&,   \
                                                             const EmbedOptions&, const internal::KnownSites<K>*, \
                                                             internal::KeepAway*);                     \
  template double mean_edge_length<K>(const Mesh<K>&);
SEAM_INSTANTIATE(Exact)
SEAM_INSTANTIATE(Filtered)
SEAM_INSTANTIATE(Float)
#undef SEAM_INSTANTIATE

}  // namespace seam
