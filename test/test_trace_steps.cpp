// The traced curve's invariant: one face per step (as many as points when closed, one fewer when
// open), and step_face[i] holds points i and i + 1. A walk tried again with another cutting plane
// used to leave one face behind, and every later step of the curve then had its neighbour's face:
// embed failed with "a curve segment inside the face ... ends at point N, which is not on that
// face" on a CT-scanned tow.
#include <catch2/catch.hpp>

#include <seam/generate.h>
#include <seam/io.h>
#include <seam/internal/trace.h>

#include <cmath>
#include <random>
#include <vector>

TEST_CASE("trace: every step's face holds both its points, on a terraced tow with wiggly and hairpin curves",
          "[embed][trace]") {
  using K = seam::Exact;
  seam::TowOptions tow;
  tow.segments_along = 24;
  tow.segments_around = 12;
  tow.crimp_amplitude = 0.4;
  tow.rotate_z = 0.3;
  // Terraced like a tow from a voxel scan (heights rounded to multiples of 0.05): many vertices
  // on common planes, where walks meet vertices and need another cutting plane.
  auto soup = seam::make_tow(tow);
  for (auto& p : soup.points) p[2] = 0.05 * std::round(p[2] / 0.05);
  const auto mesh = seam::mesh_from_soup<K>(soup, "tow");
  // Wiggly closed curves on the smooth surface: rings whose position along the tow oscillates
  // with a period of a few faces, so they cross edges back and forth and graze vertices.
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(0, 1);
  std::vector<seam::Polyline<K>> curves;
  for (int c = 0; c < 400; ++c) {
    const double s0 = 2 + 6 * unit(rng), amp = 0.02 + 0.3 * unit(rng), waves = 3 + std::floor(20 * unit(rng));
    const double tilt = 0.3 * (unit(rng) - 0.5);
    const int n = c % 2 ? 12 + int(40 * unit(rng)) : 200 + int(400 * unit(rng));  // long walks and short ones
    std::vector<seam::Point3d> pts;
    for (int k = 0; k < n; ++k) {
      const double phi = 2 * M_PI * k / n;
      pts.push_back(seam::tow_surface_point(tow, s0 + tilt * std::cos(phi) + amp * std::sin(waves * phi), phi));
    }
    pts.push_back(pts.front());
    curves.push_back(seam::to_kernel<K>(std::vector<std::vector<seam::Point3d>>{pts})[0]);
  }
  // Thin hairpin loops (out along the tow's section and back a hair's width away), whose walks
  // from the turn go back over the edges they came by.
  for (int c = 0; c < 300; ++c) {
    const double s0 = 2 + 6 * unit(rng), phi0 = 2 * M_PI * unit(rng), span = 0.3 + 2 * unit(rng);
    const double width = 1e-4 + 0.02 * unit(rng);
    const int n = 6 + int(30 * unit(rng));
    std::vector<seam::Point3d> pts;
    for (int k = 0; k <= n; ++k) pts.push_back(seam::tow_surface_point(tow, s0, phi0 + span * k / n));
    for (int k = n; k >= 0; --k) pts.push_back(seam::tow_surface_point(tow, s0 + width, phi0 + span * k / n));
    pts.push_back(pts.front());
    curves.push_back(seam::to_kernel<K>(std::vector<std::vector<seam::Point3d>>{pts})[0]);
  }
  seam::internal::TraceReport report;
  const auto traced = seam::internal::trace_curves<K>(mesh, curves, 1.0, report);
  INFO("walks tried again: " << report.retries);
  std::size_t bad = 0;
  for (const auto& tc : traced) {
    const std::size_t n = tc.points.size();
    REQUIRE(tc.step_face.size() == (tc.closed ? n : n - 1));
    for (std::size_t i = 0; i < tc.step_face.size(); ++i) {
      const auto f = tc.step_face[i];
      const auto& p = seam::internal::traced_location<K>(mesh, tc, i);
      const auto& q = seam::internal::traced_location<K>(mesh, tc, (i + 1) % n);
      if (!seam::internal::face_contains<K>(mesh, f, p) || !seam::internal::face_contains<K>(mesh, f, q)) ++bad;
    }
  }
  CHECK(bad == 0);
  // (These generated curves need no second cutting plane: report.retries is 0 here. The walk
  // that needed one, and the face left behind, came from a CT tow: scripts/real_tows_embed.py,
  // row 4.)
}

// Nodes that lie on the surface exactly (nodes_on_surface) are located by exact predicates on
// the node itself; other nodes by the exact projection onto the closest face. Both must give the
// same place: corners, points on sides, interior points, and points a hair from a side (whose
// closest face in doubles may be the neighbour).
TEST_CASE("trace: nodes on the surface are located as by their projections", "[embed][trace]") {
  using K = seam::Exact;
  using FT = K::FT;
  seam::TowOptions tow;
  tow.segments_along = 16;
  tow.segments_around = 10;
  tow.crimp_amplitude = 0.3;
  const auto mesh = seam::mesh_from_soup<K>(seam::make_tow(tow), "tow");
  std::mt19937 rng(11);
  std::uniform_int_distribution<int> kind(0, 4);
  std::vector<seam::Polyline<K>> curves;
  for (auto f : mesh.faces()) {
    const auto h = mesh.halfedge(f);
    const K::Point_3 a = mesh.point(mesh.source(h)), b = mesh.point(mesh.target(h)),
                     c = mesh.point(mesh.target(mesh.next(h)));
    auto at = [&](const FT& s, const FT& t) { return a + (b - a) * s + (c - a) * t; };
    const FT hair = FT(1) / FT(1e17);
    seam::Polyline<K> curve;
    // Three nodes in the closed face, one of each kind drawn, then back to the first.
    for (int k = 0; k < 3; ++k) {
      switch (kind(rng)) {
        case 0: curve.push_back(k == 0 ? a : k == 1 ? b : c); break;        // a corner
        case 1: curve.push_back(at(FT(1) / FT(3), FT(1) / FT(7) * k)); break;  // inside (a side for k = 0)
        case 2: curve.push_back(at(FT(k + 1) / FT(5), FT(0))); break;        // on side ab
        case 3: curve.push_back(at(FT(1) / FT(2), hair * (k + 1))); break;   // a hair inside side ab
        default: curve.push_back(at(FT(2) / FT(9), FT(3) / FT(8))); break;  // inside
      }
    }
    if (curve[0] == curve[1] || curve[1] == curve[2] || curve[0] == curve[2]) continue;
    curve.push_back(curve.front());
    curves.push_back(curve);
  }
  REQUIRE(curves.size() > 100);
  seam::internal::TraceReport on_report, off_report;
  const auto on = seam::internal::trace_curves<K>(mesh, curves, 1.0, on_report, /*nodes_on_surface=*/true);
  const auto off = seam::internal::trace_curves<K>(mesh, curves, 1.0, off_report, /*nodes_on_surface=*/false);
  REQUIRE(on.size() == off.size());
  std::size_t differ = 0, face_points = 0, edge_points = 0, vertices = 0;
  for (std::size_t c = 0; c < on.size(); ++c) {
    REQUIRE(on[c].points.size() == off[c].points.size());
    for (std::size_t i = 0; i < on[c].points.size(); ++i) {
      const auto& p = on[c].points[i];
      differ += !p.same_as(off[c].points[i]);
      face_points += p.where == seam::internal::Where::face;
      edge_points += p.where == seam::internal::Where::edge;
      vertices += p.where == seam::internal::Where::vertex;
    }
  }
  CHECK(differ == 0);
  CHECK(on_report.located_by_predicates > curves.size());  // the new path was taken
  CHECK(off_report.located_by_predicates == 0);
  CHECK(face_points > 50);  // every kind was met
  CHECK(edge_points > 50);
  CHECK(vertices > 50);
}
