// Tests of the exact triangle predicates written with orientations (internal/triangle_predicates.h)
// against CGAL's general functions, on configurations built exactly under Epeck: points on the
// edges, at the corners and on the edge lines of a triangle; two faces at a curve point whose
// next curve points lie exactly on the line where their planes meet.
#include <catch2/catch.hpp>

#include <seam/internal/triangle_predicates.h>
#include <seam/kernels.h>
#include <seam/quality.h>

#include <algorithm>
#include <cmath>
#include <random>

namespace {

using seam::Exact;
using P = Exact::Point_3;
using V = Exact::Vector_3;

P random_point(std::mt19937& rng) {
  std::uniform_real_distribution<double> unit(-1, 1);
  return P(unit(rng), unit(rng), unit(rng));
}

V random_vector(std::mt19937& rng) {
  std::uniform_real_distribution<double> unit(-1, 1);
  return V(unit(rng), unit(rng), unit(rng));
}

/// The general test of seam's acceptance predicate for two triangles sharing corner p: neither
/// triangle's edge opposite p meets the other triangle.
bool only_vertex_in_general(const P& p, const P& a, const P& b, const P& c, const P& d) {
  using S = Exact::Segment_3;
  using T = Exact::Triangle_3;
  return !CGAL::do_intersect(S(a, b), T(p, c, d)) && !CGAL::do_intersect(S(c, d), T(p, a, b));
}

}  // namespace

TEST_CASE("on_triangle agrees with Triangle_3::has_on on corners, edges, edge lines and off the plane",
          "[predicates]") {
  std::mt19937 rng(11);
  // Barycentric steps of a quarter: 0 and 1 put the point on an edge or at a corner, beyond them
  // on an edge line or outside, all exactly in the plane.
  const double steps[] = {-0.25, 0.0, 0.25, 0.5, 0.75, 1.0, 1.25};
  std::size_t on = 0, off = 0;
  for (int round = 0; round < 20; ++round) {
    const P a = random_point(rng), b = random_point(rng);
    // A proper triangle, and (every fifth round) one whose corners lie on a line.
    const P c = round % 5 == 4 ? a + (b - a) * 2 : random_point(rng);
    const Exact::Triangle_3 t(a, b, c);
    const V lift = CGAL::collinear(a, b, c) ? random_vector(rng) : CGAL::cross_product(b - a, c - a);
    for (double s : steps)
      for (double u : steps)
        for (double height : {0.0, 1e-12, -0.5}) {
          const P x = a + (b - a) * s + (c - a) * u + lift * height;
          const bool expected = t.has_on(x);
          CHECK(seam::internal::on_triangle<Exact>(a, b, c, x) == expected);
          (expected ? on : off) += 1;
        }
  }
  CHECK(on > 100);  // the configurations reach both answers
  CHECK(off > 100);
}

TEST_CASE("only_vertex_along_edges agrees with the general test at a curve point, and decides the usual cases",
          "[predicates]") {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> length(0.1, 1.0);
  std::uniform_int_distribution<int> side(0, 2);  // 0: on the line, 1 and 2: either side of it
  auto offset = [&](int k) { return k == 0 ? 0.0 : (k == 1 ? 1 : -1) * length(rng); };
  std::size_t decided = 0, along_both = 0, along_one = 0, apart = 0, meeting = 0;
  for (int round = 0; round < 3000; ++round) {
    // Two planes through p, meeting in the line p + s * l (exactly, under Epeck).
    const P p = random_point(rng);
    const V n1 = random_vector(rng), n2 = random_vector(rng);
    const V l = CGAL::cross_product(n1, n2);
    if (l == CGAL::NULL_VECTOR) continue;
    const V w1 = CGAL::cross_product(n1, l), w2 = CGAL::cross_product(n2, l);
    // Each corner on the line or off it to either side, along the line either way.
    const int ka = side(rng), kb = side(rng), kc = side(rng), kd = side(rng);
    auto along = [&]() { return (side(rng) == 0 ? -1 : 1) * length(rng); };
    const P a = p + l * along() + w1 * offset(ka), b = p + l * along() + w1 * offset(kb);
    const P c = p + l * along() + w2 * offset(kc), d = p + l * along() + w2 * offset(kd);
    if (CGAL::collinear(p, a, b) || CGAL::collinear(p, c, d)) continue;
    const auto fast = seam::internal::only_vertex_along_edges(p, a, b, c, d);
    const bool general = only_vertex_in_general(p, a, b, c, d);
    if (fast) {
      ++decided;
      CHECK(*fast == general);
    }
    (general ? apart : meeting) += 1;
    // An edge of each on the line (one corner on it, the other off): always decided.
    const bool t_edge = (ka == 0) != (kb == 0), u_edge = (kc == 0) != (kd == 0);
    if (t_edge && u_edge) {
      ++along_both;
      CHECK(fast.has_value());
    }
    // An edge of one on the line, the other straddling the first one's plane: decided too.
    const bool t_straddles = ka != 0 && kb != 0 && ka != kb, u_straddles = kc != 0 && kd != 0 && kc != kd;
    if ((t_edge && u_straddles) || (u_edge && t_straddles)) {
      ++along_one;
      CHECK(fast.has_value());
    }
  }
  CHECK(along_both > 100);
  CHECK(along_one > 100);
  CHECK(decided > 1000);
  CHECK(apart > 100);  // both answers occur
  CHECK(meeting > 100);
}

TEST_CASE("min_angle_deg is the smallest of the three angles, also where it computes one only", "[quality]") {
  // The three angles as atan2(|u x v|, u . v), the smallest taken (min_angle_deg computes the one
  // opposite the shortest side alone where that side is clearly the shortest).
  using P = seam::Filtered::Point_3;
  auto at = [](const P& a, const P& b, const P& c) {
    const auto u = b - a, v = c - a;
    if (u.squared_length() <= 0 || v.squared_length() <= 0) return 0.0;
    return std::atan2(std::sqrt(CGAL::cross_product(u, v).squared_length()), u * v) * 180.0 / M_PI;
  };
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> unit(-1, 1);
  std::size_t differ = 0, one_computed = 0;
  for (int i = 0; i < 200000; ++i) {
    const P p(unit(rng), unit(rng), unit(rng)), q(unit(rng), unit(rng), unit(rng));
    P r(unit(rng), unit(rng), unit(rng));
    switch (i % 4) {  // slivers, caps and near-isosceles triangles too
      case 1: r = P(p.x() + (q.x() - p.x()) * 0.5 + 1e-7 * unit(rng), p.y() + (q.y() - p.y()) * 0.5 + 1e-7 * unit(rng), p.z() + (q.z() - p.z()) * 0.5); break;
      case 2: r = P(q.x() + 1e-6 * unit(rng), q.y() + 1e-6 * unit(rng), q.z() + 1e-6 * unit(rng)); break;
      case 3: {  // |pr| = |pq| (1 + tiny): two sides nearly equal
        const double k = 1 + 1e-7 * unit(rng);
        r = P(p.x() + (q.y() - p.y()) * k, p.y() - (q.x() - p.x()) * k, p.z() + (q.z() - p.z()) * k);
        break;
      }
      default: break;
    }
    const double reference = std::min({at(p, q, r), at(q, r, p), at(r, p, q)});
    double d2[3] = {CGAL::squared_distance(q, r), CGAL::squared_distance(r, p), CGAL::squared_distance(p, q)};
    std::sort(d2, d2 + 3);
    one_computed += d2[0] * (1 + 1e-6) < d2[1];  // one side clearly the shortest
    if (reference < 1e-9 * 180 / M_PI) continue;  // (the bound min_angle_deg states)
    differ += seam::min_angle_deg(p, q, r) != reference;
  }
  CHECK(differ == 0);
  CHECK(one_computed > 100000);
  // Degenerate triangles: 0 (a corner twice, three corners on a line, one point).
  const P o(0, 0, 0), x(1, 0, 0), y(2, 0, 0), z(0.5, 0.25, 3);
  CHECK(seam::min_angle_deg(o, x, x) == 0);
  CHECK(seam::min_angle_deg(z, o, z) == 0);
  CHECK(seam::min_angle_deg(o, x, y) == 0);
  CHECK(seam::min_angle_deg(x, o, y) == 0);
  CHECK(seam::min_angle_deg(o, o, o) == 0);
}
