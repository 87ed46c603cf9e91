// seam::pair: two tows, one interface. See seam/pair.h.
// SPDX-License-Identifier: GPL-3.0-or-later
#include <seam/io.h>
#include <seam/internal/flat_contacts.h>
#include <seam/internal/collapse.h>
#include <seam/internal/contact_points.h>
#include <seam/internal/embed_known_sites.h>
#include <seam/internal/general_position_curves.h>
#include <seam/internal/improve.h>
#include <seam/internal/local_edits.h>
#include <seam/internal/provenance.h>
#include <seam/internal/snap.h>
#include <seam/internal/verify_output.h>
#include <seam/internal/thin_faces.h>
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

/// intersection_curves of `a` and `b` after a change within `tol` of `old_curves` (snapping):
/// computed on the faces of both near the old curves only. A point of the new curves lies on a
/// face that did not change (so on the old curves) or on a changed face, which has a vertex
/// within `tol` of them and is no longer than twice its longest edge at that vertex: every such
/// point is within `tol` + twice the longest edge near the curves, and the faces through it
/// overlap the old curves' boxes grown by that much. Both faces of an edge through a curve point
/// are then taken, as the classification of the pieces needs. The same curves as on the whole
/// meshes, without CGAL's work on all of their faces; where the parts meet in a contact
/// (touching points, or a curve point outside the grown boxes) the whole meshes are used.
template <class K>
std::vector<Polyline<K>> intersection_curves_near(const Mesh<K>& a, const Mesh<K>& b,
                                                  const std::vector<Polyline<K>>& old_curves, double tol,
                                                  std::size_t* touching_points,
                                                  std::vector<typename K::Point_3>* contacts) {
  using M = Mesh<K>;
  std::vector<CGAL::Bbox_3> boxes;
  for (const auto& c : old_curves) {
    CGAL::Bbox_3 box;
    for (const auto& p : c) box += p.bbox();
    boxes.push_back(box);
  }
  // The points of contact found before, wherever they are: one away from every curve would
  // otherwise be lost (it is then found as touching, and the whole meshes decide, below).
  if (contacts)
    for (const auto& p : *contacts) boxes.push_back(p.bbox());
  auto grown = [](const CGAL::Bbox_3& box, double by) {
    return CGAL::Bbox_3(box.xmin() - by, box.ymin() - by, box.zmin() - by, box.xmax() + by, box.ymax() + by,
                        box.zmax() + by);
  };
  auto overlaps = [](const std::vector<CGAL::Bbox_3>& in, const CGAL::Bbox_3& box) {
    return std::any_of(in.begin(), in.end(), [&](const CGAL::Bbox_3& b) { return CGAL::do_overlap(b, box); });
  };
  // The longest edge with an end within tol of the curves' boxes (rounded up a little).
  std::vector<CGAL::Bbox_3> near;
  for (const auto& box : boxes) near.push_back(grown(box, tol));
  double longest = 0;
  for (const M* m : {&a, &b})
    for (auto e : m->edges()) {
      const auto &p = m->point(m->vertex(e, 0)), &q = m->point(m->vertex(e, 1));
      if (overlaps(near, p.bbox()) || overlaps(near, q.bbox()))
        longest = std::max(longest, std::sqrt(CGAL::squared_distance(to_filtered(p), to_filtered(q))));
    }
  std::vector<CGAL::Bbox_3> reach;
  for (const auto& box : boxes) reach.push_back(grown(box, 1.01 * (tol + 2 * longest) + 1e-12));
  // The faces near the curves as a mesh of their own; none when Surface_mesh cannot hold them
  // (a vertex where two fans of the selection meet only there): then the whole mesh is used.
  auto faces_near = [&](const M& m) -> std::optional<M> {
    M part;
    std::vector<typename M::Vertex_index> copy(m.number_of_vertices() + m.number_of_removed_vertices(),
                                               M::null_vertex());
    for (auto f : m.faces()) {
      if (!overlaps(reach, CGAL::Polygon_mesh_processing::face_bbox(f, m))) continue;
      std::array<typename M::Vertex_index, 3> corners;
      std::size_t k = 0;
      for (auto v : CGAL::vertices_around_face(m.halfedge(f), m)) {
        auto& c = copy[std::size_t(v)];
        if (c == M::null_vertex()) c = part.add_vertex(m.point(v));
        corners[k++ % 3] = c;
      }
      if (k != 3 || part.add_face(corners[0], corners[1], corners[2]) == M::null_face()) return std::nullopt;
    }
    return part;
  };
  const auto part_a = faces_near(a), part_b = faces_near(b);
  if (!part_a || !part_b) return curves_and_sites<K>(a, b, touching_points, nullptr, nullptr, contacts);
  std::size_t touching = 0;
  auto curves = intersection_curves<K>(*part_a, *part_b, &touching);
  // Contacts (touching, or flat) are not local: one near the curves may run on past the parts'
  // borders, where a piece of it would be taken for a crossing (a point outside every grown
  // box), and the count of touching points must be that of the whole meshes. Then the whole
  // meshes decide.
  const bool all_inside = std::all_of(curves.begin(), curves.end(), [&](const Polyline<K>& c) {
    return std::all_of(c.begin(), c.end(), [&](const typename K::Point_3& p) { return overlaps(reach, p.bbox()); });
  });
  if (touching > 0 || !all_inside) return curves_and_sites<K>(a, b, touching_points, nullptr, nullptr, contacts);
  if (touching_points) *touching_points = 0;
  if (contacts) contacts->clear();
  return curves;
}

namespace {
/// seam::pair; `collapse_after_embedding` false skips the collapses of short curve segments right
/// after the embedding (not those after the remeshing, whose results are checked on their own);
/// `snap_vertices` false skips snapping (and with it the collapses right after the embedding),
/// but the tolerance still bounds the remeshing (a run done again after the snapped result failed
/// a check).
template <class K>
PairResult<K> pair_collapsing(Mesh<K>& a, Mesh<K>& b, const PairOptions& options, bool collapse_after_embedding,
                              bool snap_vertices = true, bool snap_to_doubles = false) {
  validate_options(options.embed);
  PairResult<K> result;
  // Edge snapping adds faces: each mesh face's input face, and whether its shape changed
  // (recorded only when snapping).
  std::optional<internal::FaceProvenance> prov_a, prov_b;
  PairStats& st = result.stats;
  const double la = mean_edge_length<K>(a), lb = mean_edge_length<K>(b);
  const std::size_t input_vertices_a = a.number_of_vertices(), input_vertices_b = b.number_of_vertices();
  const double snap_tol = options.embed.snap_tol < 0 ? 0.1 * std::min(la, lb) : options.embed.snap_tol;
  st.snap_tol = snap_tol;
  // With snapping, the inputs are kept: the snapped result is checked against them (and done again
  // without snapping if it fails), and remeshing must stay within the snapping tolerance of them.
  // The remeshing works to an edge length, not to an area: with --max-area the faces are left as
  // the re-triangulation bounded them (checking and redoing a remeshing it undoes took minutes).
  const bool remesh = options.remesh_near_curves && snap_tol > 0 && !(options.embed.max_area > 0);
  std::optional<Mesh<K>> input_a, input_b;
  if (snap_tol > 0) {
    input_a = a;
    input_b = b;
  }

  auto t = Clock::now();
  std::size_t touching = 0;
  // Where the curve points lie in each mesh, when the direct path knows (until a mesh changes).
  internal::KnownSites<K> sites_a, sites_b;
  std::vector<typename K::Point_3> contacts;  // isolated points of contact: embedded after the curves
  std::vector<Polyline<K>> curves = curves_and_sites<K>(a, b, &touching, &sites_a, &sites_b, &contacts);
  st.stage_seconds["intersect"] = seconds_since(t);

  // Snapping can turn a crossing into a touching contact (a vertex a few units in the last place
  // inside the other surface moves onto it; nothing would be embedded there and the outputs would
  // meet off the curves), or move a vertex so far that the curves of the snapped surfaces cannot
  // be embedded. The unsnapped state is kept to go back to in both cases.
  struct Unsnapped {
    Mesh<K> a, b;
    std::optional<internal::FaceProvenance> prov_a, prov_b;  // none: no provenance before snapping
    std::vector<Polyline<K>> curves;
    std::size_t touching;
    internal::KnownSites<K> sites_a, sites_b;
    std::vector<typename K::Point_3> contacts;
  };
  std::optional<Unsnapped> unsnapped;
  auto undo_snapping = [&](const char* why) {
    a = unsnapped->a;
    b = unsnapped->b;
    prov_a = unsnapped->prov_a;
    prov_b = unsnapped->prov_b;
    curves = unsnapped->curves;
    touching = unsnapped->touching;
    contacts = unsnapped->contacts;
    sites_a = std::move(unsnapped->sites_a);
    sites_b = std::move(unsnapped->sites_b);
    st.vertices_snapped_a = st.vertices_snapped_b = st.edges_snapped_a = st.edges_snapped_b = 0;
    st.snaps_refused = 0;
    st.note = std::string("snapping was undone: ") + why;
    unsnapped.reset();
  };
  if (snap_vertices && snap_tol > 0 && !curves.empty()) {
    unsnapped.emplace(Unsnapped{a, b, prov_a, prov_b, curves, touching, sites_a, sites_b, contacts});
    // Report step 1 on both meshes, against the exact intersection points; then the curves of
    // the moved surfaces.
    t = Clock::now();
    prov_a.emplace().start<K>(a);
    prov_b.emplace().start<K>(b);
    // Onto the closest point of the curves (they lie on both surfaces), not only their nodes,
    // which are sparse: one per crossing of an edge.
    const auto sa = internal::snap_vertices_to_segments<K>(a, curves, snap_tol, snap_to_doubles);
    const auto sb = internal::snap_vertices_to_segments<K>(b, curves, snap_tol, snap_to_doubles);
    st.vertices_snapped_a = sa.snapped;
    st.vertices_snapped_b = sb.snapped;
    st.snaps_refused = sa.refused + sb.refused;
    st.stage_seconds["snap"] = seconds_since(t);
    if (sa.snapped + sb.snapped > 0) {
      sites_a.sites.clear();  // the meshes changed
      sites_b.sites.clear();
      t = Clock::now();
      curves = intersection_curves_near<K>(a, b, curves, snap_tol, &touching, &contacts);
      st.stage_seconds["intersect"] += seconds_since(t);
    }
    // Then curve points next to an edge of either mesh get a vertex of their own (see
    // internal::snap_edges_to_points), one mesh at a time, the curves computed again after each.
    // One round per mesh (each splits an edge or a face at most once): more rounds reach the
    // features a split uncovers, but on the test crossovers they hardly change the quality and
    // each costs an intersection.
    for (int m = 0, idle = 0; m < 2 && idle < 2 && !curves.empty(); ++m) {
      t = Clock::now();
      auto& mesh = m % 2 == 0 ? a : b;
      auto& prov = m % 2 == 0 ? *prov_a : *prov_b;
      const auto se = internal::snap_edges_to_points<K>(mesh, curves, snap_tol);
      for (const auto& [added, from] : se.added) {
        prov.origin.resize(mesh.number_of_faces());
        prov.origin[std::size_t(added)] = prov.origin[std::size_t(from)];
        prov.reshaped.resize(mesh.number_of_faces(), 0);
        prov.reshaped[std::size_t(added)] = 1;
      }
      for (auto f : se.reshaped) prov.reshaped[std::size_t(f)] = 1;
      (m % 2 == 0 ? st.edges_snapped_a : st.edges_snapped_b) += se.snapped;
      idle = se.snapped > 0 ? 0 : idle + 1;
      st.snaps_refused += se.refused;
      st.stage_seconds["snap"] += seconds_since(t);
      if (se.snapped > 0) {
        sites_a.sites.clear();  // a mesh changed
        sites_b.sites.clear();
        t = Clock::now();
        curves = intersection_curves_near<K>(a, b, curves, snap_tol, &touching, &contacts);
        st.stage_seconds["intersect"] += seconds_since(t);
      }
    }
    // A crossing that snapping turned into isolated points of contact is kept (those points
    // become vertices of both, below); one that it removed altogether is not.
    if (curves.empty() && contacts.empty())
      undo_snapping("it turned the crossings into touching contacts");
    else if (st.vertices_snapped_a + st.vertices_snapped_b + st.edges_snapped_a + st.edges_snapped_b == 0)
      unsnapped.reset();  // nothing moved
  }

  auto count_curves = [&]() {
    st.curves = curves.size();
    st.closed_curves = st.curve_vertices = 0;
    for (const auto& c : curves) {
      const bool closed = is_closed(c);
      st.closed_curves += closed ? 1 : 0;
      st.curve_vertices += closed ? c.size() - 1 : c.size();
    }
  };
  count_curves();
  if (curves.empty()) {
    const bool snapped = unsnapped.has_value();  // kept: the snapped surfaces only touch
    st.touching_only = touching > 0 && !snapped;
    st.note = snapped ? "snapping turned the crossings into points of contact: they are made vertices of both"
              : touching > 0 ? "the meshes touch without crossing: the points of contact are made vertices of both"
                             : "the meshes do not intersect (disjoint, or one inside the other): nothing to embed";
  }

  // Embed the same curves into both meshes, keeping every curve point.
  EmbedOptions eo = options.embed;
  eo.snap_tol = 0;  // done above, on both meshes
  eo.keep_all_nodes = true;
  eo.curve_tol = 0;
  eo.max_distance = std::numeric_limits<double>::max();  // the points lie on both surfaces
  // The two embeddings are independent: they run concurrently. They share the curves, read
  // only; CGAL's lazy exact numbers are safe to read from several threads when
  // CGAL_HAS_THREADS is defined (exact values computed once, reference counts atomic).
  double seconds_a = 0, seconds_b = 0;
  auto embed_both = [&]() {
    tbb::parallel_invoke(
        [&] {
          const auto ta = Clock::now();
          result.a = internal::embed_with_known_sites<K>(a, curves, eo, sites_a.sites.empty() ? nullptr : &sites_a);
          seconds_a = seconds_since(ta);
        },
        [&] {
          const auto tb = Clock::now();
          result.b = internal::embed_with_known_sites<K>(b, curves, eo, sites_b.sites.empty() ? nullptr : &sites_b);
          seconds_b = seconds_since(tb);
        });
  };
  // Both meshes must receive the identical curves: what differs, or nothing.
  auto embedding_mismatch = [&]() -> std::string {
    if (result.a.curves.size() != result.b.curves.size()) return "the two meshes received different numbers of curves";
    for (std::size_t i = 0; i < result.a.curves.size(); ++i)
      if (result.a.curves[i] != result.b.curves[i]) {
        std::ostringstream msg;
        msg << "curve " << i << " was embedded differently in the two meshes (" << result.a.curves[i].size() << " and "
            << result.b.curves[i].size() << " points)";
        return msg.str();
      }
    return {};
  };
  try {
    embed_both();
    // The snapped surfaces can also receive a curve differently (one of them finding a crossing
    // the other does not; seen with a snapping tolerance 1.25 and 2 times the default at the
    // sharp edge of a lenticular tow): then, too, the unsnapped meshes are embedded.
    if (unsnapped && !embedding_mismatch().empty()) {
      undo_snapping("the curves of the snapped surfaces were embedded differently in the two meshes");
      embed_both();
    }
  } catch (const Error&) {
    if (!unsnapped) throw;
    undo_snapping("the curves of the snapped surfaces could not be embedded");
    embed_both();
  }
  unsnapped.reset();
  count_curves();  // those of the unsnapped meshes if snapping was undone
  st.stage_seconds["embed_a"] = seconds_a;
  st.stage_seconds["embed_b"] = seconds_b;
  result.a.stats.vertices_snapped = st.vertices_snapped_a + st.edges_snapped_a;
  result.b.stats.vertices_snapped = st.vertices_snapped_b + st.edges_snapped_b;

  if (const std::string mismatch = embedding_mismatch(); !mismatch.empty()) throw InternalError("pair: " + mismatch);
  result.curves = result.a.curves;

  // Isolated points of contact: a vertex of both, and a curve of one point (see
  // internal/contact_points.h). Under the rounded kernels a point off the faces is left out
  // (the verification then fails and says so).
  if (!contacts.empty()) {
    Mesh<K> a0 = a, b0 = b;
    const auto va = internal::insert_points<K>(a, contacts);
    const auto vb = va.empty() ? va : internal::insert_points<K>(b, contacts);
    if (va.size() == contacts.size() && vb.size() == contacts.size()) {
      for (std::size_t i = 0; i < contacts.size(); ++i) {
        for (auto* r : {&result.a, &result.b}) {
          r->curves.push_back({contacts[i]});
          r->curve_vertices.push_back({r == &result.a ? va[i] : vb[i]});
        }
        result.curves.push_back({contacts[i]});
      }
      st.contact_points = contacts.size();
      st.curves += contacts.size();
      st.curve_vertices += contacts.size();
    } else {
      a = std::move(a0);
      b = std::move(b0);
    }
  }


  // After collapses of curve segments: both meshes' curves, the curve vertex count and the sizes.
  auto recount_after_collapses = [&]() {
    result.a.curves = result.b.curves = result.curves;
    st.curve_vertices = 0;
    for (const auto& c : result.curves) st.curve_vertices += is_closed(c) ? c.size() - 1 : c.size();
    for (auto* r : {&result.a, &result.b}) {
      const auto& m = r == &result.a ? a : b;
      r->stats.output_vertices = m.number_of_vertices();
      r->stats.output_faces = m.number_of_faces();
      r->stats.curve_nodes_out = st.curve_vertices;
    }
  };
  // With a snapping tolerance, curve segments shorter than it are collapsed in both meshes at
  // once where that improves the angles and the meshes still meet only along the curves (see
  // internal/collapse.h): a crossing of A's edge next to a crossing of B's edge otherwise leaves
  // a sliver no re-triangulation avoids.
  if (prov_a) {
    t = Clock::now();
    // Edges below 1e-9 of the size of the pair go whatever the angles: written in doubles they
    // would be flat or fold (see internal/collapse.h).
    const CGAL::Bbox_3 box = CGAL::Polygon_mesh_processing::bbox(a) + CGAL::Polygon_mesh_processing::bbox(b);
    const double diagonal = std::sqrt(CGAL::square(box.xmax() - box.xmin()) + CGAL::square(box.ymax() - box.ymin()) +
                                      CGAL::square(box.zmax() - box.zmin()));
    const auto cr = internal::collapse_short_curve_segments<K>(a, b, result.curves, result.a.curve_vertices,
                                                               result.b.curve_vertices,
                                                               options.collapse_short_segments && collapse_after_embedding ? snap_tol : 0.0,
                                                               1e-9 * diagonal,
                                                               input_vertices_a, input_vertices_b);
    st.curve_vertices_collapsed = cr.collapsed;
    st.tiny_edges_collapsed = cr.tiny_edges_collapsed;
    st.short_segments_left = cr.refused;
    if (cr.collapsed + cr.tiny_edges_collapsed > 0) {
      recount_after_collapses();
    }
    st.stage_seconds["collapse"] = seconds_since(t);
    // Faces mapped back to the input faces, quality measured against the input's own angles.
    prov_a->apply<K>(a, result.a.stats);
    prov_b->apply<K>(b, result.b.stats);
  }

  // Flat contacts (faces of both in one plane, overlapping): one common triangulation in both,
  // its faces shared (see internal/flat_contacts.h); the steps below leave them alone.
  if (!result.curves.empty()) {
    t = Clock::now();
    const CGAL::Bbox_3 box = CGAL::Polygon_mesh_processing::bbox(a) + CGAL::Polygon_mesh_processing::bbox(b);
    const double diagonal = std::sqrt(CGAL::square(box.xmax() - box.xmin()) + CGAL::square(box.ymax() - box.ymin()) +
                                      CGAL::square(box.zmax() - box.zmin()));
    const auto fc = internal::unify_flat_contacts<K>(a, b, min_vertex_separation * diagonal);
    st.contact_patches = fc.patches;
    st.shared_faces = fc.shared_faces;
    st.contact_patches_left = fc.patches_left;
    if (fc.patches_left > 0) st.note += (st.note.empty() ? "" : "; ") + fc.first_left;
    if (fc.patches > 0)
      for (auto* r : {&result.a, &result.b}) {
        const auto& m = r == &result.a ? a : b;
        const auto q = new_face_quality<K>(m);
        r->stats.output_vertices = m.number_of_vertices();
        r->stats.output_faces = m.number_of_faces();
        r->stats.min_angle_deg_new = q.min_angle_deg;
        r->stats.new_faces_below_10 = q.below_10;
        r->stats.new_faces_below_20 = q.below_20;
        r->stats.faces_added = q.new_faces;
      }
    st.stage_seconds["flat_contacts"] = seconds_since(t);
  }

  // Experimental: coarsen the curve to about the edge length and remesh both meshes next to it
  // (see internal/improve.h and PairOptions::remesh_near_curves). Kept only when both succeed.
  auto add_note = [&](const std::string& sentence) { st.note += (st.note.empty() ? "" : "; ") + sentence; };

  // Snapping moves vertices, which the embedding then takes as given: a moved vertex can make a
  // surface meet itself, or the other one off the curves. The snapped result is checked with
  // seam check's own tests (on the whole meshes, once) and, if it fails, done again without
  // the collapses of short curve segments (if any), and failing that without snapping (the curves
  // are still coarsened and the meshes remeshed within the tolerance).
  const bool snapped = st.vertices_snapped_a + st.vertices_snapped_b + st.edges_snapped_a + st.edges_snapped_b > 0;
  // The run done again from the inputs (snapped results that fail a check), `why` first in its note.
  auto redo_from_inputs = [&](const PairOptions& redo_options, bool redo_collapse_after_embedding,
                              bool redo_snap_vertices, const std::string& why) {
    a = *input_a;
    b = *input_b;
    PairResult<K> redone =
        pair_collapsing<K>(a, b, redo_options, redo_collapse_after_embedding, redo_snap_vertices, snap_to_doubles);
    redone.stats.note = why + (redone.stats.note.empty() ? "" : "; " + redone.stats.note);
    return redone;
  };
  PairOptions unsnapped_options = options;
  unsnapped_options.embed.snap_tol = 0;
  // Collapses of short curve segments change the embedded meshes too (also without snapping).
  // (Each run done again has fewer changes: no collapses, then no snapping, then neither.)
  const bool collapsed_segments =
      collapse_after_embedding && options.collapse_short_segments && st.curve_vertices_collapsed > 0;
  if ((snapped || collapsed_segments) && !result.curves.empty()) {
    t = Clock::now();
    // (Check 4, the distances from the inputs, and the figures are not needed: an empty focus.)
    const CheckFocus whole_meshes;
    PairCheckReport report;
    try {
      report = check_pair<K>(*input_a, *input_b, a, b, result.curves, std::numeric_limits<double>::infinity(),
                             &whole_meshes);
    } catch (const InternalError& e) {  // the check could not be done (rounded kernels): a failure
      report.problems.push_back(e.what());
    }
    st.stage_seconds["verify"] = seconds_since(t);
    // (Once: the run done again has no collapses right after the embedding, so it cannot come
    // back here; tiny segments are counted as collapses too, and are collapsed again there.)
    if (!report.ok() && collapsed_segments) {
      // The collapses tilt faces by up to the snapping tolerance, which can make a surface meet
      // itself (they are tested against the other mesh only): done again without them first. The
      // collapses after the remeshing stay: each remeshing attempt is checked as a whole.
      return redo_from_inputs(options, false, snap_vertices,
                              "short curve segments were kept after the embedding: with them collapsed the result "
                              "failed seam check's tests (" +
                                  report.problems.front() + ")");
    }
    // Without snapping the curves are still coarsened and both meshes remeshed next to them,
    // within the tolerance (before, snapping was undone by setting the tolerance to 0, which
    // turned the remeshing off too: on CT tows, 36% of the new faces below 10 degrees).
    if (!report.ok())
      return redo_from_inputs(options, true, false,
                              "snapping was undone: the snapped result failed seam check's tests (" +
                                  report.problems.front() + ")");
  }

  if (remesh && !result.curves.empty()) {
    t = Clock::now();
    // The coarse curve: points about the smaller edge length apart, its chords within the snapping
    // tolerance of the curve.
    const double spacing = std::min(la, lb);
    const auto chosen = internal::choose_curve_points<K>(result.curves, spacing, snap_tol);
    const internal::SurfaceDistance surface_a(internal::triangles_of<K>(*input_a)),
        surface_b(internal::triangles_of<K>(*input_b));
    // Positions kept besides the chosen ones: refused collapses (they would break a surface), and
    // where an attempt failed (the meshes crossed, or strayed from the inputs): first all the
    // embedded points there are kept (the remeshing still runs), then, if it fails there again,
    // the stretch is frozen (left as embedded), and if it still fails there, the faces next to it
    // are frozen for the steps after the remeshing too (frozen value 2; see
    // internal::frozen_face_property). (Freezing those faces at once leaves the faces next to a
    // frozen stretch as embedded, thin ones among them, where the steps would have mended them.)
    std::vector<std::vector<std::size_t>> also_kept(result.curves.size());
    std::vector<std::vector<char>> keep_all(result.curves.size()), frozen(result.curves.size());
    for (std::size_t c = 0; c < result.curves.size(); ++c) {
      frozen[c].assign(result.curves[c].size() - (is_closed(result.curves[c]) ? 1 : 0), 0);
      keep_all[c] = frozen[c];
    }
    std::vector<std::vector<std::size_t>> refused;
    auto keep_refused_too = [&]() {
      for (std::size_t c = 0; c < also_kept.size(); ++c)
        also_kept[c].insert(also_kept[c].end(), refused[c].begin(), refused[c].end());
    };
    // How escalate_near moves a curve position: one stage on (embedded -> kept -> frozen), frozen
    // -> frozen with its faces (frozen value 2), or any stage straight to that.
    enum class Escalation { one_stage, frozen_to_faces, straight_to_faces };
    // Escalates the curve positions within `radius` of a vertex of a failing face; returns how
    // many changed.
    auto escalate_near = [&](const Mesh<K>& m, const std::vector<std::size_t>& faces, double radius, Escalation how) {
      std::vector<Filtered::Point_3> near;
      for (std::size_t f : faces)
        for (auto v : CGAL::vertices_around_face(m.halfedge(typename Mesh<K>::Face_index(f)), m))
          near.push_back(to_filtered(m.point(v)));
      std::size_t count = 0;
      for (std::size_t c = 0; c < frozen.size(); ++c)
        for (std::size_t i = 0; i < frozen[c].size(); ++i) {
          const char stage = frozen[c][i];
          if (how == Escalation::one_stage ? stage != 0
              : how == Escalation::frozen_to_faces ? stage != 1
                                                   : stage == 2)
            continue;
          const auto p = to_filtered(result.curves[c][i]);
          for (const auto& q : near)
            if (CGAL::squared_distance(p, q) < radius * radius) {
              if (how == Escalation::one_stage)
                (keep_all[c][i] ? frozen[c][i] : keep_all[c][i]) = 1;
              else
                keep_all[c][i] = 1, frozen[c][i] = 2;
              ++count;
              break;
            }
        }
      return count;
    };
    // The curves as points of a mesh, from its curve vertices.
    auto curves_of = [](const Mesh<K>& m, const std::vector<std::vector<typename Mesh<K>::Vertex_index>>& cv) {
      std::vector<Polyline<K>> curves;
      for (const auto& vs : cv) {
        curves.emplace_back();
        for (auto v : vs) curves.back().push_back(m.point(v));
      }
      return curves;
    };
    constexpr int max_attempts = 16;
    for (int attempt = 0; attempt < max_attempts; ++attempt) {
      auto kept = chosen;
      for (std::size_t c = 0; c < kept.size(); ++c) {
        kept[c].insert(kept[c].end(), also_kept[c].begin(), also_kept[c].end());
        for (std::size_t i = 0; i < keep_all[c].size(); ++i)
          if (keep_all[c][i]) kept[c].push_back(i);
        std::sort(kept[c].begin(), kept[c].end());
        kept[c].erase(std::unique(kept[c].begin(), kept[c].end()), kept[c].end());
      }
      Mesh<K> a2 = a, b2 = b;
      auto cva = result.a.curve_vertices, cvb = result.b.curve_vertices;
      // The faces of a2 and b2 that seam check's tests need to see: remeshed, or reshaped by a
      // step after the remeshing (the rest passed the check before).
      auto focus_on_changed_faces = [&]() {
        CheckFocus focus;
        for (auto [m, marks] : {std::make_pair(&a2, &focus.faces_a), std::make_pair(&b2, &focus.faces_b)}) {
          const auto source = m->template property_map<typename Mesh<K>::Face_index, std::uint32_t>(source_face_property).first;
          marks->assign(m->number_of_faces() + m->number_of_removed_faces(), 0);
          const auto is_new = m->template property_map<typename Mesh<K>::Face_index, bool>(new_face_property).first;
          for (auto f : m->faces())
            (*marks)[std::size_t(f)] = source[f] == std::numeric_limits<std::uint32_t>::max() || is_new[f];
        }
        return focus;
      };
      // CGAL's remeshing on rounded coordinates can fail its own assertions on a degenerate
      // band: that attempt then counts as a failure of the remeshing, the embedded meshes stay.
      bool coarsened = false;
      try {
        coarsened = internal::coarsen_and_remesh_near_curves<K>(a2, cva, kept, frozen, la, refused) &&
                    internal::coarsen_and_remesh_near_curves<K>(b2, cvb, kept, frozen, lb, refused);
        if (coarsened) {
          // Remeshed faces that cut across bends of the input surface: split them, their new
          // vertices on the input surface, until within the snapping tolerance (up to eight rounds:
          // at the sharp edge of a lenticular tow fewer leave faces outside).
          internal::split_edges_off_surface<K>(a2, cva, surface_a, snap_tol, 8);
          internal::split_edges_off_surface<K>(b2, cvb, surface_b, snap_tol, 8);
          // Then smoothing (vertices inside the remeshed band towards the centroid of their
          // neighbours, on the input surface) and edge flips between remeshed faces, each where it
          // raises the smallest angle and stays within the tolerance (CGAL's remeshing aims at edge
          // lengths and valences, not angles), twice.
          for (int pass = 0; pass < 2; ++pass) {
            internal::smooth_remeshed_vertices<K>(a2, cva, surface_a, snap_tol, 2);
            internal::smooth_remeshed_vertices<K>(b2, cvb, surface_b, snap_tol, 2);
            internal::flip_to_improve_angles<K>(a2, cva, surface_a, snap_tol, 2);
            internal::flip_to_improve_angles<K>(b2, cvb, surface_b, snap_tol, 2);
          }
          // Thin faces left (a needle's short edge, often from the splits at a sharp bend; a cap
          // no flip removes; a vertex close to the curve): merge the ends of one of their edges,
          // then move their vertices where their faces are better (a search on the surface), then
          // smooth and flip once more around them.
          const double thin = options.embed.min_angle_deg;
          constexpr double target_min_angle = 10;  // issue #3: no new face below 10 degrees
          auto merge_thin_faces = [&](Mesh<K>& m, std::vector<std::vector<typename Mesh<K>::Vertex_index>>& cv,
                                      const internal::SurfaceDistance& surface) {
            const bool merged = internal::collapse_short_edges_of_thin_faces<K>(m, cv, surface, snap_tol, thin, 3) > 0;
            const bool moved = internal::relocate_vertices_of_thin_faces<K>(m, cv, surface, snap_tol, thin, 4) > 0;
            if (merged || moved) {
              internal::smooth_remeshed_vertices<K>(m, cv, surface, snap_tol, 2);
              internal::flip_to_improve_angles<K>(m, cv, surface, snap_tol, 2);
            }
          };
          merge_thin_faces(a2, cva, surface_a);
          merge_thin_faces(b2, cvb, surface_b);
          // Curve segments still short (kept by the coarsening, or frozen): collapsed in both
          // meshes where that raises the angles and crosses nothing, as after the embedding
          // (internal/collapse.h), any curve vertex this time, and both ends may merge at a point
          // between them (the faces of both share the move). Segments shorter than half the
          // spacing (the coarsening's own lower bound) are tried, and each changed face must stay
          // within the tolerance of its input surface (corners, edge middles and centroid,
          // doubles): the chords of the coarser curve then lie within it too. The thin faces
          // around them are merged again.
          const internal::MergedFaceTest near_inputs = [&](int m, const Filtered::Point_3& p,
                                                           const Filtered::Point_3& q, const Filtered::Point_3& r) {
            return (m == 0 ? surface_a : surface_b).sampled_distance(p, q, r) <= snap_tol;
          };
          auto collapse_then_merge = [&](double max_length, double only_next_to_faces_below) {
            std::vector<Polyline<K>> coarse = curves_of(a2, cva);
            if (internal::collapse_short_curve_segments<K>(a2, b2, coarse, cva, cvb, max_length, 0.0, 0, 0, near_inputs,
                                                          only_next_to_faces_below).collapsed > 0) {
              merge_thin_faces(a2, cva, surface_a);
              merge_thin_faces(b2, cvb, surface_b);
            }
          };
          if (options.collapse_short_segments) {
            collapse_then_merge(0.5 * spacing, 0);
            // A curve vertex still at a corner of a face below 10 degrees (a cap of three curve
            // vertices at a bend of the curve, say): a segment of it up to twice the spacing long
            // is collapsed too, under the same tests.
            collapse_then_merge(2 * spacing, target_min_angle);
          }
          // Caps left standing on a curve segment (where the curve leaves a sharp edge of the
          // surface at a small angle, say): the segment is split in both meshes under the cap's
          // apex, which moves onto it.
          if (internal::split_curve_segments_under_caps<K>(a2, b2, cva, cvb, surface_a, surface_b, snap_tol, thin) > 0) {
            merge_thin_faces(a2, cva, surface_a);
            merge_thin_faces(b2, cvb, surface_b);
          }
          // A last round of merges and moves: the smoothing and flips after the previous round,
          // and the collapses and splits of curve segments since, can open merges that were not
          // allowed before.
          merge_thin_faces(a2, cva, surface_a);
          merge_thin_faces(b2, cvb, surface_b);
          // Faces still below 10 degrees: an edge at their smallest angle is split at its middle,
          // then flips.
          internal::split_edges_of_thin_faces<K>(a2, cva, surface_a, snap_tol, target_min_angle);
          internal::split_edges_of_thin_faces<K>(b2, cvb, surface_b, snap_tol, target_min_angle);
        }
      } catch (const CGAL::Failure_exception&) {
        add_note("remeshing next to the curves failed (a CGAL assertion); the embedded meshes are kept");
        break;
      } catch (const std::exception& e) {  // InternalError from a step: the embedded meshes stay
        add_note(std::string("remeshing next to the curves failed (") + e.what() + "); the embedded meshes are kept");
        break;
      }
      if (!coarsened) {
        if (std::all_of(refused.begin(), refused.end(), [](const auto& r) { return r.empty(); })) {
          add_note("remeshing next to the curves failed; the embedded meshes are kept");
          break;
        }
        keep_refused_too();
        continue;
      }
      const std::vector<Polyline<K>> ca = curves_of(a2, cva), cb = curves_of(b2, cvb);
      if (!(ca == cb)) {
        add_note("remeshing next to the curves failed (the two curves differ); the embedded meshes are kept");
        break;
      }
      // Accept the remeshed pair only if it passes seam check's tests (valid, no self-intersection,
      // meeting only along the curves); otherwise freeze the curve next to the conflicting faces
      // and try again.
      // Only the faces that changed need checking when the rest passed the check above; without
      // snapping nothing was checked, and the empty focus takes all faces. Check 4 is not needed.
      const CheckFocus focus = snapped ? focus_on_changed_faces() : CheckFocus{};
      PairCheckReport report;
      try {
        report = check_pair<K>(a, b, a2, b2, ca, std::numeric_limits<double>::infinity(), &focus);
      } catch (const InternalError&) {  // the check could not be done (rounded kernels)
        add_note("remeshing next to the curves failed (its check could not be done); the embedded meshes are kept");
        break;
      }
      // Nor may a remeshed face stray farther than the snapping tolerance from its input surface
      // (a flip across a bend of the surface, say).
      double deviation_a = 0, deviation_b = 0;
      std::vector<std::size_t> off_a, off_b;
      if (report.ok()) {
        off_a = internal::remeshed_faces_off_surface<K>(a2, surface_a, snap_tol, deviation_a);
        off_b = internal::remeshed_faces_off_surface<K>(b2, surface_b, snap_tol, deviation_b);
      }
      if (!report.ok() || !off_a.empty() || !off_b.empty()) {
        auto& faces_a = report.ok() ? off_a : report.conflict_faces_a;
        auto& faces_b = report.ok() ? off_b : report.conflict_faces_b;
        // Within half the spacing of the failing faces: positions kept, or frozen; where all are
        // frozen already, their faces frozen too; then farther away. In the last quarter of the
        // attempts (long curves on real tows with many places to mend: one step at a time would
        // run out of attempts and undo all of the remeshing), each position goes straight to the
        // last stage.
        const double near_radius = 0.5 * spacing;
        const Escalation how = 4 * (attempt + 1) >= 3 * max_attempts ? Escalation::straight_to_faces
                                                                     : Escalation::one_stage;
        auto escalate_both = [&](double radius, Escalation e) {
          return escalate_near(a2, faces_a, radius, e) + escalate_near(b2, faces_b, radius, e);
        };
        std::size_t newly = escalate_both(near_radius, how);
        if (newly == 0 && how == Escalation::one_stage) newly = escalate_both(near_radius, Escalation::frozen_to_faces);
        for (double radius = 2 * near_radius; newly == 0 && radius < 1e3 * spacing; radius *= 2)
          newly = escalate_both(radius, how);
        if (newly == 0 || attempt + 1 == max_attempts) {
          add_note(report.ok() ? "remeshing next to the curves was undone: it moved the surfaces farther than the "
                                 "snapping tolerance"
                               : "remeshing next to the curves was undone: the remeshed meshes crossed off the curves");
          break;
        }
        continue;
      }
      st.remesh_max_deviation = std::max(deviation_a, deviation_b);
      for (Mesh<K>* m : {&a2, &b2})  // (the steps' business only)
        if (auto [frozen_faces, found] =
                m->template property_map<typename Mesh<K>::Face_index, bool>(internal::frozen_face_property);
            found)
          m->remove_property_map(frozen_faces);
      a = std::move(a2);
      b = std::move(b2);
      result.curves = ca;
      result.a.curves = ca;
      result.b.curves = cb;
      result.a.curve_vertices = cva;
      result.b.curve_vertices = cvb;
      st.remeshed = true;
      for (const auto& f : frozen)  // (frozen, with or without their faces)
        st.curve_vertices_frozen += std::size_t(std::count_if(f.begin(), f.end(), [](char x) { return x != 0; }));
      st.remesh_attempts = std::size_t(attempt + 1);
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
      break;
    }
    st.stage_seconds["remesh"] = seconds_since(t);
  }

  // No two output vertices closer than a volume mesher's tolerance (min_vertex_separation of the
  // pair's size, TetGen's -T twice over): tiny edges left by the exact constructions are
  // collapsed, and a vertex that close to a curve point merges into it (moving by that much at
  // most). Nothing changes where there are none.
  if (!result.curves.empty()) {
    t = Clock::now();
    const CGAL::Bbox_3 box = CGAL::Polygon_mesh_processing::bbox(a) + CGAL::Polygon_mesh_processing::bbox(b);
    const double diagonal = std::sqrt(CGAL::square(box.xmax() - box.xmin()) + CGAL::square(box.ymax() - box.ymin()) +
                                      CGAL::square(box.zmax() - box.zmin()));
    const auto cr = internal::collapse_short_curve_segments<K>(a, b, result.curves, result.a.curve_vertices,
                                                               result.b.curve_vertices, 0.0,
                                                               min_vertex_separation * diagonal, 0, 0, {}, 0, true);
    if (cr.collapsed + cr.tiny_edges_collapsed > 0) {
      st.tiny_edges_collapsed += cr.tiny_edges_collapsed;
      st.curve_vertices_collapsed += cr.collapsed;
      recount_after_collapses();
    }
    st.stage_seconds["separate"] = seconds_since(t);
  }

  // The outputs are written in doubles. Snapped surfaces meet along nearly coplanar faces, and
  // where the remeshing did not run (it failed, or the curve was frozen) the exact points of the
  // embedding stay: rounded, a few can make a surface meet itself, or the other one off the
  // curves. Under the exact kernel the faces with a corner that rounding moves are checked again
  // on the rounded meshes (seam check's tests). A failure undoes snapping (the run is done again
  // without it, still remeshed), or, without snapping, the remeshing.
  if constexpr (kernel_traits<K>::exact_constructions) {
    if ((snapped || st.remeshed) && !result.curves.empty()) {
      t = Clock::now();
      // Each point's exact value is computed first (the lazy representations are shared with
      // a, b and the curves): CGAL::to_double then rounds it the same way here and when the
      // outputs are written, whatever the approximation held before.
      auto round = [](typename K::Point_3 p) {
        make_exact(p);
        return typename K::Point_3(CGAL::to_double(p.x()), CGAL::to_double(p.y()), CGAL::to_double(p.z()));
      };
      CheckFocus moved;
      bool any_moved = false;
      Mesh<K> ra = a, rb = b;
      for (auto [m, marks] : {std::make_pair(&ra, &moved.faces_a), std::make_pair(&rb, &moved.faces_b)}) {
        marks->assign(m->number_of_faces() + m->number_of_removed_faces(), 0);
        std::vector<char> vertex_moved(m->number_of_vertices() + m->number_of_removed_vertices(), 0);
        for (auto v : m->vertices()) {
          const auto r = round(m->point(v));
          if (r == m->point(v)) continue;  // exact comparison: the point is a double already
          m->point(v) = r;
          vertex_moved[std::size_t(v)] = 1;
        }
        for (auto f : m->faces())
          for (auto v : CGAL::vertices_around_face(m->halfedge(f), *m))
            if (vertex_moved[std::size_t(v)]) (*marks)[std::size_t(f)] = 1, any_moved = true;
      }
      if (any_moved) {
        std::vector<Polyline<K>> rounded_curves = result.curves;
        for (auto& c : rounded_curves)
          for (auto& p : c) p = round(p);
        PairCheckReport report;
        try {
          report = check_pair<K>(*input_a, *input_b, ra, rb, rounded_curves, std::numeric_limits<double>::infinity(),
                                 &moved);
        } catch (const InternalError& e) {  // the check could not be done: a failure
          report.problems.push_back(e.what());
        }
        st.stage_seconds["verify_rounded"] = seconds_since(t);
        // Done again without snapping (still remeshed), and if that fails too, as embedded.
        if (!report.ok())
          return redo_from_inputs(snapped ? options : unsnapped_options, true, false,
                                  std::string(snapped ? "snapping was undone" : "the remeshing was undone") +
                                      ": the result, rounded to doubles, failed seam check's tests (" +
                                      report.problems.front() + ")");
      }
    }
  }
  return result;
}
}  // namespace

template <class K> PairResult<K> pair(Mesh<K>& a, Mesh<K>& b, const PairOptions& options) {
  check_coordinate_range<K>(a, "A");
  check_coordinate_range<K>(b, "B");
  if (!options.verify_output) return pair_collapsing<K>(a, b, options, true);
  const Mesh<K> a0 = a, b0 = b;
  PairResult<K> result = pair_collapsing<K>(a, b, options, true);
  std::string problem;
  if (internal::verify_outputs<K>(a0, b0, a, b, result, problem)) return result;
  // Snapping and the remeshing move vertices: done again without snapping (still remeshed within
  // the tolerance), then without either (the outputs are then the input surfaces, cut along the
  // exact curves). An exact result can still fail once rounded to doubles (a sliver of crossing
  // thinner than a unit in the last place): last, snapped at the vertex separation of check 5
  // (TetGen's tolerance, twice over), which no volume mesher resolves anyway: first onto the
  // exact points of the curves, then onto those points rounded to doubles (which can leave a
  // vertex a unit in the last place off the other surface, and the curve beside it). At most
  // four runs more, so this ends.
  const CGAL::Bbox_3 box = CGAL::Polygon_mesh_processing::bbox(a0) + CGAL::Polygon_mesh_processing::bbox(b0);
  const double diagonal = std::sqrt(CGAL::square(box.xmax() - box.xmin()) + CGAL::square(box.ymax() - box.ymin()) +
                                    CGAL::square(box.zmax() - box.zmin()));
  struct Redo {
    PairOptions options;
    bool snap_vertices;
    const char* what;
    bool to_doubles = false;
  };
  std::vector<Redo> redos;
  PairOptions unsnapped = options, minimal = options;
  unsnapped.embed.snap_tol = 0;
  minimal.embed.snap_tol = min_vertex_separation * diagonal;
  minimal.remesh_near_curves = false;
  if (result.stats.snap_tol > 0) {
    redos.push_back({options, false, "done again without snapping"});
    redos.push_back({unsnapped, true, "done again without snapping or remeshing"});
  }
  if (result.stats.snap_tol != minimal.embed.snap_tol) {
    redos.push_back({minimal, true, "done again snapped at the vertex separation only"});
    redos.push_back({minimal, true, "done again snapped at the vertex separation only, onto doubles", true});
  }
  std::string tried;
  for (const Redo& redo : redos) {
    tried += (tried.empty() ? "" : "; then ") + problem;
    a = a0;
    b = b0;
    PairResult<K> again;
    bool verified = false;
    try {  // the inputs passed the first run's checks: any error now is the redo's own
      again = pair_collapsing<K>(a, b, redo.options, true, redo.snap_vertices, redo.to_doubles);
      again.stats.note = std::string(redo.what) + ": the result failed seam check's tests (" + tried + ")" +
                         (again.stats.note.empty() ? "" : "; " + again.stats.note);
      again.stats.stage_seconds["verify_output"] = result.stats.stage_seconds["verify_output"];
      verified = internal::verify_outputs<K>(a0, b0, a, b, again, problem);
    } catch (const std::bad_alloc&) {
      a = a0;
      b = b0;
      throw;
    } catch (const std::exception& e) {  // seam's errors and CGAL's failures alike
      problem = std::string(redo.what) + ": " + e.what();
      continue;
    }
    if (verified) return again;
    problem = std::string(redo.what) + ": " + problem;
  }
  a = a0;
  b = b0;
  tried += (tried.empty() ? "" : "; then ") + problem;
  throw InternalError("pair: the outputs fail seam check's tests, so none is given (" + tried + ")");
}

#define SEAM_INSTANTIATE(K)                                                                       \
  template std::vector<Polyline<K>> intersection_curves<K>(const Mesh<K>&, const Mesh<K>&, std::size_t*); \
  template PairResult<K> pair<K>(Mesh<K>&, Mesh<K>&, const PairOptions&);
SEAM_INSTANTIATE(Exact)
SEAM_INSTANTIATE(Filtered)
SEAM_INSTANTIATE(Float)
#undef SEAM_INSTANTIATE

}  // namespace seam
