// seam: the curve gap of each face the quality stage leaves below its bound (seam/improve.h):
// how close two curve segments with no common point come near it. Where that is below the
// feature size, a face between them meets the bound only with points closer together than the
// feature size, which the stage does not make: the input's curves, at the stage's scale, force
// it. Measured on the output as it is (its curves and faces), in doubles, after the stage.
// SPDX-License-Identifier: GPL-3.0-or-later

#include <seam/internal/improve_state.h>

#include <CGAL/squared_distance_3.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <unordered_map>
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

/// A uniform grid of cubes of side `cell` holding each segment in the cells its box meets.
class SegmentGrid {
 public:
  SegmentGrid(const CurveSegments& c, double cell) : cell_(cell) {
    for (std::size_t i = 0; i < c.segments.size(); ++i) {
      boxes_.push_back(c.segments[i].bbox());
      for_cells(boxes_.back(), [&](std::int64_t key) { cells_[key].push_back(i); });
    }
  }
  /// The segments whose cells meet the box (each once, in increasing order). A box over more
  /// cells than there are segments (a large face): the segments whose boxes meet it, one by one.
  std::vector<std::size_t> near(const CGAL::Bbox_3& box) const {
    std::vector<std::size_t> found;
    double cells = 1;
    for (int k = 0; k < 3; ++k) cells *= std::floor(box.max(k) / cell_) - std::floor(box.min(k) / cell_) + 1;
    if (!(cells <= double(boxes_.size()))) {
      for (std::size_t i = 0; i < boxes_.size(); ++i)
        if (CGAL::do_overlap(box, boxes_[i])) found.push_back(i);
      return found;
    }
    for_cells(box, [&](std::int64_t key) {
      if (const auto it = cells_.find(key); it != cells_.end()) found.insert(found.end(), it->second.begin(), it->second.end());
    });
    std::sort(found.begin(), found.end());
    found.erase(std::unique(found.begin(), found.end()), found.end());
    return found;
  }

 private:
  template <class Visit> void for_cells(const CGAL::Bbox_3& box, Visit visit) const {
    auto index = [&](double x) { return std::int64_t(std::floor(x / cell_)); };
    for (auto i = index(box.xmin()); i <= index(box.xmax()); ++i)
      for (auto j = index(box.ymin()); j <= index(box.ymax()); ++j)
        for (auto k = index(box.zmin()); k <= index(box.zmax()); ++k)
          visit(((i & 0x1fffff) << 42) | ((j & 0x1fffff) << 21) | (k & 0x1fffff));  // (a hash: collisions only add candidates)
  }
  double cell_;
  std::vector<CGAL::Bbox_3> boxes_;
  std::unordered_map<std::int64_t, std::vector<std::size_t>> cells_;
};

/// At most this many segments (the nearest to the face's centroid) are paired per face.
constexpr std::size_t max_segments_per_face = 256;

}  // namespace

template <class K>
void measure_curve_gaps(const std::vector<ImproveMesh<K>>& meshes, const SharedCurves<K>& curves, double feature_size,
                        std::vector<Shortfall>& shortfalls) {
  if (shortfalls.empty() || !(feature_size > 0)) return;
  const CurveSegments c(curves);
  double longest = 0;
  for (const auto& s : c.segments) longest = std::max(longest, std::sqrt(s.squared_length()));
  // Cells of a few feature sizes, but not so small that a long segment fills too many of them.
  const SegmentGrid grid(c, std::max(4 * feature_size, longest / 16));
  for (auto& shortfall : shortfalls) {
    const auto& mesh = *meshes[shortfall.mesh].mesh;
    const typename Mesh<K>::Face_index f(static_cast<typename Mesh<K>::size_type>(shortfall.face));
    std::array<FP, 3> p;
    std::size_t n = 0;
    for (const auto v : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) p[n++] = to_filtered(mesh.point(v));
    const FP centre = CGAL::centroid(p[0], p[1], p[2]);
    double radius = 0;
    for (const auto& q : p) radius = std::max(radius, std::sqrt(CGAL::squared_distance(centre, q)));
    radius += feature_size;
    const CGAL::Bbox_3 box(centre.x() - radius, centre.y() - radius, centre.z() - radius, centre.x() + radius,
                           centre.y() + radius, centre.z() + radius);
    std::vector<std::pair<double, std::size_t>> near;  // (squared distance to the centre, segment)
    for (const std::size_t i : grid.near(box))
      if (const double d2 = CGAL::squared_distance(centre, c.segments[i]); d2 <= radius * radius) near.emplace_back(d2, i);
    // (A large face over many segments: the nearest ones, so that the pairs stay few.)
    if (near.size() > max_segments_per_face) {
      std::nth_element(near.begin(), near.begin() + std::ptrdiff_t(max_segments_per_face), near.end());
      near.resize(max_segments_per_face);
    }
    std::vector<std::size_t> within;
    for (const auto& dn : near) within.push_back(dn.second);
    double gap2 = std::numeric_limits<double>::infinity();
    for (std::size_t a = 0; a < within.size(); ++a)
      for (std::size_t b = a + 1; b < within.size(); ++b)
        if (!c.share_a_point(within[a], within[b]))
          gap2 = std::min(gap2, CGAL::squared_distance(c.segments[within[a]], c.segments[within[b]]));
    shortfall.curve_gap = std::sqrt(gap2);
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
