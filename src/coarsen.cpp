// seam, pipeline step 4: coarsening. See seam/internal/coarsen.h.
// SPDX-License-Identifier: GPL-3.0-or-later
#include <seam/internal/coarsen.h>
#include <seam/internal/trace.h>

#include <algorithm>
#include <cmath>

namespace seam::internal {

namespace {

template <class P> std::array<double, 3> dbl(const P& p) {
  const auto q = to_filtered(p);  // under Epeck from the interval approximation, no lazy number
  return {q.x(), q.y(), q.z()};
}

/// Squared distance from p to the segment [a, b] (to a when a == b), in doubles: used only to
/// choose which node to keep, never to decide topology.
double squared_distance_to_segment(const std::array<double, 3>& p, const std::array<double, 3>& a,
                                   const std::array<double, 3>& b) {
  double ab[3], ap[3], ab2 = 0, t = 0;
  for (int i = 0; i < 3; ++i) {
    ab[i] = b[i] - a[i];
    ap[i] = p[i] - a[i];
    ab2 += ab[i] * ab[i];
    t += ab[i] * ap[i];
  }
  t = ab2 > 0 ? std::clamp(t / ab2, 0.0, 1.0) : 0.0;
  double d2 = 0;
  for (int i = 0; i < 3; ++i) d2 += (ap[i] - t * ab[i]) * (ap[i] - t * ab[i]);
  return d2;
}

template <class K> bool on_edge(const Mesh<K>& mesh, typename MeshTypes<K>::H h, const SurfacePoint<K>& x) {
  switch (x.where) {
    case Where::vertex: return x.v == mesh.source(h) || x.v == mesh.target(h);
    case Where::edge: return x.e == mesh.edge(h);
    case Where::face: return false;
  }
  return false;
}

}  // namespace

template <class K>
bool on_common_edge(const Mesh<K>& mesh, typename MeshTypes<K>::F f, const SurfacePoint<K>& a,
                    const SurfacePoint<K>& b) {
  for (auto h : CGAL::halfedges_around_face(mesh.halfedge(f), mesh))
    if (on_edge<K>(mesh, h, a) && on_edge<K>(mesh, h, b)) return true;
  return false;
}

template <class K>
bool CurvePoints<K>::Less::operator()(const SurfacePoint<K>& a, const SurfacePoint<K>& b) const {
  if (a.where != b.where) return a.where < b.where;
  switch (a.where) {
    case Where::vertex: return a.v < b.v;
    case Where::edge:
      if (a.e != b.e) return a.e < b.e;
      break;
    case Where::face:
      if (a.f != b.f) return a.f < b.f;
      break;
  }
  return CGAL::compare_xyz(a.p, b.p) == CGAL::SMALLER;
}

template <class K> std::size_t CurvePoints<K>::id(const SurfacePoint<K>& sp) {
  auto [it, inserted] = index_.try_emplace(sp, points.size());
  if (inserted) {
    points.push_back(sp);
    make_exact(points.back().p);  // a kept point: cut its lazy expression tree once
  }
  return it->second;
}

namespace {

/// coarsen_curves on one traced curve: the points kept, then each run between two kept points
/// refined (recursively, as an explicit stack), then the kept points emitted with their faces.
template <class K> class CurveCoarsener {
 public:
  CurveCoarsener(const Mesh<K>& mesh, const TracedCurve<K>& tc, double curve_tol, bool keep_all_nodes)
      : mesh_(mesh), tc_(tc), pts_(tc.points), n_(pts_.size()), closed_(tc.closed), curve_tol_(curve_tol),
        xyz_(n_), kept_(n_, 0) {
    for (std::size_t i = 0; i < n_; ++i)
      xyz_[i] = tc.face_points_deferred && pts_[i].where == Where::face ? rounded_projection(pts_[i]) : dbl(pts_[i].p);
    keep_crossings(keep_all_nodes);
    if (closed_ && std::none_of(kept_.begin(), kept_.end(), [](char k) { return k != 0; })) keep_three_of_a_loop();
    refine_runs();
  }

  /// The kept points (ids in `points`) and the face of each segment.
  CoarseCurve<K> emit(CurvePoints<K>& points) const {
    CoarseCurve<K> cc;
    cc.closed = closed_;
    std::vector<std::size_t> k;
    for (std::size_t i = 0; i < n_; ++i)
      if (kept_[i]) k.push_back(i);
    for (std::size_t j = 0; j < k.size(); ++j) {
      cc.ids.push_back(points.id(location(k[j])));
      cc.traced_index.push_back(k[j]);
      const bool last = j + 1 == k.size();
      if (last && !closed_) break;
      const std::size_t a = k[j], b = last ? k.front() : k[j + 1];
      // face of the step leaving a (the same face holds the whole run when it has nodes)
      // A step without a valid face: only rounded kernels get there (found by fuzzing, float
      // kernel); an internal error, not an out-of-range face.
      if (a >= tc_.step_face.size() || std::size_t(tc_.step_face[a]) >= mesh_.number_of_faces())
        throw InternalError("coarsen: a step of the traced curve has no face on the mesh (rounded arithmetic)");
      const auto f = tc_.step_face[a];
      const bool run_on_edges = (a + 1) % n_ != b && pts_[(a + 1) % n_].where == Where::edge;
      const bool along_edge = run_on_edges || ((a + 1) % n_ == b && on_common_edge<K>(mesh_, f, pts_[a], pts_[b]));
      cc.segment_face.push_back(along_edge ? Mesh<K>::null_face() : f);
    }
    return cc;
  }

 private:
  /// Where traced point i lies (its exact projection when the trace deferred it).
  SurfacePoint<K> location(std::size_t i) const {
    return tc_.face_points_deferred ? traced_location<K>(mesh_, tc_, i) : pts_[i];
  }

  /// A deferred face point's projection onto its face's plane, in doubles (for choosing which
  /// nodes to keep, as the rounded exact projection would be).
  std::array<double, 3> rounded_projection(const SurfacePoint<K>& sp) {
    if (sp.f != plane_face_) {  // consecutive points mostly share a face
      plane_face_ = sp.f;
      const auto h = mesh_.halfedge(sp.f);
      const auto b = dbl(mesh_.point(mesh_.target(h))), c = dbl(mesh_.point(mesh_.target(mesh_.next(h))));
      plane_a_ = dbl(mesh_.point(mesh_.source(h)));
      const auto& a = plane_a_;
      const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]}, v[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]};
      plane_n_ = {u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]};
    }
    const auto &a = plane_a_, &n = plane_n_;
    const auto q = dbl(sp.p);
    const double nn = n[0] * n[0] + n[1] * n[1] + n[2] * n[2];
    const double t = nn > 0 ? ((q[0] - a[0]) * n[0] + (q[1] - a[1]) * n[1] + (q[2] - a[2]) * n[2]) / nn : 0.0;
    return {q[0] - t * n[0], q[1] - t * n[1], q[2] - t * n[2]};
  }
  typename MeshTypes<K>::F plane_face_;  ///< rounded_projection's face, its corner a and normal n
  std::array<double, 3> plane_a_{}, plane_n_{};

  /// Points on edges and vertices (crossings), the ends of an open curve, and with
  /// keep_all_nodes every input node. A point inside an edge with both neighbours on that same
  /// edge is not a crossing: the curve runs along the edge there. It is dropped (the edge is not
  /// split).
  void keep_crossings(bool keep_all_nodes) {
    for (std::size_t i = 0; i < n_; ++i) kept_[i] = pts_[i].where != Where::face;
    auto on_edge_e = [&](const SurfacePoint<K>& x, typename MeshTypes<K>::E e) {
      if (x.where == Where::edge) return x.e == e;
      if (x.where == Where::vertex) return x.v == mesh_.vertex(e, 0) || x.v == mesh_.vertex(e, 1);
      return false;
    };
    for (std::size_t i = 0; i < n_; ++i) {
      if (pts_[i].where != Where::edge || (!closed_ && (i == 0 || i + 1 == n_)) || n_ < 3) continue;
      const auto& before = pts_[(i + n_ - 1) % n_];
      const auto& after = pts_[(i + 1) % n_];
      if (on_edge_e(before, pts_[i].e) && on_edge_e(after, pts_[i].e)) kept_[i] = 0;
    }
    if (!closed_ && n_ > 0) kept_.front() = kept_.back() = 1;
    if (keep_all_nodes)
      for (std::size_t i = 0; i < n_; ++i) kept_[i] |= tc_.input_node[i] >= 0;
  }

  /// The index strictly between a and b (cyclic) farthest from segment [a, b], but `skip`; n if
  /// none. Rounded distances.
  std::pair<std::size_t, double> farthest(std::size_t a, std::size_t b, std::size_t skip) const {
    std::size_t best = n_;
    double best_d = -1;
    for (std::size_t i = (a + 1) % n_; i != b; i = (i + 1) % n_) {
      if (i == skip) continue;
      double d = squared_distance_to_segment(xyz_[i], xyz_[a], xyz_[b]);
      if (d > best_d) best_d = d, best = i;
    }
    return {best, best_d};
  }

  /// A closed curve inside one face: keep node 0, the node farthest from it and the node
  /// farthest from the line through both.
  void keep_three_of_a_loop() {
    kept_[0] = 1;
    const auto [i1, d1] = farthest(0, 0, n_);
    if (i1 >= n_) return;
    kept_[i1] = 1;
    std::size_t best = n_;
    double best_d = -1;
    for (std::size_t i = 1; i < n_; ++i) {
      if (i == i1) continue;
      // distance to the line through 0 and i1 (not the segment)
      double ab[3], ap[3], ab2 = 0, t = 0, d2 = 0;
      for (int k = 0; k < 3; ++k) {
        ab[k] = xyz_[i1][k] - xyz_[0][k];
        ap[k] = xyz_[i][k] - xyz_[0][k];
        ab2 += ab[k] * ab[k];
        t += ab[k] * ap[k];
      }
      t = ab2 > 0 ? t / ab2 : 0;
      for (int k = 0; k < 3; ++k) d2 += (ap[k] - t * ab[k]) * (ap[k] - t * ab[k]);
      if (d2 > best_d) best_d = d2, best = i;
    }
    if (best < n_) kept_[best] = 1;
  }

  /// Refine each run between two kept points: recursion on (a, b), cyclic indices.
  void refine_runs() {
    std::vector<std::pair<std::size_t, std::size_t>> stack;
    {
      std::vector<std::size_t> k;
      for (std::size_t i = 0; i < n_; ++i)
        if (kept_[i]) k.push_back(i);
      for (std::size_t j = 0; j + 1 < k.size(); ++j) stack.emplace_back(k[j], k[j + 1]);
      if (closed_ && !k.empty()) stack.emplace_back(k.back(), k.front());
    }
    const std::size_t n = n_;
    while (!stack.empty()) {
      auto [a, b] = stack.back();
      stack.pop_back();
      if ((a + 1) % n == b) continue;  // no interior node
      if (pts_[(a + 1) % n].where != Where::face) continue;  // dropped points along an edge
      const auto f = pts_[(a + 1) % n].f;
      std::size_t keep = n;
      if (location(a).same_as(location(b))) {
        // A loop from a point back to itself: keep the two nodes farthest apart from it.
        auto [i1, d1] = farthest(a, b, n);
        auto [i2, d2] = farthest(a, b, i1);
        if (i1 < n) kept_[i1] = 1;
        if (i2 < n) kept_[i2] = 1;
        std::size_t lo = std::min((i1 + n - a) % n, (i2 + n - a) % n), hi = std::max((i1 + n - a) % n, (i2 + n - a) % n);
        if (i2 < n) {
          std::size_t m1 = (a + lo) % n, m2 = (a + hi) % n;
          stack.emplace_back(a, m1);
          stack.emplace_back(m1, m2);
          stack.emplace_back(m2, b);
        } else if (i1 < n) {
          stack.emplace_back(a, i1);
          stack.emplace_back(i1, b);
        }
        continue;
      }
      auto [i, d] = farthest(a, b, n);
      if (on_common_edge<K>(mesh_, f, pts_[a], pts_[b]) || (curve_tol_ > 0 && d > curve_tol_ * curve_tol_)) keep = i;
      if (keep < n) {
        kept_[keep] = 1;
        stack.emplace_back(a, keep);
        stack.emplace_back(keep, b);
      }
    }
  }

  const Mesh<K>& mesh_;
  const TracedCurve<K>& tc_;
  const std::vector<SurfacePoint<K>>& pts_;
  const std::size_t n_;
  const bool closed_;
  const double curve_tol_;
  std::vector<std::array<double, 3>> xyz_;  ///< the points, rounded
  std::vector<char> kept_;
};

}  // namespace

template <class K>
CoarsenOutput<K> coarsen_curves(const Mesh<K>& mesh, const std::vector<TracedCurve<K>>& traced, double curve_tol,
                                bool keep_all_nodes) {
  CoarsenOutput<K> out;
  for (const TracedCurve<K>& tc : traced)
    out.curves.push_back(CurveCoarsener<K>(mesh, tc, curve_tol, keep_all_nodes).emit(out.points));
  return out;
}

#define SEAM_INSTANTIATE(K)                                                                                        \
  template struct CurvePoints<K>;                                                                                 \
  template CoarsenOutput<K> coarsen_curves<K>(const Mesh<K>&, const std::vector<TracedCurve<K>>&, double, bool);        \
  template bool on_common_edge<K>(const Mesh<K>&, typename MeshTypes<K>::F, const SurfacePoint<K>&,               \
                                  const SurfacePoint<K>&);
SEAM_INSTANTIATE(Exact)
SEAM_INSTANTIATE(Filtered)
SEAM_INSTANTIATE(Float)
#undef SEAM_INSTANTIATE

}  // namespace seam::internal
