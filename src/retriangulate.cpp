// seam, pipeline step 5: re-triangulation of one face. See seam/internal/retriangulate.h.
// SPDX-License-Identifier: GPL-3.0-or-later
#include <seam/internal/retriangulate.h>

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Delaunay_mesh_face_base_2.h>
#include <CGAL/Delaunay_mesh_vertex_base_2.h>
#include <CGAL/Delaunay_mesher_no_edge_refinement_2.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>

#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <sstream>

namespace seam::internal {

namespace {

/// Delaunay refinement criteria: smallest angle (as sin^2) and largest area. The area test uses
/// rounded values: it only decides which triangles to split further.
template <class CDT> class AngleAreaCriteria {
 public:
  using Face_handle = typename CDT::Face_handle;
  struct Quality {
    double sine2 = 1;      // squared sine of the smallest angle
    double area_ratio = 0;  // area / max_area (0 when unbounded)
    // q1 < q2: q1 is refined first. Oversized faces first, then the worst shaped.
    bool operator<(const Quality& q) const {
      if (area_ratio > 1 || q.area_ratio > 1) return area_ratio > q.area_ratio;
      return sine2 < q.sine2;
    }
  };

  class Is_bad {
   public:
    Is_bad(double sine2_bound, double max_area) : B_(sine2_bound), max_area_(max_area) {}
    CGAL::Mesh_2::Face_badness operator()(const Quality& q) const {
      if (q.area_ratio > 1) return CGAL::Mesh_2::IMPERATIVELY_BAD;
      if (q.sine2 < B_) return CGAL::Mesh_2::BAD;
      return CGAL::Mesh_2::NOT_BAD;
    }
    CGAL::Mesh_2::Face_badness operator()(const Face_handle& fh, Quality& q) const {
      const auto& pa = fh->vertex(0)->point();
      const auto& pb = fh->vertex(1)->point();
      const auto& pc = fh->vertex(2)->point();
      const double area = std::abs(CGAL::to_double(CGAL::area(pa, pb, pc)));
      const double a = CGAL::to_double(CGAL::squared_distance(pb, pc));
      const double b = CGAL::to_double(CGAL::squared_distance(pc, pa));
      const double c = CGAL::to_double(CGAL::squared_distance(pa, pb));
      // sin^2 of the angle opposite the shortest side: (2 area)^2 / (product of the two others)
      const double four_area2 = 4 * area * area;
      if (a < b)
        q.sine2 = a < c ? four_area2 / (b * c) : four_area2 / (a * b);
      else
        q.sine2 = b < c ? four_area2 / (a * c) : four_area2 / (a * b);
      q.area_ratio = max_area_ > 0 ? area / max_area_ : 0;
      return operator()(q);
    }

   private:
    double B_, max_area_;
  };

  AngleAreaCriteria(double min_angle_deg, double max_area)
      : B_(std::pow(std::sin(min_angle_deg * M_PI / 180.0), 2)), max_area_(max_area) {}
  Is_bad is_bad_object() const { return Is_bad(B_, max_area_); }

 private:
  double B_, max_area_;
};

template <class K> struct Cdt {
  using Vb0 = CGAL::Triangulation_vertex_base_with_info_2<long, K>;
  using Vb = CGAL::Delaunay_mesh_vertex_base_2<K, Vb0>;
  using Fb = CGAL::Delaunay_mesh_face_base_2<K>;
  using Tds = CGAL::Triangulation_data_structure_2<Vb, Fb>;
  using type = CGAL::Constrained_Delaunay_triangulation_2<K, Tds, CGAL::Exact_predicates_tag>;
};

constexpr long kNoId = std::numeric_limits<long>::min();

}  // namespace

template <class K>
FacePatch<K> retriangulate_face(const FaceConstraints<K>& face, const RetriangulateOptions& options) {
  using FT = typename K::FT;
  using Point2 = typename K::Point_2;
  using Point3 = typename K::Point_3;
  using Vector3 = typename K::Vector_3;
  using CDT = typename Cdt<K>::type;
  using VH = typename CDT::Vertex_handle;

  // The face's own 2D frame (see the header): exact affine map, rounded scale L.
  const Point3& a = face.corners[0];
  const Vector3 u = face.corners[1] - a;
  const Vector3 n = CGAL::cross_product(u, face.corners[2] - a);
  const Vector3 v = CGAL::cross_product(n, u);
  const double L_d = std::sqrt(CGAL::to_double(n.squared_length()));
  if (!(L_d > 0)) throw InternalError("re-triangulation of a degenerate face");
  const FT L(L_d);
  auto to_2d = [&](const Point3& p) {
    const Vector3 d = p - a;
    Point2 q(d * u, (d * v) / L);
    make_exact(q);
    return q;
  };
  const FT uu = u.squared_length(), vv = v.squared_length();
  auto to_3d = [&](const Point2& q) {
    Point3 p = a + u * (q.x() / uu) + v * (q.y() * L / vv);
    make_exact(p);
    return p;
  };

  // Points with their ids, in a fixed order (deterministic triangulation).
  std::vector<std::pair<long, Point3>> points;
  for (int i = 0; i < 3; ++i) points.emplace_back(long(face.corner_ids[i]), face.corners[i]);
  for (int i = 0; i < 3; ++i)
    for (const auto& [id, p] : face.edge_points[i]) points.emplace_back(long(id), p);
  for (const auto& [id, p] : face.interior_points) points.emplace_back(long(id), p);

  auto build = [&](CDT& cdt, std::vector<std::pair<VH, VH>>& constraints) {
    std::map<long, VH> handle;
    for (const auto& [id, p] : points) {
      VH vh = cdt.insert(to_2d(p));
      vh->info() = id;
      handle[id] = vh;
    }
    // Two input points at one place: only possible with rounded constructions.
    if (cdt.number_of_vertices() != points.size()) throw InternalError("two curve points coincide after rounding");
    for (int i = 0; i < 3; ++i) {
      long prev = long(face.corner_ids[i]);
      for (const auto& ep : face.edge_points[i]) {
        constraints.emplace_back(handle[prev], handle[long(ep.first)]);
        prev = long(ep.first);
      }
      constraints.emplace_back(handle[prev], handle[long(face.corner_ids[(i + 1) % 3])]);
    }
    for (const auto& [s, t] : face.segments) constraints.emplace_back(handle[long(s)], handle[long(t)]);
    for (const auto& [s, t] : constraints) cdt.insert_constraint(s, t);
  };
  auto check = [&](const CDT& cdt, const std::vector<std::pair<VH, VH>>& constraints) {
    for (const auto& [s, t] : constraints)
      if (!cdt.is_edge(s, t)) return false;
    return true;
  };

  CDT cdt;
  std::vector<std::pair<VH, VH>> constraints;
  build(cdt, constraints);
  if (cdt.number_of_vertices() != points.size() || !check(cdt, constraints)) {
    std::ostringstream msg;
    msg << "curve segments cross each other (or an edge) inside the face with corners " << face.corner_ids[0]
        << ", " << face.corner_ids[1] << ", " << face.corner_ids[2];
    if (kernel_traits<K>::exact_constructions) throw InvalidInput(msg.str());
    throw InternalError(msg.str() + " (rounded arithmetic)");
  }

  FacePatch<K> patch;
  const bool refine = options.min_angle_deg > 0 || options.max_area > 0;
  if (refine && options.max_steiner > 0) {
    // Refine a second copy; keep it only if every constraint survived as an edge.
    CDT refined;
    std::vector<std::pair<VH, VH>> refined_constraints;
    build(refined, refined_constraints);
    std::set<const void*> input_vertices;
    for (auto vit = refined.finite_vertices_begin(); vit != refined.finite_vertices_end(); ++vit)
      input_vertices.insert(&*vit);

    const double max_area_2d = options.max_area > 0 ? options.max_area * CGAL::to_double(uu) : 0.0;
    using Criteria = AngleAreaCriteria<CDT>;
    CGAL::Delaunay_mesher_no_edge_refinement_2<CDT, Criteria> mesher(
        refined, Criteria(std::min(options.min_angle_deg, 60.0), max_area_2d));
    mesher.init();  // no seeds: the whole triangle (the convex hull) is the domain
    const std::size_t n0 = refined.number_of_vertices();
    std::size_t steps = 0;
    while (!mesher.is_refinement_done() && refined.number_of_vertices() - n0 < options.max_steiner &&
           steps < 16 * options.max_steiner) {
      mesher.step_by_step_refine_mesh();
      ++steps;
    }
    if (check(refined, refined_constraints)) {
      for (auto vit = refined.finite_vertices_begin(); vit != refined.finite_vertices_end(); ++vit)
        if (!input_vertices.count(&*vit)) vit->info() = kNoId;
      cdt = std::move(refined);
    } else {
      patch.refinement_undone = true;
    }
  }

  // Number the Steiner points and emit the triangles (CDT faces are counterclockwise in the
  // frame, which is the face's own orientation).
  std::map<const void*, long> steiner_ref;
  for (auto vit = cdt.finite_vertices_begin(); vit != cdt.finite_vertices_end(); ++vit) {
    if (vit->info() != kNoId) continue;
    patch.steiner_points.push_back(to_3d(vit->point()));
    steiner_ref[&*vit] = -long(patch.steiner_points.size());
  }
  for (auto fit = cdt.finite_faces_begin(); fit != cdt.finite_faces_end(); ++fit) {
    std::array<long, 3> tri;
    for (int i = 0; i < 3; ++i) {
      auto vh = fit->vertex(i);
      tri[i] = vh->info() != kNoId ? vh->info() : steiner_ref.at(&*vh);
    }
    patch.triangles.push_back(tri);
  }
  return patch;
}

template FacePatch<Exact> retriangulate_face<Exact>(const FaceConstraints<Exact>&, const RetriangulateOptions&);
template FacePatch<Filtered> retriangulate_face<Filtered>(const FaceConstraints<Filtered>&, const RetriangulateOptions&);
template FacePatch<Float> retriangulate_face<Float>(const FaceConstraints<Float>&, const RetriangulateOptions&);

}  // namespace seam::internal
