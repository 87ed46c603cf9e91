// seam::pair: two tows, one interface. See seam/pair.h.
// SPDX-License-Identifier: GPL-3.0-or-later
#include <seam/internal/improve.h>
#include <seam/internal/snap.h>
#include <seam/quality.h>
#include <seam/check.h>
#include <seam/pair.h>

#include <CGAL/Polygon_mesh_processing/intersection.h>

#include <algorithm>
#include <chrono>
#include <map>
#include <sstream>

namespace seam {

namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

template <class Point> struct PointLess {
  bool operator()(const Point& a, const Point& b) const { return CGAL::compare_xyz(a, b) == CGAL::SMALLER; }
};

/// Chains polylines that share end points (exact comparison) into maximal polylines.
template <class Point> std::vector<std::vector<Point>> chain(std::vector<std::vector<Point>> pieces) {
  // Drop repeated consecutive points and pieces with no length.
  std::vector<std::vector<Point>> clean;
  for (auto& piece : pieces) {
    std::vector<Point> out;
    for (const auto& p : piece)
      if (out.empty() || !(out.back() == p)) out.push_back(p);
    if (out.size() >= 2) clean.push_back(std::move(out));
  }
  // End point -> pieces ending there.
  std::map<Point, std::vector<std::size_t>, PointLess<Point>> ends;
  for (std::size_t i = 0; i < clean.size(); ++i) {
    if (clean[i].front() == clean[i].back()) continue;  // already closed
    ends[clean[i].front()].push_back(i);
    ends[clean[i].back()].push_back(i);
  }
  std::vector<char> used(clean.size(), 0);
  std::vector<std::vector<Point>> result;
  auto extend = [&](std::vector<Point>& line) {
    // Grow at the back while exactly one other unused piece continues there (degree-2 point).
    for (;;) {
      if (line.front() == line.back() && line.size() > 2) return;
      auto it = ends.find(line.back());
      if (it == ends.end()) return;
      std::size_t next = clean.size(), unused = 0;
      for (std::size_t j : it->second)
        if (!used[j]) ++unused, next = j;
      if (unused != 1 || it->second.size() != 2) return;
      used[next] = 1;
      auto piece = clean[next];
      if (!(piece.front() == line.back())) std::reverse(piece.begin(), piece.end());
      line.insert(line.end(), piece.begin() + 1, piece.end());
    }
  };
  // Open chains first: start at an end point that is not a degree-2 point.
  for (std::size_t i = 0; i < clean.size(); ++i) {
    if (used[i] || clean[i].front() == clean[i].back()) continue;
    const bool front_free = ends[clean[i].front()].size() != 2, back_free = ends[clean[i].back()].size() != 2;
    if (!front_free && !back_free) continue;
    used[i] = 1;
    auto line = clean[i];
    if (!front_free) std::reverse(line.begin(), line.end());
    extend(line);
    result.push_back(std::move(line));
  }
  // The rest form loops.
  for (std::size_t i = 0; i < clean.size(); ++i) {
    if (used[i]) continue;
    used[i] = 1;
    auto line = clean[i];
    extend(line);
    result.push_back(std::move(line));
  }
  // Closed curves start at their smallest point (deterministic output).
  for (auto& line : result) {
    if (!(line.size() > 2 && line.front() == line.back())) continue;
    line.pop_back();
    auto first = std::min_element(line.begin(), line.end(), PointLess<Point>());
    std::rotate(line.begin(), first, line.end());
    line.push_back(line.front());
  }
  std::sort(result.begin(), result.end(), [](const auto& x, const auto& y) {
    return CGAL::compare_xyz(x.front(), y.front()) == CGAL::SMALLER;
  });
  return result;
}

}  // namespace

template <class K>
std::vector<Polyline<K>> intersection_curves(const Mesh<K>& a, const Mesh<K>& b, std::size_t* touching_points) {
  std::vector<std::vector<typename K::Point_3>> pieces;
  CGAL::Polygon_mesh_processing::surface_intersection(a, b, std::back_inserter(pieces));
  if (touching_points) {
    *touching_points = 0;
    for (const auto& piece : pieces)
      if (std::all_of(piece.begin(), piece.end(), [&](const auto& p) { return p == piece.front(); }))
        ++*touching_points;
  }
  auto curves = chain(std::move(pieces));
  for (auto& c : curves)
    for (auto& p : c) make_exact(p);  // kept points: cut the expression trees once
  return curves;
}

template <class K> PairResult<K> pair(Mesh<K>& a, Mesh<K>& b, const PairOptions& options) {
  validate_options(options.embed);
  PairResult<K> result;
  PairStats& st = result.stats;
  const double la = mean_edge_length<K>(a), lb = mean_edge_length<K>(b);
  const double snap_tol = options.embed.snap_tol < 0 ? 0.1 * std::min(la, lb) : options.embed.snap_tol;
  st.snap_tol = snap_tol;

  auto t = Clock::now();
  std::size_t touching = 0;
  std::vector<Polyline<K>> curves = intersection_curves<K>(a, b, &touching);
  st.stage_seconds["intersect"] = seconds_since(t);

  if (snap_tol > 0 && !curves.empty()) {
    // Report step 1 on both meshes, against the exact intersection points; then the curves of
    // the moved surfaces.
    t = Clock::now();
    // Onto the closest point of the curves (they lie on both surfaces), not only their nodes,
    // which are sparse: one per crossing of an edge.
    const auto sa = internal::snap_vertices_to_segments<K>(a, curves, snap_tol);
    const auto sb = internal::snap_vertices_to_segments<K>(b, curves, snap_tol);
    st.vertices_snapped_a = sa.snapped;
    st.vertices_snapped_b = sb.snapped;
    st.snaps_refused = sa.refused + sb.refused;
    st.stage_seconds["snap"] = seconds_since(t);
    if (sa.snapped + sb.snapped > 0) {
      t = Clock::now();
      curves = intersection_curves<K>(a, b, &touching);
      st.stage_seconds["intersect"] += seconds_since(t);
    }
  }

  st.curves = curves.size();
  for (const auto& c : curves) {
    const bool closed = is_closed(c);
    st.closed_curves += closed ? 1 : 0;
    st.curve_vertices += closed ? c.size() - 1 : c.size();
  }
  if (curves.empty()) {
    st.touching_only = touching > 0;
    st.note = touching > 0 ? "the meshes touch without crossing: nothing to embed"
                           : "the meshes do not intersect (disjoint, or one inside the other): nothing to embed";
  }

  // Embed the same curves into both meshes, keeping every curve point.
  EmbedOptions eo = options.embed;
  eo.snap_tol = 0;  // done above, on both meshes
  eo.keep_all_nodes = true;
  eo.curve_tol = 0;
  eo.max_distance = std::numeric_limits<double>::max();  // the points lie on both surfaces
  t = Clock::now();
  result.a = embed<K>(a, curves, eo);
  st.stage_seconds["embed_a"] = seconds_since(t);
  t = Clock::now();
  result.b = embed<K>(b, curves, eo);
  st.stage_seconds["embed_b"] = seconds_since(t);
  result.a.stats.vertices_snapped = st.vertices_snapped_a;
  result.b.stats.vertices_snapped = st.vertices_snapped_b;

  // Both meshes must have received the identical curve.
  if (result.a.curves.size() != result.b.curves.size())
    throw InternalError("pair: the two meshes received different numbers of curves");
  for (std::size_t i = 0; i < result.a.curves.size(); ++i)
    if (result.a.curves[i] != result.b.curves[i]) {
      std::ostringstream msg;
      msg << "pair: curve " << i << " was embedded differently in the two meshes (" << result.a.curves[i].size()
          << " and " << result.b.curves[i].size() << " points)";
      throw InternalError(msg.str());
    }
  result.curves = result.a.curves;

  // Experimental: coarsen the curve to about the edge length and remesh both meshes next to it
  // (see internal/improve.h and PairOptions::remesh_near_curves). Kept only when both succeed.
  if (options.remesh_near_curves && !result.curves.empty()) {
    t = Clock::now();
    const double spacing = std::min(la, lb);
    auto kept = internal::choose_curve_points<K>(result.curves, spacing);
    std::vector<std::vector<std::size_t>> refused;
    auto keep_refused_too = [&]() {
      for (std::size_t c = 0; c < kept.size(); ++c) {
        kept[c].insert(kept[c].end(), refused[c].begin(), refused[c].end());
        std::sort(kept[c].begin(), kept[c].end());
        kept[c].erase(std::unique(kept[c].begin(), kept[c].end()), kept[c].end());
      }
    };
    for (int attempt = 0; attempt < 8; ++attempt) {
      Mesh<K> a2 = a, b2 = b;
      auto cva = result.a.curve_vertices, cvb = result.b.curve_vertices;
      if (!internal::coarsen_and_remesh_near_curves<K>(a2, cva, kept, la, refused)) {
        if (std::all_of(refused.begin(), refused.end(), [](const auto& r) { return r.empty(); })) break;
        keep_refused_too();
        continue;
      }
      if (!internal::coarsen_and_remesh_near_curves<K>(b2, cvb, kept, lb, refused)) {
        if (std::all_of(refused.begin(), refused.end(), [](const auto& r) { return r.empty(); })) break;
        keep_refused_too();
        continue;
      }
      std::vector<Polyline<K>> ca, cb;
      for (const auto& vs : cva) {
        ca.emplace_back();
        for (auto v : vs) ca.back().push_back(a2.point(v));
      }
      for (const auto& vs : cvb) {
        cb.emplace_back();
        for (auto v : vs) cb.back().push_back(b2.point(v));
      }
      // Accept the remeshed pair only if it still meets only along the curves (seam check's test).
      const bool conforming =
          ca == cb && check_pair<K>(a, b, a2, b2, ca, std::numeric_limits<double>::infinity()).ok();
      if (!conforming) st.note = "remeshing next to the curves was undone: the remeshed meshes crossed off the curves";
      if (conforming) {
        a = std::move(a2);
        b = std::move(b2);
        result.curves = ca;
        result.a.curves = ca;
        result.b.curves = cb;
        result.a.curve_vertices = cva;
        result.b.curve_vertices = cvb;
        st.remeshed = true;
        for (auto* r : {&result.a, &result.b}) {  // the figures of the remeshed meshes
          const auto& m = r == &result.a ? a : b;
          const auto q = new_face_quality<K>(m);
          r->stats.min_angle_deg_new = q.min_angle_deg;
          r->stats.new_faces_below_10 = q.below_10;
          r->stats.new_faces_below_20 = q.below_20;
          r->stats.new_faces_below_10_unforced = q.below_10;
          r->stats.faces_added = q.new_faces;
          r->stats.output_vertices = m.number_of_vertices();
          r->stats.output_faces = m.number_of_faces();
          r->stats.curve_nodes_out = 0;
          for (const auto& c : r->curves) r->stats.curve_nodes_out += is_closed(c) ? c.size() - 1 : c.size();
        }
        st.curve_vertices = result.a.stats.curve_nodes_out;
      }
      break;
    }
    st.stage_seconds["remesh"] = seconds_since(t);
  }
  return result;
}

#define SEAM_INSTANTIATE(K)                                                                       \
  template std::vector<Polyline<K>> intersection_curves<K>(const Mesh<K>&, const Mesh<K>&, std::size_t*); \
  template PairResult<K> pair<K>(Mesh<K>&, Mesh<K>&, const PairOptions&);
SEAM_INSTANTIATE(Exact)
SEAM_INSTANTIATE(Filtered)
SEAM_INSTANTIATE(Float)
#undef SEAM_INSTANTIATE

}  // namespace seam
