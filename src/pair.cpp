// seam::pair: two tows, one interface. See seam/pair.h.
// SPDX-License-Identifier: GPL-3.0-or-later
#include <seam/io.h>
#include <seam/internal/flat_contacts.h>
#include <seam/internal/collapse.h>
#include <seam/internal/contact_points.h>
#include <seam/internal/embed_known_sites.h>
#include <seam/internal/general_position_curves.h>
#include <seam/internal/improve_state.h>
#include <seam/internal/local_edits.h>
#include <seam/internal/snap.h>
#include <seam/internal/verify_output.h>
#include <seam/quality.h>
#include <seam/check.h>
#include <seam/pair.h>

#include <CGAL/Polygon_mesh_processing/bbox.h>
#include <CGAL/Polygon_mesh_processing/intersection.h>

#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <chrono>
#include <map>
#include <new>
#include <optional>
#include <set>
#include <sstream>

#ifndef CGAL_HAS_THREADS
#error "seam::pair embeds the two meshes in parallel: CGAL must be thread-aware (CGAL_HAS_THREADS)"
#endif

namespace seam {

namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

template <class Point> struct PointLess {
  bool operator()(const Point& a, const Point& b) const { return CGAL::compare_xyz(a, b) == CGAL::SMALLER; }
};

/// Sorts polylines by their first points (compare_xyz, exact): a deterministic curve order.
template <class Point> void sort_by_first_point(std::vector<std::vector<Point>>& lines) {
  std::sort(lines.begin(), lines.end(), [](const auto& x, const auto& y) {
    return CGAL::compare_xyz(x.front(), y.front()) == CGAL::SMALLER;
  });
}

/// Chains polylines that share end points (exact comparison) into maximal polylines, through points
/// where an even number of them meet (see below).
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
  // Where an even number of pieces meet (2, or 4 where two curves touch or one crosses itself),
  // the chain goes on through, with the first unused piece: so every curve of a set of closed
  // curves stays closed (a walk through even points can only stop where it started). Chains end
  // where an odd number meet (a branch, such as the corner of a flat contact).
  auto odd = [&](const Point& p) {
    const auto it = ends.find(p);
    return it != ends.end() && it->second.size() % 2 == 1;
  };
  auto extend = [&](std::vector<Point>& line) {
    for (;;) {
      if (line.front() == line.back() && line.size() > 2) return;
      auto it = ends.find(line.back());
      if (it == ends.end() || it->second.size() % 2 == 1) return;
      std::size_t next = clean.size();
      for (std::size_t j : it->second)
        if (!used[j]) {
          next = j;
          break;
        }
      if (next == clean.size()) return;
      used[next] = 1;
      auto piece = clean[next];
      if (!(piece.front() == line.back())) std::reverse(piece.begin(), piece.end());
      line.insert(line.end(), piece.begin() + 1, piece.end());
    }
  };
  // Open chains first: start at an end point where an odd number of pieces meet.
  for (std::size_t i = 0; i < clean.size(); ++i) {
    if (used[i] || clean[i].front() == clean[i].back()) continue;
    const bool front_free = odd(clean[i].front()), back_free = odd(clean[i].back());
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
  sort_by_first_point(result);
  return result;
}


/// Orients each curve along n_A x n_B, the cross product of the normals of the faces of A and B
/// that contain it (faces as oriented in the inputs): the usual orientation of a transverse
/// intersection, and the same for the same pair whatever order CGAL returned the pieces in.
/// Decided on the first segment whose containing faces all give the same nonzero sign (exact
/// under the exact kernel; normals rounded under Epick). A curve without one (the boundary of a
/// flat contact, where the normals are parallel) runs from its smaller end point, or, closed,
/// from its first point towards the smaller of its two neighbours.
template <class K> void orient_curves(const Mesh<K>& a, const Mesh<K>& b, std::vector<std::vector<typename K::Point_3>>& curves) {
  using Point = typename K::Point_3;
  using F = typename Mesh<K>::Face_index;
  constexpr std::size_t segments_tried = 32;
  auto corners = [](const Mesh<K>& m, F f) {
    const auto h = m.halfedge(f);
    return std::array<Point, 3>{m.point(m.source(h)), m.point(m.target(h)), m.point(m.target(m.next(h)))};
  };
  for (auto& line : curves) {
    if (line.size() < 2) continue;
    const std::size_t tried = std::min(line.size() - 1, segments_tried);
    CGAL::Bbox_3 near;
    for (std::size_t i = 0; i <= tried; ++i) near += line[i].bbox();
    std::vector<std::pair<F, CGAL::Bbox_3>> near_a, near_b;
    for (F f : a.faces())
      if (const auto box = CGAL::Polygon_mesh_processing::face_bbox(f, a); CGAL::do_overlap(box, near))
        near_a.emplace_back(f, box);
    for (F f : b.faces())
      if (const auto box = CGAL::Polygon_mesh_processing::face_bbox(f, b); CGAL::do_overlap(box, near))
        near_b.emplace_back(f, box);
    auto containing = [&](const Mesh<K>& m, const std::vector<std::pair<F, CGAL::Bbox_3>>& faces, const Point& p,
                          const Point& q) {
      std::vector<std::array<Point, 3>> result;
      const CGAL::Bbox_3 box = p.bbox() + q.bbox();
      for (const auto& [f, fbox] : faces) {
        if (!CGAL::do_overlap(box, fbox)) continue;
        const auto c = corners(m, f);
        const typename K::Triangle_3 t(c[0], c[1], c[2]);
        if (!t.is_degenerate() && t.has_on(p) && t.has_on(q)) result.push_back(c);
      }
      return result;
    };
    int direction = 0;
    for (std::size_t i = 0; i < tried && direction == 0; ++i) {
      const Point &p = line[i], &q = line[i + 1];
      const auto fa = containing(a, near_a, p, q), fb = containing(b, near_b, p, q);
      int sign = 0;
      bool agree = !fa.empty() && !fb.empty();
      for (const auto& ca : fa)
        for (const auto& cb : fb) {
          if (!agree) break;
          const int s = CGAL::sign(CGAL::determinant(q - p, CGAL::cross_product(ca[1] - ca[0], ca[2] - ca[0]),
                                                     CGAL::cross_product(cb[1] - cb[0], cb[2] - cb[0])));
          if (s == 0 || (sign != 0 && s != sign)) agree = false;
          sign = s;
        }
      if (agree) direction = sign;
    }
    if (direction == 0) {
      const bool closed = line.size() > 3 && line.front() == line.back();
      const Point& forward = closed ? line[1] : line.front();
      const Point& backward = closed ? line[line.size() - 2] : line.back();
      direction = CGAL::compare_xyz(backward, forward) == CGAL::SMALLER ? -1 : 1;
    }
    if (direction < 0) std::reverse(line.begin(), line.end());  // a closed curve keeps its first point
  }
  sort_by_first_point(curves);
}

}  // namespace

/// intersection_curves; when the direct path computed them (exact kernel), also where each curve
/// point lies in each mesh (`sites_a`, `sites_b`, may be null; left empty otherwise), and the
/// isolated points of contact (`contacts`, may be null).
template <class K>
std::vector<Polyline<K>> curves_and_sites(const Mesh<K>& a, const Mesh<K>& b, std::size_t* touching_points,
                                          internal::KnownSites<K>* sites_a, internal::KnownSites<K>* sites_b,
                                          std::vector<typename K::Point_3>* contacts = nullptr) {
  if (contacts) contacts->clear();
  if constexpr (std::is_same_v<K, Float>) {
    // CGAL's surface_intersection (its coplanar corefinement in particular) needs exact
    // predicates: with plain doubles it fails assertions or runs into undefined behaviour on
    // degenerate inputs (found by fuzzing). Under the float kernel the curves are computed with
    // Epick on the same doubles (exact decisions, constructions rounded as under float anyway).
    auto to_filtered_mesh = [](const Mesh<Float>& m) {
      Mesh<Filtered> r;
      std::vector<Mesh<Filtered>::Vertex_index> vertex(m.num_vertices());
      for (auto v : m.vertices()) {
        const auto& p = m.point(v);
        vertex[std::size_t(v)] = r.add_vertex(Filtered::Point_3(p.x(), p.y(), p.z()));
      }
      for (auto f : m.faces()) {
        std::vector<Mesh<Filtered>::Vertex_index> corners;
        for (auto v : CGAL::vertices_around_face(m.halfedge(f), m)) corners.push_back(vertex[std::size_t(v)]);
        if (r.add_face(corners) == Mesh<Filtered>::null_face())
          throw InternalError("intersection_curves: a face could not be copied");
      }
      return r;
    };
    std::vector<Filtered::Point_3> filtered_contacts;
    const auto curves = curves_and_sites<Filtered>(to_filtered_mesh(a), to_filtered_mesh(b), touching_points, nullptr,
                                                   nullptr, contacts ? &filtered_contacts : nullptr);
    if (contacts)
      for (const auto& p : filtered_contacts) contacts->emplace_back(p.x(), p.y(), p.z());
    std::vector<Polyline<K>> result;
    for (const auto& c : curves) {
      result.emplace_back();
      for (const auto& p : c) result.back().emplace_back(p.x(), p.y(), p.z());
    }
    return result;
  }
  // Meshes in general position with respect to each other (no zero predicate): the direct path.
  if (auto direct = internal::general_position_curves<K>(a, b)) {
    if (touching_points) *touching_points = 0;
    if (sites_a) *sites_a = std::move(direct->sites_a);
    if (sites_b) *sites_b = std::move(direct->sites_b);
    return chain(std::move(direct->curves));  // already oriented; chain() keeps the direction
  }
  using Point = typename K::Point_3;
  using F = typename Mesh<K>::Face_index;
  std::vector<std::vector<Point>> pieces;
  CGAL::Polygon_mesh_processing::surface_intersection(a, b, std::back_inserter(pieces));
  std::size_t touching = 0;
  for (auto& piece : pieces) {
    for (auto& p : piece) make_exact(p);  // kept points: cut the expression trees once
    if (std::all_of(piece.begin(), piece.end(), [&](const Point& p) { return p == piece.front(); })) {
      ++touching;
      if (contacts && std::find(contacts->begin(), contacts->end(), piece.front()) == contacts->end())
        contacts->push_back(piece.front());
    }
  }

  // surface_intersection returns every common point: also where the surfaces only touch, and the
  // whole common arrangement of coplanar faces. Each segment pq is classified by the faces of
  // each mesh that contain it (a segment never crosses an edge inside: that would be a curve
  // point), seen as half-planes bounded by the line pq: one face around it gives the two halves
  // of its plane, two faces with pq on their common edge give one half-plane each.
  //   - an A half-plane equal to a B half-plane (flat contact): one is the boundary of the
  //     contact region (kept), two or more is its inside (dropped);
  //   - otherwise the B half-planes on both sides of the A pair: the surfaces cross (kept), on
  //     one side: they touch (dropped, counted as touching).
  // Every test is an exact predicate on the points as given; a segment whose faces are not found
  // that way (rounded points of an inexact kernel, a border edge, a non-manifold edge) is kept.
  std::vector<std::pair<const Point*, const Point*>> segments;
  for (const auto& piece : pieces)
    for (std::size_t i = 0; i + 1 < piece.size(); ++i)
      if (!(piece[i] == piece[i + 1])) segments.emplace_back(&piece[i], &piece[i + 1]);
  using Box = CGAL::Box_intersection_d::Box_with_info_d<double, 3, std::size_t>;
  std::vector<Box> segment_boxes;
  segment_boxes.reserve(segments.size());
  CGAL::Bbox_3 all_segments;
  for (std::size_t s = 0; s < segments.size(); ++s) {
    segment_boxes.emplace_back(segments[s].first->bbox() + segments[s].second->bbox(), s);
    all_segments += segment_boxes.back().bbox();
  }
  // Fast path, certified interval arithmetic: it rules out most faces, and a segment left with one
  // candidate face in each mesh, the two planes surely different, is a crossing (the segment lies
  // on both surfaces, so each candidate contains it; where rounded points of an inexact kernel do
  // not, "kept" is the default anyway). No exact evaluation then: on a face that contains the
  // segment the exact kernel's own filters always fail.
  using I = CGAL::Interval_nt<false>;  // needs the rounding mode set by Protect_FPU_rounding
  using IP = std::array<I, 3>;
  auto interval = [](const Point& p) -> IP {
    if constexpr (std::is_same_v<K, Exact>) {
      const auto& x = CGAL::approx(p);
      return {x.x(), x.y(), x.z()};
    } else {
      return {I(CGAL::to_double(p.x())), I(CGAL::to_double(p.y())), I(CGAL::to_double(p.z()))};
    }
  };
  auto surely_off_plane = [](const std::array<IP, 3>& c, const IP& p) {  // p not in the plane of c
    const I ax = c[0][0] - p[0], ay = c[0][1] - p[1], az = c[0][2] - p[2];
    const I bx = c[1][0] - p[0], by = c[1][1] - p[1], bz = c[1][2] - p[2];
    const I cx = c[2][0] - p[0], cy = c[2][1] - p[1], cz = c[2][2] - p[2];
    const I det = ax * (by * cz - bz * cy) - ay * (bx * cz - bz * cx) + az * (bx * cy - by * cx);
    return det.inf() > 0 || det.sup() < 0;
  };
  auto face_intervals = [&](const Mesh<K>& m, F f) {
    const auto h = m.halfedge(f);
    return std::array<IP, 3>{interval(m.point(m.source(h))), interval(m.point(m.target(h))),
                             interval(m.point(m.target(m.next(h))))};
  };
  // Per segment, the faces of m that may contain it (in whose plane both ends may lie).
  auto candidate_faces = [&](const Mesh<K>& m) {
    std::vector<std::vector<F>> result(segments.size());
    std::vector<Box> face_boxes;
    for (F f : m.faces())
      if (const auto box = CGAL::Polygon_mesh_processing::face_bbox(f, m); CGAL::do_overlap(box, all_segments))
        face_boxes.emplace_back(box, std::size_t(f));
    CGAL::Protect_FPU_rounding<true> rounding;
    CGAL::box_intersection_d(segment_boxes.begin(), segment_boxes.end(), face_boxes.begin(), face_boxes.end(),
                             [&](const Box& sb, const Box& fb) {
                               const F f(static_cast<typename F::size_type>(fb.info()));
                               const auto c = face_intervals(m, f);
                               const auto& seg = segments[sb.info()];
                               if (!surely_off_plane(c, interval(*seg.first)) &&
                                   !surely_off_plane(c, interval(*seg.second)))
                                 result[sb.info()].push_back(f);
                             });
    return result;
  };
  const auto candidates_a = candidate_faces(a), candidates_b = candidate_faces(b);
  auto surely_crossing = [&](std::size_t s) {
    if (candidates_a[s].size() != 1 || candidates_b[s].size() != 1) return false;
    CGAL::Protect_FPU_rounding<true> rounding;
    const auto ca = face_intervals(a, candidates_a[s][0]), cb = face_intervals(b, candidates_b[s][0]);
    return surely_off_plane(ca, cb[0]) || surely_off_plane(ca, cb[1]) || surely_off_plane(ca, cb[2]);
  };
  // Exactly: the faces of m that contain the segment, among the candidates.
  auto faces_containing = [&](const Mesh<K>& m, const std::vector<F>& candidates, std::size_t s) {
    std::vector<F> result;
    for (F f : candidates) {
      const auto h = m.halfedge(f);
      const typename K::Triangle_3 t(m.point(m.source(h)), m.point(m.target(h)), m.point(m.target(m.next(h))));
      if (t.has_on(*segments[s].first) && t.has_on(*segments[s].second)) result.push_back(f);
    }
    return result;
  };
  // The two half-planes of m around pq, each given by a point of it off the line pq.
  auto half_planes = [](const Mesh<K>& m, const std::vector<F>& faces, const Point& p, const Point& q,
                        std::array<Point, 2>& r) {
    auto corners = [&](F f) {
      const auto h = m.halfedge(f);
      return std::array<Point, 3>{m.point(m.source(h)), m.point(m.target(h)), m.point(m.target(m.next(h)))};
    };
    if (faces.size() == 1) {  // pq inside the face: a corner on each side of it
      const auto c = corners(faces[0]);
      int off = -1, other = -1;
      for (int i = 0; i < 3 && off < 0; ++i)
        if (!CGAL::collinear(p, q, c[i])) off = i;
      if (off < 0) return false;
      for (int i = 0; i < 3 && other < 0; ++i)
        if (i != off && !CGAL::collinear(p, q, c[i]) &&
            CGAL::coplanar_orientation(p, q, c[off], c[i]) == CGAL::NEGATIVE)
          other = i;
      if (other < 0) return false;  // pq on a border edge
      r = {c[off], c[other]};
      return true;
    }
    if (faces.size() == 2) {  // pq on their common edge: the corner of each face off it
      for (int k = 0; k < 2; ++k) {
        const auto c = corners(faces[k]);
        int off = -1, count = 0;
        for (int i = 0; i < 3; ++i)
          if (!CGAL::collinear(p, q, c[i])) off = i, ++count;
        if (count != 1) return false;
        r[k] = c[off];
      }
      return true;
    }
    return false;
  };
  enum class Kind { cross, contact_boundary, contact_inside, touch };
  auto classify = [&](std::size_t s) {
    const Point &p = *segments[s].first, &q = *segments[s].second;
    if (surely_crossing(s)) return Kind::cross;
    std::array<Point, 2> ra, rb;
    if (!half_planes(a, faces_containing(a, candidates_a[s], s), p, q, ra) ||
        !half_planes(b, faces_containing(b, candidates_b[s], s), p, q, rb))
      return Kind::cross;
    int same = 0;
    for (const auto& x : ra)
      for (const auto& y : rb)
        if (CGAL::coplanar(p, q, x, y) && CGAL::coplanar_orientation(p, q, x, y) == CGAL::POSITIVE) ++same;
    // Both surfaces the same on both sides of pq: inside a flat contact, unless they bend there
    // together (a ridge of both, where two flat contacts meet at an angle): that edge is where
    // faces of A and B that are not coplanar meet, so it is kept as a curve.
    if (same >= 2)
      return CGAL::coplanar(p, q, ra[0], ra[1]) ? Kind::contact_inside : Kind::contact_boundary;
    if (same == 1) return Kind::contact_boundary;
    // Turning about pq (positive: CGAL::orientation(p, q, x, y) > 0), is y strictly inside the
    // wedge from ra[0] to ra[1]? (no B half-plane equals an A half-plane here)
    auto turn = [&](const Point& x, const Point& y) { return CGAL::orientation(p, q, x, y); };
    const auto o = turn(ra[0], ra[1]);
    if (o == CGAL::COPLANAR && CGAL::coplanar_orientation(p, q, ra[0], ra[1]) == CGAL::POSITIVE)
      return Kind::cross;  // A folded onto itself: not decided here
    auto inside = [&](const Point& y) {
      if (o == CGAL::POSITIVE) return turn(ra[0], y) == CGAL::POSITIVE && turn(y, ra[1]) == CGAL::POSITIVE;
      if (o == CGAL::NEGATIVE) return !(turn(ra[1], y) == CGAL::POSITIVE && turn(y, ra[0]) == CGAL::POSITIVE);
      return turn(ra[0], y) == CGAL::POSITIVE;  // a flat wedge: half a turn
    };
    return inside(rb[0]) != inside(rb[1]) ? Kind::cross : Kind::touch;
  };

  // Runs of kept segments are the curves' pieces; runs of touching ones are counted.
  std::vector<std::vector<Point>> kept, touched;
  std::size_t s = 0;
  for (const auto& piece : pieces) {
    std::vector<Point> run;
    int run_of = -1;  // 0 kept, 1 touching, 2 inside a flat contact
    auto flush = [&]() {
      if (run.size() >= 2 && run_of == 0) kept.push_back(run);
      if (run.size() >= 2 && run_of == 1) touched.push_back(run);
      run.clear();
    };
    for (std::size_t i = 0; i + 1 < piece.size(); ++i) {
      if (piece[i] == piece[i + 1]) continue;
      const Kind kind = classify(s++);
      const int of = kind == Kind::cross || kind == Kind::contact_boundary ? 0 : kind == Kind::touch ? 1 : 2;
      if (of != run_of) flush(), run_of = of;
      if (run.empty()) run.push_back(piece[i]);
      run.push_back(piece[i + 1]);
    }
    flush();
  }
  // Touching runs (an edge of one surface lying in a face of the other, the surfaces on one side
  // of each other there) are kept too: the outputs meet along them, so they must be curves of
  // both, or the merged outputs are not a valid complex (seam check and TetGen reject them). Only
  // isolated points of contact are not curves; they are counted (snapping must not make more).
  if (touching_points) *touching_points = touching;
  kept.insert(kept.end(), std::make_move_iterator(touched.begin()), std::make_move_iterator(touched.end()));
  auto curves = chain(std::move(kept));
  orient_curves<K>(a, b, curves);
  return curves;
}

template <class K>
std::vector<Polyline<K>> intersection_curves(const Mesh<K>& a, const Mesh<K>& b, std::size_t* touching_points) {
  return curves_and_sites<K>(a, b, touching_points, nullptr, nullptr);
}

namespace {

template <class K> double diagonal_of(const Mesh<K>& a, const Mesh<K>& b) {
  const CGAL::Bbox_3 box = CGAL::Polygon_mesh_processing::bbox(a) + CGAL::Polygon_mesh_processing::bbox(b);
  return std::sqrt(CGAL::square(box.xmax() - box.xmin()) + CGAL::square(box.ymax() - box.ymin()) +
                   CGAL::square(box.zmax() - box.zmin()));
}

/// The curve counts of a result from its curves.
template <class K> void count_curves(PairResult<K>& result) {
  auto& st = result.stats;
  st.curves = result.curves.size();
  st.closed_curves = st.curve_vertices = 0;
  for (const auto& c : result.curves) {
    const bool closed = is_closed(c);
    st.closed_curves += closed ? 1 : 0;
    st.curve_vertices += closed ? c.size() - 1 : c.size();
  }
}

/// The per-mesh figures (sizes, new faces and their angles) from the meshes as they are.
template <class K> void measure_meshes(const Mesh<K>& a, const Mesh<K>& b, PairResult<K>& result) {
  for (auto* r : {&result.a, &result.b}) {
    const Mesh<K>& m = r == &result.a ? a : b;
    const auto q = new_face_quality<K>(m);
    r->curves = result.curves;
    r->stats.output_vertices = m.number_of_vertices();
    r->stats.output_faces = m.number_of_faces();
    r->stats.min_angle_deg_new = q.min_angle_deg;
    r->stats.new_faces_below_10 = q.below_10;
    r->stats.new_faces_below_20 = q.below_20;
    r->stats.faces_added = q.new_faces;
    r->stats.curve_nodes_out = result.stats.curve_vertices;
  }
}

/// Stages 1-3 of seam::pair: the exact intersection curves, embedded into both meshes (at once),
/// and the isolated points of contact made vertices of both. Features thinner than `separation`
/// (a vertex of one mesh that close to the other surface: a crossing as thin as that cannot be
/// written in doubles, nor meshed by TetGen) are first closed: such vertices move onto the curve
/// there (exactly), and the curves are computed again.
template <class K>
PairResult<K> embed_into_both(Mesh<K>& a, Mesh<K>& b, const PairOptions& options, double separation) {
  PairResult<K> result;
  PairStats& st = result.stats;
  auto t = Clock::now();
  std::size_t touching = 0;
  internal::KnownSites<K> sites_a, sites_b;  // where each curve point lies in each mesh
  std::vector<typename K::Point_3> contacts;  // isolated points of contact
  std::vector<Polyline<K>> curves = curves_and_sites<K>(a, b, &touching, &sites_a, &sites_b, &contacts);
  if (!curves.empty() && separation > 0) {
    const auto sa = internal::snap_vertices_to_segments<K>(a, curves, separation, false, true);
    const auto sb = internal::snap_vertices_to_segments<K>(b, curves, separation, false, true);
    st.vertices_closed = sa.snapped + sb.snapped;
    st.max_close_move = std::max(sa.max_move, sb.max_move);
    if (st.vertices_closed > 0) {
      sites_a.sites.clear();
      sites_b.sites.clear();
      contacts.clear();
      curves = curves_and_sites<K>(a, b, &touching, &sites_a, &sites_b, &contacts);
    }
  }
  st.stage_seconds["intersect"] = seconds_since(t);
  if (curves.empty())
    st.note = touching > 0 ? "the meshes touch without crossing: the points of contact are made vertices of both"
                           : "the meshes do not intersect (disjoint, or one inside the other): nothing to embed";
  st.touching_only = curves.empty() && touching > 0;
  // The two embeddings are independent: they run concurrently. They share the curves, read only;
  // CGAL's lazy exact numbers are safe to read from several threads when CGAL_HAS_THREADS is
  // defined (exact values computed once, reference counts atomic).
  EmbedOptions eo = options.embed;
  eo.snap_tol = 0;
  eo.keep_all_nodes = true;
  eo.curve_tol = 0;
  eo.max_distance = std::numeric_limits<double>::max();  // the points lie on both surfaces
  double seconds_a = 0, seconds_b = 0;
  tbb::parallel_invoke(
      [&] {
        const auto ta = Clock::now();
        result.a = internal::embed_with_known_sites<K>(a, curves, eo, &sites_a);
        seconds_a = seconds_since(ta);
      },
      [&] {
        const auto tb = Clock::now();
        result.b = internal::embed_with_known_sites<K>(b, curves, eo, &sites_b);
        seconds_b = seconds_since(tb);
      });
  st.stage_seconds["embed_a"] = seconds_a;
  st.stage_seconds["embed_b"] = seconds_b;
  if (result.a.curves != result.b.curves) throw InternalError("pair: the two meshes received different curves");
  result.curves = result.a.curves;
  // Isolated points of contact: a vertex of both, and a curve of one point (see
  // internal/contact_points.h). Under the rounded kernels a point off the faces is left out (the
  // verification then fails and says so).
  if (!contacts.empty()) {
    const auto va = internal::insert_points<K>(a, contacts);
    const auto vb = va.empty() ? va : internal::insert_points<K>(b, contacts);
    if (va.size() == contacts.size() && vb.size() == contacts.size()) {
      for (std::size_t i = 0; i < contacts.size(); ++i) {
        result.curves.push_back({contacts[i]});
        result.a.curve_vertices.push_back({va[i]});
        result.b.curve_vertices.push_back({vb[i]});
      }
      st.contact_points = contacts.size();
    }
  }
  count_curves(result);
  return result;
}

/// Curve segments and edges next to the curves shorter than `length` collapse in both meshes (see
/// internal/collapse.h): written in doubles, their faces would be flat, and TetGen merges points
/// that close.
template <class K> void collapse_tiny_edges(Mesh<K>& a, Mesh<K>& b, PairResult<K>& result, double length) {
  if (result.curves.empty()) return;
  const auto t = Clock::now();
  const auto cr = internal::collapse_short_curve_segments<K>(a, b, result.curves, result.a.curve_vertices,
                                                             result.b.curve_vertices, 0.0, length, 0, 0, {}, 0, true);
  auto& st = result.stats;
  st.tiny_edges_collapsed += cr.tiny_edges_collapsed;
  st.curve_vertices_collapsed += cr.collapsed;
  if (cr.collapsed + cr.tiny_edges_collapsed > 0) count_curves(result);
  st.stage_seconds["separate"] += seconds_since(t);
}

/// Flat contacts: one common triangulation in both meshes (internal/flat_contacts.h).
template <class K> void unify_contacts(Mesh<K>& a, Mesh<K>& b, PairResult<K>& result, double separation) {
  if (result.curves.empty()) return;
  const auto t = Clock::now();
  const auto fc = internal::unify_flat_contacts<K>(a, b, separation);
  auto& st = result.stats;
  st.contact_patches = fc.patches;
  st.shared_faces = fc.shared_faces;
  st.contact_patches_left = fc.patches_left;
  if (fc.patches_left > 0) st.note += (st.note.empty() ? "" : "; ") + fc.first_left;
  st.stage_seconds["flat_contacts"] = seconds_since(t);
}

}  // namespace

template <class K>
void improve_pair(Mesh<K>& a, Mesh<K>& b, PairResult<K>& result, const PairOptions& options, const Mesh<K>* input_a,
                  const Mesh<K>* input_b) {
  if (result.curves.empty()) return;
  const auto t = Clock::now();
  // The smallest angle of each input face: a face is held to the bound or, where less, to that.
  auto angles_of = [](const Mesh<K>* input) {
    return input ? internal::face_min_angles<K>(*input) : std::vector<double>{};
  };
  const std::vector<double> angles_a = angles_of(input_a), angles_b = angles_of(input_b);
  std::vector<internal::ImproveMesh<K>> meshes{{&a, nullptr, input_a ? &angles_a : nullptr},
                                               {&b, nullptr, input_b ? &angles_b : nullptr}};
  internal::SharedCurves<K> shared{result.curves, {result.a.curve_vertices, result.b.curve_vertices}};
  ImproveOptions io = options.quality;
  io.tolerance = result.stats.snap_tol;
  io.min_angle_deg = options.embed.min_angle_deg;
  io.min_separation = min_vertex_separation * diagonal_of<K>(a, b);
  result.stats.improve = internal::improve<K>(meshes, shared, io);
  result.stats.improved = true;
  result.curves = result.a.curves = result.b.curves = shared.curves;
  result.a.curve_vertices = shared.vertices[0];
  result.b.curve_vertices = shared.vertices[1];
  count_curves(result);
  result.stats.stage_seconds["improve"] = seconds_since(t);
}

template <class K> PairResult<K> pair(Mesh<K>& a, Mesh<K>& b, const PairOptions& options) {
  check_coordinate_range<K>(a, "A");
  check_coordinate_range<K>(b, "B");
  validate_options(options.embed);
  const Mesh<K> a0 = a, b0 = b;
  const double diagonal = diagonal_of<K>(a, b), separation = min_vertex_separation * diagonal;
  const double la = mean_edge_length<K>(a), lb = mean_edge_length<K>(b);
  const double snap_tol = options.embed.snap_tol < 0 ? 0.1 * std::min(la, lb) : options.embed.snap_tol;
  // The quality stage works to angles, not to an area: with --max-area the faces are left as the
  // re-triangulation bounded them.
  const bool improve = options.improve && !(options.embed.max_area > 0);
  // Stages 1-3 on the inputs (closing features thinner than the separation, or not).
  auto embedded = [&](bool close_thin_features) {
    a = a0;
    b = b0;
    PairResult<K> r = embed_into_both<K>(a, b, options, close_thin_features ? separation : 0.0);
    r.stats.snap_tol = snap_tol;
    unify_contacts<K>(a, b, r, separation);
    return r;
  };
  // Stage 5 and the figures.
  auto finish = [&](PairResult<K>& r) {
    collapse_tiny_edges<K>(a, b, r, separation);
    measure_meshes<K>(a, b, r);
  };
  // Stage 6. Outputs that fail once written in doubles: the embedded meshes without the quality
  // stage; then the same two with features thinner than the separation closed (a vertex a few
  // units in the last place inside the other surface, say). Each is verified alike.
  std::string problem, problems;
  auto failed = [&](const std::string& what) {
    problems += (problems.empty() ? "" : "; ") + what + problem;
  };
  for (const bool close : {false, true}) {
    const std::string closed = close ? "with features thinner than the vertex separation closed" : "";
    PairResult<K> result;
    try {
      result = embedded(close);
    } catch (const InternalError& e) {  // (a flat contact that does not fit, say): the next way
      problem = e.what();
      failed(closed.empty() ? "" : closed + ": ");
      continue;
    }
    if (close && result.stats.vertices_closed == 0) break;  // the same meshes again
    std::optional<std::tuple<Mesh<K>, Mesh<K>, PairResult<K>>> before_improve;
    if (improve && options.verify_output && !result.curves.empty()) before_improve.emplace(a, b, result);
    bool improved = true;  // false: the quality stage stopped (an edit it could not make)
    try {
      if (improve) improve_pair<K>(a, b, result, options, &a0, &b0);
    } catch (const InternalError& e) {
      if (!before_improve) throw;
      problem = e.what();
      improved = false;
    }
    if (improved) finish(result);
    if (!options.verify_output) return result;
    auto passes = [&](bool without_improve) {
      if (!internal::verify_outputs<K>(a0, b0, a, b, result, problem)) return false;
      if (!problems.empty())
        result.stats.note += (result.stats.note.empty() ? "" : "; ") + std::string("seam check failed on (") +
                             problems + "): these outputs are " + (closed.empty() ? "" : closed + ", ") +
                             (without_improve ? "the embedded meshes without the quality stage" : "improved");
      return true;
    };
    if (improved && passes(false)) return result;
    failed(closed.empty() ? "" : closed + ": ");
    if (!before_improve) continue;
    a = std::move(std::get<0>(*before_improve));
    b = std::move(std::get<1>(*before_improve));
    result = std::move(std::get<2>(*before_improve));
    finish(result);
    if (passes(true)) return result;
    failed((closed.empty() ? "" : closed + ", ") + "without the quality stage: ");
    before_improve.reset();
  }
  a = a0;
  b = b0;
  throw InternalError("pair: the outputs fail seam check's tests, so none is given (" + problems + ")");
}

#define SEAM_INSTANTIATE(K)                                                                                   \
  template std::vector<Polyline<K>> intersection_curves<K>(const Mesh<K>&, const Mesh<K>&, std::size_t*);    \
  template PairResult<K> pair<K>(Mesh<K>&, Mesh<K>&, const PairOptions&);                                     \
  template void improve_pair<K>(Mesh<K>&, Mesh<K>&, PairResult<K>&, const PairOptions&, const Mesh<K>*,          \
                                const Mesh<K>*);
SEAM_INSTANTIATE(Exact)
SEAM_INSTANTIATE(Filtered)
SEAM_INSTANTIATE(Float)
#undef SEAM_INSTANTIATE

}  // namespace seam
