// seam: the intersection curves of two triangle meshes (pair stage 1). See
// seam/internal/intersection_curves.h and, for what the curves are, seam/pair.h.
// SPDX-License-Identifier: GPL-3.0-or-later
#include <seam/internal/general_position_curves.h>
#include <seam/internal/intersection_curves.h>
#include <seam/internal/triangle_predicates.h>

#include <CGAL/box_intersection_d.h>
#include <CGAL/Polygon_mesh_processing/bbox.h>
#include <CGAL/Polygon_mesh_processing/intersection.h>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#ifndef CGAL_HAS_THREADS
#error "intersection_curves evaluates lazy exact points on several threads: CGAL must be thread-aware"
#endif

#include <algorithm>
#include <array>
#include <map>
#include <set>
#include <type_traits>
#include <utility>
#include <vector>

namespace seam {
namespace internal {
namespace {

// Certified interval tests of this file. The curve computation has its own, as seam check has
// its own (seam/internal/certified.h): the verification shares no code with what it verifies.
using CI = CGAL::Interval_nt<false>;  // needs the rounding mode set by Protect_FPU_rounding
using CIP = std::array<CI, 3>;

/// Intervals that hold the point's coordinates (under Exact its approximation).
template <class P> CIP interval_of(const P& p) {
  if constexpr (std::is_same_v<typename CGAL::Kernel_traits<P>::Kernel, Exact>) {
    const auto& x = CGAL::approx(p);
    return {x.x(), x.y(), x.z()};
  } else {
    return {CI(CGAL::to_double(p.x())), CI(CGAL::to_double(p.y())), CI(CGAL::to_double(p.z()))};
  }
}

/// The sign of x when certain, else 0.
inline int sure_sign(const CI& x) { return x.inf() > 0 ? 1 : (x.sup() < 0 ? -1 : 0); }

/// Point p surely lies off the plane of (a, b, c). Needs Protect_FPU_rounding.
inline bool surely_off_plane(const CIP& a, const CIP& b, const CIP& c, const CIP& p) {
  const CI ax = a[0] - p[0], ay = a[1] - p[1], az = a[2] - p[2];
  const CI bx = b[0] - p[0], by = b[1] - p[1], bz = b[2] - p[2];
  const CI cx = c[0] - p[0], cy = c[1] - p[1], cz = c[2] - p[2];
  return sure_sign(ax * (by * cz - bz * cy) - ay * (bx * cz - bz * cx) + az * (bx * cy - by * cx)) != 0;
}

/// Point p surely lies off the closed triangle (a, b, c): off its plane, or, in an axis projection
/// where the triangle is surely not degenerate (one to one on its plane), strictly beyond one of
/// its edges. False when not certain.
inline bool surely_off_triangle(const CIP& a, const CIP& b, const CIP& c, const CIP& p) {
  CGAL::Protect_FPU_rounding<true> rounding;
  if (surely_off_plane(a, b, c, p)) return true;
  auto orient2 = [](const CIP& u, const CIP& v, const CIP& w, int i, int j) {
    return (v[i] - u[i]) * (w[j] - u[j]) - (v[j] - u[j]) * (w[i] - u[i]);
  };
  for (int axis = 0; axis < 3; ++axis) {
    const int i = (axis + 1) % 3, j = (axis + 2) % 3;
    const int o = sure_sign(orient2(a, b, c, i, j));
    if (o == 0) continue;
    if (sure_sign(orient2(a, b, p, i, j)) == -o || sure_sign(orient2(b, c, p, i, j)) == -o ||
        sure_sign(orient2(c, a, p, i, j)) == -o)
      return true;
  }
  return false;
}

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
  // Per curve, the faces of A and of B whose boxes meet the box of its first segments tried (one
  // box intersection for all curves: a CT pair has hundreds of curves, and a scan of every face
  // per curve took a tenth of a whole run).
  using Box = CGAL::Box_intersection_d::Box_with_info_d<double, 3, std::size_t>;
  std::vector<Box> curve_boxes;
  for (std::size_t c = 0; c < curves.size(); ++c) {
    const auto& line = curves[c];
    if (line.size() < 2) continue;
    CGAL::Bbox_3 near;
    for (std::size_t i = 0; i <= std::min(line.size() - 1, segments_tried); ++i) near += line[i].bbox();
    curve_boxes.emplace_back(near, c);
  }
  auto faces_near = [&](const Mesh<K>& m) {
    std::vector<Box> face_boxes;
    for (F f : m.faces()) face_boxes.emplace_back(CGAL::Polygon_mesh_processing::face_bbox(f, m), std::size_t(f));
    std::vector<std::vector<std::pair<F, CGAL::Bbox_3>>> near(curves.size());
    std::vector<Box> queries = curve_boxes;  // box_intersection_d reorders its ranges
    CGAL::box_intersection_d(queries.begin(), queries.end(), face_boxes.begin(), face_boxes.end(),
                             [&](const Box& c, const Box& f) {
                               near[c.info()].emplace_back(F(static_cast<typename F::size_type>(f.info())), f.bbox());
                             });
    for (auto& faces : near)  // (in the order of the faces, as before)
      std::sort(faces.begin(), faces.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
    return near;
  };
  const auto near_of_a = faces_near(a), near_of_b = faces_near(b);
  for (std::size_t c = 0; c < curves.size(); ++c) {
    auto& line = curves[c];
    if (line.size() < 2) continue;
    const std::size_t tried = std::min(line.size() - 1, segments_tried);
    const auto& near_a = near_of_a[c];
    const auto& near_b = near_of_b[c];
    auto containing = [&](const Mesh<K>& m, const std::vector<std::pair<F, CGAL::Bbox_3>>& faces, const Point& p,
                          const Point& q) {
      std::vector<std::array<Point, 3>> result;
      const CGAL::Bbox_3 box = p.bbox() + q.bbox();
      const CIP pi = interval_of(p), qi = interval_of(q);
      for (const auto& [f, fbox] : faces) {
        if (!CGAL::do_overlap(box, fbox)) continue;
        const auto c = corners(m, f);
        const CIP c0 = interval_of(c[0]), c1 = interval_of(c[1]), c2 = interval_of(c[2]);
        if (surely_off_triangle(c0, c1, c2, pi) || surely_off_triangle(c0, c1, c2, qi)) continue;
        if (!CGAL::collinear(c[0], c[1], c[2]) && on_triangle<K>(c[0], c[1], c[2], p) &&
            on_triangle<K>(c[0], c[1], c[2], q))
          result.push_back(c);
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

/// Segments (point pairs) in lexicographic order of their points (exact comparisons).
template <class Point> struct PairLess {
  bool operator()(const std::pair<Point, Point>& x, const std::pair<Point, Point>& y) const {
    const auto c = CGAL::compare_xyz(x.first, y.first);
    if (c != CGAL::EQUAL) return c == CGAL::SMALLER;
    return CGAL::compare_xyz(x.second, y.second) == CGAL::SMALLER;
  }
};

enum class SegmentKind { cross, contact_boundary, contact_inside, touch };

/// Classifies the segments of surface_intersection's pieces by the faces of each mesh that contain
/// them, seen as half-planes bounded by the segment's line: one face around it gives the two
/// halves of its plane, two faces with the segment on their common edge give one half-plane each.
///   - an A half-plane equal to a B half-plane (flat contact): one is the boundary of the contact
///     region (kept), two or more is its inside (dropped);
///   - otherwise the B half-planes on both sides of the A pair: the surfaces cross (kept), on one
///     side: they touch.
/// Every test is an exact predicate on the points as given; a segment whose faces are not found
/// that way (rounded points of an inexact kernel, a border edge, a non-manifold edge) is a crossing.
template <class K> class SegmentClassifier {
 public:
  using Point = typename K::Point_3;
  using F = typename Mesh<K>::Face_index;
  using Segment = std::pair<const Point*, const Point*>;

  SegmentClassifier(const Mesh<K>& a, const Mesh<K>& b, std::vector<Segment> segments)
      : a_(a), b_(b), segments_(std::move(segments)) {
    boxes_.reserve(segments_.size());
    for (std::size_t s = 0; s < segments_.size(); ++s) {
      boxes_.emplace_back(segments_[s].first->bbox() + segments_[s].second->bbox(), s);
      all_segments_ += boxes_.back().bbox();
    }
    tbb::parallel_invoke([&] { candidates_a_ = candidate_faces(a_); }, [&] { candidates_b_ = candidate_faces(b_); });
  }

  std::size_t size() const { return segments_.size(); }

  /// The kind of segment s. Safe on several threads at once: it only reads the meshes and the
  /// segments (CGAL_HAS_THREADS makes evaluating a shared lazy point safe), builds its own points,
  /// and answers from exact predicates alone, so the threads' order changes no answer.
  SegmentKind classify(std::size_t s) const {
    const Point &p = *segments_[s].first, &q = *segments_[s].second;
    if (surely_crossing(s)) return SegmentKind::cross;
    std::array<Point, 2> ra, rb;
    if (!half_planes(a_, faces_containing(a_, candidates_a_[s], s), p, q, ra) ||
        !half_planes(b_, faces_containing(b_, candidates_b_[s], s), p, q, rb))
      return SegmentKind::cross;
    int same = 0;
    for (const auto& x : ra)
      for (const auto& y : rb)
        if (CGAL::coplanar(p, q, x, y) && CGAL::coplanar_orientation(p, q, x, y) == CGAL::POSITIVE) ++same;
    // Both surfaces the same on both sides of pq: inside a flat contact, unless they bend there
    // together (a ridge of both, where two flat contacts meet at an angle): that edge is where
    // faces of A and B that are not coplanar meet, so it is kept as a curve.
    if (same >= 2)
      return CGAL::coplanar(p, q, ra[0], ra[1]) ? SegmentKind::contact_inside : SegmentKind::contact_boundary;
    if (same == 1) return SegmentKind::contact_boundary;
    // Turning about pq (positive: CGAL::orientation(p, q, x, y) > 0), is y strictly inside the
    // wedge from ra[0] to ra[1]? (no B half-plane equals an A half-plane here)
    auto turn = [&](const Point& x, const Point& y) { return CGAL::orientation(p, q, x, y); };
    const auto o = turn(ra[0], ra[1]);
    if (o == CGAL::COPLANAR && CGAL::coplanar_orientation(p, q, ra[0], ra[1]) == CGAL::POSITIVE)
      return SegmentKind::cross;  // A folded onto itself: not decided here
    auto inside = [&](const Point& y) {
      if (o == CGAL::POSITIVE) return turn(ra[0], y) == CGAL::POSITIVE && turn(y, ra[1]) == CGAL::POSITIVE;
      if (o == CGAL::NEGATIVE) return !(turn(ra[1], y) == CGAL::POSITIVE && turn(y, ra[0]) == CGAL::POSITIVE);
      return turn(ra[0], y) == CGAL::POSITIVE;  // a flat wedge: half a turn
    };
    return inside(rb[0]) != inside(rb[1]) ? SegmentKind::cross : SegmentKind::touch;
  }

 private:
  using Box = CGAL::Box_intersection_d::Box_with_info_d<double, 3, std::size_t>;
  // Fast path, certified interval arithmetic: it rules out most faces, and a segment left with one
  // candidate face in each mesh, the two planes surely different, is a crossing (the segment lies
  // on both surfaces, so each candidate contains it; where rounded points of an inexact kernel do
  // not, "kept" is the default anyway). No exact evaluation then: on a face that contains the
  // segment the exact kernel's own filters always fail.
  using IP = CIP;  // (the file's interval tests, at the top)
  static IP interval(const Point& p) { return interval_of(p); }
  static bool surely_off_plane(const std::array<IP, 3>& c, const IP& p) {
    return internal::surely_off_plane(c[0], c[1], c[2], p);
  }
  static std::array<IP, 3> face_intervals(const Mesh<K>& m, F f) {
    const auto h = m.halfedge(f);
    return {interval(m.point(m.source(h))), interval(m.point(m.target(h))), interval(m.point(m.target(m.next(h))))};
  }
  static std::array<Point, 3> corners(const Mesh<K>& m, F f) {
    const auto h = m.halfedge(f);
    return {m.point(m.source(h)), m.point(m.target(h)), m.point(m.target(m.next(h)))};
  }

  /// Per segment, the faces of m that may contain it (in whose plane both ends may lie).
  std::vector<std::vector<F>> candidate_faces(const Mesh<K>& m) const {
    std::vector<std::vector<F>> result(segments_.size());
    std::vector<Box> face_boxes;
    for (F f : m.faces())
      if (const auto box = CGAL::Polygon_mesh_processing::face_bbox(f, m); CGAL::do_overlap(box, all_segments_))
        face_boxes.emplace_back(box, std::size_t(f));
    std::vector<Box> segment_boxes = boxes_;  // box_intersection_d reorders its ranges
    CGAL::Protect_FPU_rounding<true> rounding;
    CGAL::box_intersection_d(segment_boxes.begin(), segment_boxes.end(), face_boxes.begin(), face_boxes.end(),
                             [&](const Box& sb, const Box& fb) {
                               const F f(static_cast<typename F::size_type>(fb.info()));
                               const auto c = face_intervals(m, f);
                               const auto& seg = segments_[sb.info()];
                               if (!surely_off_plane(c, interval(*seg.first)) &&
                                   !surely_off_plane(c, interval(*seg.second)))
                                 result[sb.info()].push_back(f);
                             });
    return result;
  }

  bool surely_crossing(std::size_t s) const {
    if (candidates_a_[s].size() != 1 || candidates_b_[s].size() != 1) return false;
    CGAL::Protect_FPU_rounding<true> rounding;
    const auto ca = face_intervals(a_, candidates_a_[s][0]), cb = face_intervals(b_, candidates_b_[s][0]);
    return surely_off_plane(ca, cb[0]) || surely_off_plane(ca, cb[1]) || surely_off_plane(ca, cb[2]);
  }

  /// Exactly: the faces of m that contain the segment, among the candidates.
  std::vector<F> faces_containing(const Mesh<K>& m, const std::vector<F>& candidates, std::size_t s) const {
    std::vector<F> result;
    const CIP p = interval(*segments_[s].first), q = interval(*segments_[s].second);
    for (F f : candidates) {
      // (a face whose plane or edges the segment surely lies off is settled in intervals; the
      // others by the kernel's exact predicates)
      const auto ci = face_intervals(m, f);
      if (surely_off_triangle(ci[0], ci[1], ci[2], p) || surely_off_triangle(ci[0], ci[1], ci[2], q))
        continue;
      const auto c = corners(m, f);
      if (on_triangle<K>(c[0], c[1], c[2], *segments_[s].first) && on_triangle<K>(c[0], c[1], c[2], *segments_[s].second))
        result.push_back(f);
    }
    return result;
  }

  /// The two half-planes of m around pq, each given by a point of it off the line pq.
  static bool half_planes(const Mesh<K>& m, const std::vector<F>& faces, const Point& p, const Point& q,
                          std::array<Point, 2>& r) {
    if (faces.size() == 1) {  // pq inside the face: a corner on each side of it
      const auto c = corners(m, faces[0]);
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
        const auto c = corners(m, faces[k]);
        int off = -1, count = 0;
        for (int i = 0; i < 3; ++i)
          if (!CGAL::collinear(p, q, c[i])) off = i, ++count;
        if (count != 1) return false;
        r[k] = c[off];
      }
      return true;
    }
    return false;
  }

  const Mesh<K>& a_;
  const Mesh<K>& b_;
  std::vector<Segment> segments_;
  std::vector<Box> boxes_;
  CGAL::Bbox_3 all_segments_;
  std::vector<std::vector<F>> candidates_a_, candidates_b_;
};

/// The pieces of curve where the surfaces cross or bound a flat contact (`kept`) and where they
/// only touch (`touched`), from surface_intersection's pieces: runs of segments of one kind.
template <class K> struct ClassifiedPieces {
  std::vector<std::vector<typename K::Point_3>> kept, touched;
};

template <class K>
ClassifiedPieces<K> classify_pieces(const Mesh<K>& a, const Mesh<K>& b,
                                    const std::vector<std::vector<typename K::Point_3>>& pieces) {
  using Point = typename K::Point_3;
  std::vector<std::pair<const Point*, const Point*>> segments;
  for (const auto& piece : pieces)
    for (std::size_t i = 0; i + 1 < piece.size(); ++i)
      if (!(piece[i] == piece[i + 1])) segments.emplace_back(&piece[i], &piece[i + 1]);
  const SegmentClassifier<K> classifier(a, b, std::move(segments));
  std::vector<SegmentKind> kinds(classifier.size());
  using Range = tbb::blocked_range<std::size_t>;
  tbb::parallel_for(Range(0, kinds.size(), 64), [&](const Range& r) {
    for (std::size_t i = r.begin(); i != r.end(); ++i) kinds[i] = classifier.classify(i);
  });
  ClassifiedPieces<K> result;
  std::size_t s = 0;
  for (const auto& piece : pieces) {
    std::vector<Point> run;
    int run_of = -1;  // 0 kept, 1 touching, 2 inside a flat contact
    auto flush = [&]() {
      if (run.size() >= 2 && run_of == 0) result.kept.push_back(run);
      if (run.size() >= 2 && run_of == 1) result.touched.push_back(run);
      run.clear();
    };
    for (std::size_t i = 0; i + 1 < piece.size(); ++i) {
      if (piece[i] == piece[i + 1]) continue;
      const SegmentKind kind = kinds[s++];
      const int of = kind == SegmentKind::cross || kind == SegmentKind::contact_boundary ? 0
                     : kind == SegmentKind::touch                                        ? 1
                                                                                         : 2;
      if (of != run_of) flush(), run_of = of;
      if (run.empty()) run.push_back(piece[i]);
      run.push_back(piece[i + 1]);
    }
    flush();
  }
  return result;
}

/// Why each open curve ends where it does (see CurveEnds): the pieces meeting at the end point,
/// counted over all curves (exact point equality), and, at a loose end, whether its last segment
/// is one where the surfaces only touch, or the end lies on a border edge of either mesh.
template <class K>
CurveEnds explain_curve_ends(const Mesh<K>& a, const Mesh<K>& b, const std::vector<Polyline<K>>& curves,
                             const std::vector<std::vector<typename K::Point_3>>& touched) {
  using Point = typename K::Point_3;
  std::map<Point, std::size_t, PointLess<Point>> degree;  // 1 per open end, 2 per pass through
  for (const auto& c : curves) {
    if (c.size() < 2) continue;
    const bool closed = is_closed(c);
    for (std::size_t k = 0; k + (closed ? 1 : 0) < c.size(); ++k)
      degree[c[k]] += !closed && (k == 0 || k + 1 == c.size()) ? 1 : 2;
  }
  std::set<std::pair<Point, Point>, PairLess<Point>> touching;
  for (const auto& run : touched)
    for (std::size_t i = 0; i + 1 < run.size(); ++i) {
      touching.insert({run[i], run[i + 1]});
      touching.insert({run[i + 1], run[i]});
    }
  CurveEnds ends;
  auto on_border = [](const Mesh<K>& m, const Point& p) {
    const CGAL::Bbox_3 box = p.bbox();
    for (auto h : m.halfedges()) {
      if (!m.is_border(h)) continue;
      const Point &s = m.point(m.source(h)), &t = m.point(m.target(h));
      if (CGAL::do_overlap(box, s.bbox() + t.bbox()) && typename K::Segment_3(s, t).has_on(p)) return true;
    }
    return false;
  };
  for (const auto& c : curves) {
    if (c.size() < 2 || is_closed(c)) continue;
    for (const auto& [end, next] : {std::make_pair(c.front(), c[1]), std::make_pair(c.back(), c[c.size() - 2])}) {
      if (degree[end] >= 2)
        ++ends.junction;
      else if (touching.count({end, next}))
        ++ends.touching;
      else if (on_border(a, end) || on_border(b, end))
        ++ends.border;
      else
        ++ends.unexplained;
    }
  }
  return ends;
}

/// Under the float kernel: CGAL's surface_intersection (its coplanar corefinement in particular)
/// needs exact predicates; with plain doubles it fails assertions or runs into undefined
/// behaviour on degenerate inputs (found by fuzzing). So the curves are computed with Epick on the
/// same doubles (exact decisions, constructions rounded as under float anyway).
IntersectionCurves<Float> float_kernel_curves(const Mesh<Float>& a, const Mesh<Float>& b) {
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
  const auto filtered = compute_intersection_curves<Filtered>(to_filtered_mesh(a), to_filtered_mesh(b));
  IntersectionCurves<Float> result;
  for (const auto& p : filtered.contacts) result.contacts.emplace_back(p.x(), p.y(), p.z());
  for (const auto& c : filtered.curves) {
    result.curves.emplace_back();
    for (const auto& p : c) result.curves.back().emplace_back(p.x(), p.y(), p.z());
  }
  result.touching_points = filtered.touching_points;
  result.ends = filtered.ends;
  return result;
}

}  // namespace

template <class K>
IntersectionCurves<K> compute_intersection_curves(const Mesh<K>& a, const Mesh<K>& b, bool known_degenerate) {
  if constexpr (std::is_same_v<K, Float>) {
    return float_kernel_curves(a, b);
  } else {
    IntersectionCurves<K> result;
    // Meshes in general position with respect to each other (no zero predicate): the direct path.
    if (auto direct = known_degenerate ? std::nullopt : general_position_curves<K>(a, b)) {
      result.sites_a = std::move(direct->sites_a);
      result.sites_b = std::move(direct->sites_b);
      result.curves = chain(std::move(direct->curves));  // already oriented; chain() keeps the direction
      result.ends = explain_curve_ends<K>(a, b, result.curves, {});
      return result;
    }
    // surface_intersection returns every common point: also where the surfaces only touch, and
    // the whole common arrangement of coplanar faces; classify_pieces keeps the curves.
    using Point = typename K::Point_3;
    std::vector<std::vector<Point>> pieces;
    CGAL::Polygon_mesh_processing::surface_intersection(a, b, std::back_inserter(pieces));
    // Kept points: cut the expression trees once (a piece per task; the exact values, and the
    // intervals they leave, do not depend on the order).
    tbb::parallel_for(std::size_t(0), pieces.size(), [&](std::size_t i) {
      for (auto& p : pieces[i]) make_exact(p);
    });
    for (auto& piece : pieces) {
      if (std::all_of(piece.begin(), piece.end(), [&](const Point& p) { return p == piece.front(); })) {
        ++result.touching_points;
        if (std::find(result.contacts.begin(), result.contacts.end(), piece.front()) == result.contacts.end())
          result.contacts.push_back(piece.front());
      }
    }
    auto classified = classify_pieces<K>(a, b, pieces);
    // Touching runs (an edge of one surface lying in a face of the other, the surfaces on one
    // side of each other there) are kept too: the outputs meet along them, so they must be curves
    // of both, or the merged outputs are not a valid complex (seam check and TetGen reject them).
    // Only isolated points of contact are not curves; they are counted (snapping must not make
    // more).
    auto kept = classified.kept;
    kept.insert(kept.end(), classified.touched.begin(), classified.touched.end());
    result.curves = chain(std::move(kept));
    orient_curves<K>(a, b, result.curves);
    result.ends = explain_curve_ends<K>(a, b, result.curves, classified.touched);
    return result;
  }
}

}  // namespace internal

template <class K>
std::vector<Polyline<K>> intersection_curves(const Mesh<K>& a, const Mesh<K>& b, std::size_t* touching_points) {
  auto result = internal::compute_intersection_curves<K>(a, b);
  if (touching_points) *touching_points = result.touching_points;
  return std::move(result.curves);
}

#define SEAM_INSTANTIATE(K)                                                                                   \
  template internal::IntersectionCurves<K> internal::compute_intersection_curves<K>(const Mesh<K>&,           \
                                                                                   const Mesh<K>&, bool);     \
  template std::vector<Polyline<K>> intersection_curves<K>(const Mesh<K>&, const Mesh<K>&, std::size_t*);
SEAM_INSTANTIATE(Exact)
SEAM_INSTANTIATE(Filtered)
SEAM_INSTANTIATE(Float)
#undef SEAM_INSTANTIATE

}  // namespace seam
