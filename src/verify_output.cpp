// seam: the outputs checked as written. See seam/internal/verify_output.h.
// SPDX-License-Identifier: GPL-3.0-or-later
#include <seam/errors.h>
#include <seam/internal/bbox_diagonal.h>
#include <seam/internal/splice.h>
#include <seam/internal/verify_output.h>

#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <string>
#include <type_traits>
#include <vector>

namespace seam::internal {

namespace {

/// Makes p exact where its approximation is not a point (fix_rounding), and where a coordinate is
/// -0: making it exact turns that into +0, as making every point exact did before, so that what
/// is written (and checked) is the same.
template <class P> void settle_for_writing(P& p) {
  fix_rounding(p);
  if constexpr (std::is_same_v<typename CGAL::Kernel_traits<P>::Kernel, Exact>) {
    const auto& q = CGAL::approx(p);
    auto negative_zero = [](const auto& x) {
      return (x.inf() == 0 && std::signbit(x.inf())) || (x.sup() == 0 && std::signbit(x.sup()));
    };
    if (negative_zero(q.x()) || negative_zero(q.y()) || negative_zero(q.z())) make_exact(p);
  }
}

/// The mesh with its coordinates rounded to doubles, as an exact-kernel mesh (the same
/// connectivity, vertices and faces in the same order). Its points are doubles or made exact
/// (fix_rounding, see check_as_written): their intervals are then as tight as they get, and
/// to_filtered rounds them as to_double(p.x()) would, without a lazy number per coordinate.
template <class K> Mesh<Exact> rounded(const Mesh<K>& mesh) {
  Mesh<Exact> out;
  out.reserve(mesh.number_of_vertices(), mesh.number_of_edges(), mesh.number_of_faces());
  std::vector<MeshTypes<Exact>::V> index(mesh.number_of_vertices() + mesh.number_of_removed_vertices());
  for (auto v : mesh.vertices()) {
    const Filtered::Point_3 p = to_filtered(mesh.point(v));
    index[std::size_t(v)] = out.add_vertex(Exact::Point_3(p.x(), p.y(), p.z()));
  }
  std::vector<std::array<MeshTypes<Exact>::V, 3>> triangles;
  triangles.reserve(mesh.number_of_faces());
  for (auto f : mesh.faces()) {
    const auto h = mesh.halfedge(f);
    triangles.push_back({index[std::size_t(mesh.source(h))], index[std::size_t(mesh.target(h))],
                         index[std::size_t(mesh.target(mesh.next(h)))]});
  }
  if (add_triangles<Exact>(out, triangles) != triangles.size())
    throw InternalError("check as written: a mesh could not be copied");
  return out;
}

}  // namespace

template <class K>
PairCheckReport check_as_written(const Mesh<K>& a, const Mesh<K>& b, Mesh<K>& a2, Mesh<K>& b2,
                                 std::vector<Polyline<K>>& curves, double tol) {
  // Inputs whose coordinates are not all doubles (exact ones made in memory, not read from a
  // file) cannot be written as given either: then the outputs are checked as they are.
  // Where an exact-kernel input has no removed elements and every point's approximation is its
  // double (as for a mesh read from a file), rounded<K> would give it back as it is: the check
  // takes it so, instead of a copy.
  bool as_is[2] = {std::is_same_v<K, Exact> && !a.has_garbage(), std::is_same_v<K, Exact> && !b.has_garbage()};
  if constexpr (kernel_traits<K>::exact_constructions) {
    for (const int k : {0, 1})
      for (auto v : (k == 0 ? a : b).vertices()) {
        const auto& p = (k == 0 ? a : b).point(v);
        if (is_double_by_approximation(p)) continue;
        as_is[k] = false;
        if (!(typename K::Point_3(CGAL::to_double(p.x()), CGAL::to_double(p.y()), CGAL::to_double(p.z())) == p))
          return check_pair<K>(a, b, a2, b2, curves, tol, nullptr, false);
      }
  }
  // A's and B's sides side by side (independent meshes). Only the points that are not doubles
  // already are made exact (most output vertices are input vertices, read as doubles: making
  // them exact too cost a rational per coordinate, about 0.5 s and 400 MB at 1M faces per tow).
  Mesh<Exact> ra, rb, ra2, rb2;
  tbb::parallel_invoke(
      [&] {
        for (auto v : a2.vertices()) settle_for_writing(a2.point(v));
        if (!as_is[0]) ra = rounded<K>(a);
        ra2 = rounded<K>(a2);
      },
      [&] {
        for (auto v : b2.vertices()) settle_for_writing(b2.point(v));
        if (!as_is[1]) rb = rounded<K>(b);
        rb2 = rounded<K>(b2);
      });
  // The inputs as written: themselves where as_is, else their rounded copies.
  const Mesh<Exact>* written_a = &ra;
  const Mesh<Exact>* written_b = &rb;
  if constexpr (std::is_same_v<K, Exact>) {
    if (as_is[0]) written_a = &a;
    if (as_is[1]) written_b = &b;
  }
  std::vector<Polyline<Exact>> rc;
  for (auto& c : curves) {
    rc.emplace_back();
    for (auto& p : c) {
      settle_for_writing(p);
      rc.back().emplace_back(CGAL::to_double(p.x()), CGAL::to_double(p.y()), CGAL::to_double(p.z()));
    }
  }
  return check_pair<Exact>(*written_a, *written_b, ra2, rb2, rc, tol);
}

template <class K>
EmbedCheckReport check_embedding_as_written(const Mesh<K>& input, Mesh<K>& output, std::vector<Polyline<K>>& curves,
                                            double tol, const std::vector<Polyline<K>>* given) {
  for (auto v : output.vertices()) settle_for_writing(output.point(v));
  for (auto& c : curves)
    for (auto& p : c) settle_for_writing(p);
  if constexpr (kernel_traits<K>::exact_constructions) {
    for (auto v : input.vertices()) {
      const auto& p = input.point(v);
      if (!is_double_by_approximation(p) &&
          !(typename K::Point_3(CGAL::to_double(p.x()), CGAL::to_double(p.y()), CGAL::to_double(p.z())) == p))
        return check_embedding<K>(input, output, curves, tol, given);
    }
  }
  auto doubles = [](const std::vector<Polyline<K>>& from) {
    std::vector<Polyline<Exact>> to;
    for (const auto& c : from) {
      to.emplace_back();
      for (const auto& p : c) to.back().emplace_back(CGAL::to_double(p.x()), CGAL::to_double(p.y()), CGAL::to_double(p.z()));
    }
    return to;
  };
  const std::vector<Polyline<Exact>> rc = doubles(curves);
  std::vector<Polyline<Exact>> rg;
  if (given) rg = doubles(*given);
  return check_embedding<Exact>(rounded<K>(input), rounded<K>(output), rc, tol, given ? &rg : nullptr);
}

/// The tolerance seam::pair's outputs are verified at: the quality stage's tolerance, plus the
/// given curves' largest move and stage 1's largest move (features thinner than the vertex
/// separation closed); at least 1e-9 of the pair's size.
template <class K> double verification_tolerance(const Mesh<K>& a, const Mesh<K>& b, const PairStats& st) {
  return std::max(st.snap_tol + st.max_curve_move + st.max_close_move, 1e-9 * bbox_diagonal<K>(a, b)) * (1 + 1e-9);
}

template <class K>
bool verify_outputs(const Mesh<K>& a, const Mesh<K>& b, Mesh<K>& a2, Mesh<K>& b2, PairResult<K>& result,
                    std::string& problem, std::vector<std::array<double, 3>>* close_points) {
  const auto t = std::chrono::steady_clock::now();
  auto& st = result.stats;
  st.verify_tolerance = verification_tolerance<K>(a, b, st);
  PairCheckReport report;
  try {
    report = check_as_written<K>(a, b, a2, b2, result.curves, st.verify_tolerance);
  } catch (const InternalError& e) {
    report.problems.push_back(e.what());
  }
  st.stage_seconds["verify_output"] += std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
  st.verified = report.ok();
  if (!report.ok()) problem = report.problems.front();
  if (close_points && report.problems.size() == 1)  // (pairs too close the only problem: check 5's points)
    close_points->insert(close_points->end(), report.close_vertex_points.begin(), report.close_vertex_points.end());
  return report.ok();
}

template PairCheckReport check_as_written<Exact>(const Mesh<Exact>&, const Mesh<Exact>&, Mesh<Exact>&, Mesh<Exact>&,
                                                 std::vector<Polyline<Exact>>&, double);
template PairCheckReport check_as_written<Filtered>(const Mesh<Filtered>&, const Mesh<Filtered>&, Mesh<Filtered>&,
                                                    Mesh<Filtered>&, std::vector<Polyline<Filtered>>&, double);
template PairCheckReport check_as_written<Float>(const Mesh<Float>&, const Mesh<Float>&, Mesh<Float>&, Mesh<Float>&,
                                                 std::vector<Polyline<Float>>&, double);
#define SEAM_INSTANTIATE(K)                                                                                    \
  template bool verify_outputs<K>(const Mesh<K>&, const Mesh<K>&, Mesh<K>&, Mesh<K>&, PairResult<K>&, std::string&, \
                                    std::vector<std::array<double, 3>>*); \
  template EmbedCheckReport check_embedding_as_written<K>(const Mesh<K>&, Mesh<K>&, std::vector<Polyline<K>>&, double, \
                                                          const std::vector<Polyline<K>>*);
SEAM_INSTANTIATE(Exact)
SEAM_INSTANTIATE(Filtered)
SEAM_INSTANTIATE(Float)
#undef SEAM_INSTANTIATE

}  // namespace seam::internal
