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
