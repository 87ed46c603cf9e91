// seam: the curve gap of each face the quality stage leaves below its bound (seam/improve.h):
// how close two curve segments with no common point come near it. Where that is below the
// feature size, a face between them meets the bound only with points closer together than the
// feature size, which the stage does not make: the input's curves, at the stage's scale, force
// it. Measured on the output as it is (its curves and faces), in doubles, after the stage.
// SPDX-License-Identifier: GPL-3.0-or-later

#include <seam/internal/improve_state.h>

#include <CGAL/box_intersection_d.h>
#include <CGAL/squared_distance_3.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <vector>

namespace seam::internal {

namespace {

using FP = Filtered::Point_3;
using FS = Filtered::Segment_3;

/// The curves' segments in doubles, each with the ids of its two end points (points with the same
/// coordinates are one point: a point where curves meet, or a closed curve's first and last).
struct CurveSegments {
  std::vector<FS> segments;
  std::vector<std::array<std::size_t, 2>> ends;

  template <class K> explicit CurveSegments(const SharedCurves<K>& curves) {
    std::map<std::array<double, 3>, std::size_t> id;
    auto point_id = [&](const FP& p) { return id.emplace(std::array<double, 3>{p.x(), p.y(), p.z()}, id.size()).first->second; };
    for (const auto& curve : curves.curves)
      for (std::size_t i = 0; i + 1 < curve.size(); ++i) {
        const FP a = to_filtered(curve[i]), b = to_filtered(curve[i + 1]);
        if (a == b) continue;
        segments.emplace_back(a, b);
        ends.push_back({point_id(a), point_id(b)});
      }
  }
  bool share_a_point(std::size_t i, std::size_t j) const {
    return ends[i][0] == ends[j][0] || ends[i][0] == ends[j][1] || ends[i][1] == ends[j][0] || ends[i][1] == ends[j][1];
  }
};

/// At most this many segments (the nearest to the face's centroid) are paired per face.
constexpr std::size_t max_segments_per_face = 256;

}  // namespace

template <class K>
void measure_curve_gaps(const std::vector<ImproveMesh<K>>& meshes, const SharedCurves<K>& curves, double feature_size,
                        std::vector<Shortfall>& shortfalls) {
  if (shortfalls.empty() || !(feature_size > 0)) return;
  const CurveSegments c(curves);
  // Each face's ball grown by feature_size, as a box: the segments whose boxes meet it
  // (CGAL::box_intersection_d), then those within the ball.
  using Box = CGAL::Box_intersection_d::Box_with_info_d<double, 3, std::size_t>;
  std::vector<Box> face_boxes, segment_boxes;
  std::vector<std::pair<FP, double>> balls;  // per shortfall: centre, radius
  for (std::size_t k = 0; k < shortfalls.size(); ++k) {
    const auto& mesh = *meshes[shortfalls[k].mesh].mesh;
    const typename Mesh<K>::Face_index f(static_cast<typename Mesh<K>::size_type>(shortfalls[k].face));
    std::array<FP, 3> p;
    std::size_t n = 0;
    for (const auto v : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) p[n++] = to_filtered(mesh.point(v));
    const FP centre = CGAL::centroid(p[0], p[1], p[2]);
    double radius = 0;
    for (const auto& q : p) radius = std::max(radius, std::sqrt(CGAL::squared_distance(centre, q)));
    radius += feature_size;
    balls.emplace_back(centre, radius);
    face_boxes.emplace_back(CGAL::Bbox_3(centre.x() - radius, centre.y() - radius, centre.z() - radius,
                                         centre.x() + radius, centre.y() + radius, centre.z() + radius),
                            k);
  }
  for (std::size_t i = 0; i < c.segments.size(); ++i) segment_boxes.emplace_back(c.segments[i].bbox(), i);
  std::vector<std::vector<std::pair<double, std::size_t>>> near(shortfalls.size());  // (squared distance, segment)
  CGAL::box_intersection_d(face_boxes.begin(), face_boxes.end(), segment_boxes.begin(), segment_boxes.end(),
                           [&](const Box& face, const Box& segment) {
                             const auto& [centre, radius] = balls[face.info()];
                             const double d2 = CGAL::squared_distance(centre, c.segments[segment.info()]);
                             if (d2 <= radius * radius) near[face.info()].emplace_back(d2, segment.info());
                           });
  for (std::size_t k = 0; k < shortfalls.size(); ++k) {
    auto& candidates = near[k];
    // (A large face over many segments: the nearest ones, so that the pairs stay few.)
    if (candidates.size() > max_segments_per_face) {
      std::nth_element(candidates.begin(), candidates.begin() + std::ptrdiff_t(max_segments_per_face), candidates.end());
      candidates.resize(max_segments_per_face);
    }
    // In segment order (a distance in doubles depends on which segment comes first).
    std::sort(candidates.begin(), candidates.end(), [](const auto& x, const auto& y) { return x.second < y.second; });
    double gap2 = std::numeric_limits<double>::infinity();
    for (std::size_t a = 0; a < candidates.size(); ++a)
      for (std::size_t b = a + 1; b < candidates.size(); ++b) {
        const std::size_t i = candidates[a].second, j = candidates[b].second;
        if (!c.share_a_point(i, j)) gap2 = std::min(gap2, CGAL::squared_distance(c.segments[i], c.segments[j]));
      }
    shortfalls[k].curve_gap = std::sqrt(gap2);
  }
}

#define SEAM_INSTANTIATE(K)                                                                                      \
  template void measure_curve_gaps<K>(const std::vector<ImproveMesh<K>>&, const SharedCurves<K>&, double, \
                                      std::vector<Shortfall>&);
SEAM_INSTANTIATE(Exact)
SEAM_INSTANTIATE(Filtered)
SEAM_INSTANTIATE(Float)
#undef SEAM_INSTANTIATE

}  // namespace seam::internal
