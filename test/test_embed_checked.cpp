// Tests of seam::embed_checked (`seam embed` as a whole: embed, the quality stage, the output
// checked as written) and of seam::check_embedding, its independent check.
#include <catch2/catch.hpp>

#include <seam/check.h>
#include <seam/embed.h>
#include <seam/generate.h>
#include <seam/io.h>
#include <seam/quality.h>
#include <seam/verify.h>

#include <CGAL/Polygon_mesh_processing/measure.h>

#include <cmath>
#include <vector>

#include "test_support.h"
#include "tow_fixtures.h"

namespace {

/// A crimped, turned tow and two tilted rings on its smooth surface (off the facets by up to the
/// chordal error), as a user's given curves.
struct TowAndRings {
  seam::TriangleSoup tow;
  std::vector<std::vector<seam::Point3d>> rings;
};

TowAndRings tow_and_rings(seam::Section section) {
  seam::TowOptions tow;
  tow.segments_along = 40;
  tow.segments_around = 20;
  tow.crimp_amplitude = 0.4;
  tow.rotate_z = 0.3;
  tow.rotate_x = 0.2;
  tow.section = section;
  return {seam::make_tow(tow), {seam::make_ring_curve(tow, 4.93, 0.6, 1500), seam::make_ring_curve(tow, 7.41, -0.3, 1500)}};
}

/// Faces of `mesh` below `degrees` among those marked new.
template <class K> std::size_t new_faces_below(const seam::Mesh<K>& mesh, double degrees) {
  const auto q = seam::new_face_quality<K>(mesh);
  return degrees == 10 ? q.below_10 : q.below_20;
}

}  // namespace

TEMPLATE_TEST_CASE("embed_checked: given rings off the facets come out embedded, improved and verified", "[embed][improve]",
                   seam::Exact, seam::Filtered) {
  using K = TestType;
  for (auto section : {seam::Section::elliptical, seam::Section::lenticular}) {
    INFO((section == seam::Section::lenticular ? "lenticular" : "elliptical"));
    const auto given = tow_and_rings(section);
    const auto input = seam::mesh_from_soup<K>(given.tow, "tow");
    const auto curves = seam::to_kernel<K>(given.rings);
    for (double snap : {0.0, -1.0}) {
      INFO("snap_tol " << snap);
      seam::EmbedRunOptions o;
      o.embed.snap_tol = snap;
      auto mesh = input;
      const auto r = seam::embed_checked<K>(mesh, curves, o);
      INFO(r.note);
      REQUIRE(r.verified);
      CHECK(r.improved == (snap != 0));  // (at tolerance 0 the stage is not run: see EmbedRunOptions)
      REQUIRE(r.curves.size() == 2);
      for (const auto& c : r.curves) CHECK(seam::is_closed(c));
      // The contract, tested apart from the check embed ran: a valid closed mesh holding the curves.
      auto problems = seam::check_valid_mesh<K>(mesh, true);
      const auto more = seam::check_curves_embedded<K>(mesh, r);
      problems.insert(problems.end(), more.begin(), more.end());
      for (const auto& p : problems) UNSCOPED_INFO(p);
      CHECK(problems.empty());
      // And the independent check, in the kernel, at the tolerance embed states.
      const auto report = seam::check_embedding<K>(input, mesh, r.curves, r.verify_tolerance, &curves);
      for (const auto& p : report.problems) UNSCOPED_INFO(p);
      CHECK(report.ok());
      CHECK(report.max_distance <= r.verify_tolerance);
      // The enclosed volume moves at most by the tolerance times the area (the quality stage's
      // changes stay within it of the surface).
      const double v0 = CGAL::to_double(CGAL::Polygon_mesh_processing::volume(input));
      const double v1 = CGAL::to_double(CGAL::Polygon_mesh_processing::volume(mesh));
      const double area = CGAL::to_double(CGAL::Polygon_mesh_processing::area(input));
      CHECK(std::abs(v1 - v0) <= r.verify_tolerance * area);
      // The quality stage leaves no more thin new faces than the re-triangulation made.
      auto embedded = input;
      o.improve = false;
      const auto r0 = seam::embed_checked<K>(embedded, curves, o);
      CHECK(r0.verified);
      CHECK_FALSE(r0.improved);
      CHECK(new_faces_below<K>(mesh, 10) <= new_faces_below<K>(embedded, 10));
      CHECK(new_faces_below<K>(mesh, 20) <= new_faces_below<K>(embedded, 20));
      CHECK(r.stats.new_faces_below_20 == new_faces_below<K>(mesh, 20));
    }
  }
}

TEST_CASE("embed_checked: under an area bound the quality stage refines to it as well as to the angle bound",
          "[embed][improve][max-area]") {
  using K = seam::Exact;
  const auto given = tow_and_rings(seam::Section::elliptical);
  const auto input = seam::mesh_from_soup<K>(given.tow, "tow");
  const auto curves = seam::to_kernel<K>(given.rings);
  // Half the input's mean face area: the re-triangulation alone leaves larger faces. (At a
  // quarter, without the quality stage, its Steiner points come closer than the vertex separation
  // and the output is refused; the stage's merges remove them.)
  const double area = CGAL::to_double(CGAL::Polygon_mesh_processing::area(input));
  seam::EmbedRunOptions o;
  o.embed.max_area = 0.5 * area / double(input.number_of_faces());
  auto mesh = input, embedded = input;
  o.improve = false;
  const auto r0 = seam::embed_checked<K>(embedded, curves, o);
  o.improve = true;
  const auto r = seam::embed_checked<K>(mesh, curves, o);
  REQUIRE(r.verified);
  REQUIRE(r0.verified);
  CHECK(r.improved);
  INFO("above the bound " << r.stats.new_faces_above_max_area << " (without the stage " << r0.stats.new_faces_above_max_area
                          << "), below 20 degrees " << r.stats.new_faces_below_20 << " (" << r0.stats.new_faces_below_20 << ")");
  // The figures embed reports are what a count here finds. Without the stage faces are left above
  // the bound; with it none of those held to it (made within the faces the curves cross or
  // touch; farther out the band is graded to the input's size), and fewer thin faces.
  CHECK(r.stats.new_faces_above_max_area == seam_test::new_faces_larger_than<K>(mesh, o.embed.max_area));
  CHECK(r0.stats.new_faces_above_max_area > 0);
  CHECK(r.improve.above_max_area_after == 0);
  CHECK(r.stats.new_faces_below_20 < r0.stats.new_faces_below_20);
  CHECK(seam::check_embedding<K>(input, mesh, r.curves, r.verify_tolerance, &curves).ok());
}

TEST_CASE("embed_checked: under the float kernel a result is verified or refused, never given unverified",
          "[embed][improve]") {
  using K = seam::Float;
  const auto given = tow_and_rings(seam::Section::elliptical);
  const auto input = seam::mesh_from_soup<K>(given.tow, "tow");
  auto mesh = input;
  try {
    const auto r = seam::embed_checked<K>(mesh, seam::to_kernel<K>(given.rings));
    CHECK(r.verified);
    CHECK(seam::check_embedding<K>(input, mesh, r.curves, r.verify_tolerance).ok());
  } catch (const seam::InternalError& e) {
    INFO(e.what());
    CHECK(mesh.number_of_faces() == input.number_of_faces());  // restored
  }
}

TEST_CASE("check_embedding: fails on a missing curve point, a moved vertex and a self-intersection", "[check][embed]") {
  using K = seam::Exact;
  const auto given = tow_and_rings(seam::Section::elliptical);
  const auto input = seam::mesh_from_soup<K>(given.tow, "tow");
  auto mesh = input;
  const auto r = seam::embed_checked<K>(mesh, seam::to_kernel<K>(given.rings));
  REQUIRE(seam::check_embedding<K>(input, mesh, r.curves, r.verify_tolerance).ok());

  SECTION("a curve point that is not a vertex") {
    auto curves = r.curves;
    const auto& p = curves[0][1];
    curves[0][1] = K::Point_3(p.x() + 1e-6, p.y(), p.z());
    CHECK_FALSE(seam::check_embedding<K>(input, mesh, curves, r.verify_tolerance).ok());
  }
  SECTION("a vertex moved off the surface by more than the tolerance") {
    auto moved = mesh;
    const auto v = *moved.vertices().begin();
    const auto& p = moved.point(v);
    moved.point(v) = K::Point_3(p.x(), p.y(), p.z() + 10 * r.verify_tolerance + 0.01);
    CHECK_FALSE(seam::check_embedding<K>(input, moved, r.curves, r.verify_tolerance).ok());
  }
  SECTION("a vertex pushed through the opposite side") {
    // The vertex of largest z goes below the smallest z: its faces cross the tow's bottom.
    auto moved = mesh;
    auto top = *moved.vertices().begin();
    double zmin = HUGE_VAL;
    for (auto v : moved.vertices()) {
      if (moved.point(v).z() > moved.point(top).z()) top = v;
      zmin = std::min(zmin, CGAL::to_double(moved.point(v).z()));
    }
    const auto& p = moved.point(top);
    moved.point(top) = K::Point_3(p.x(), p.y(), zmin - 0.1);
    const auto report = seam::check_embedding<K>(input, moved, r.curves, 1.0);  // (distance allowed)
    CHECK_FALSE(report.ok());
    CHECK_FALSE(report.conflict_faces.empty());
  }
}

TEST_CASE("check_embedding and tetgen -d agree on whether an output intersects itself", "[check][embed][tetgen]") {
  // Outputs of embed, as written (doubles), and the same with one vertex moved: a little outward
  // (still a valid surface), or through the tow (its faces cross others). The check's verdict on
  // self-intersection (faces in conflict) must be TetGen's on the written surface.
  using K = seam::Exact;
  int cases = 0, intersecting = 0;
  for (auto section : {seam::Section::elliptical, seam::Section::lenticular}) {
    const auto given = tow_and_rings(section);
    const auto input = seam::mesh_from_soup<K>(given.tow, "tow");
    auto mesh = input;
    const auto r = seam::embed_checked<K>(mesh, seam::to_kernel<K>(given.rings));
    const seam::TriangleSoup written = seam::soup_from_mesh<K>(mesh);
    double zmin = HUGE_VAL;
    for (const auto& p : written.points) zmin = std::min(zmin, p[2]);
    for (int variant = 0; variant < 4; ++variant) {
      INFO("variant " << variant);
      seam::TriangleSoup soup = written;
      // The vertex of largest z (a top vertex) moves: 0 not at all, 1 up by 1e-3, 2 down to just
      // below the bottom, 3 down to the middle of the tow (its faces then cross the rest).
      std::size_t top = 0;
      for (std::size_t i = 0; i < soup.points.size(); ++i)
        if (soup.points[i][2] > soup.points[top][2]) top = i;
      const double z = soup.points[top][2];
      if (variant == 1) soup.points[top][2] = z + 1e-3;
      if (variant == 2) soup.points[top][2] = zmin - 0.05;
      if (variant == 3) soup.points[top][2] = (z + zmin) / 2;
      const auto out = seam::mesh_from_soup<K>(soup, "out");
      const auto report = seam::check_embedding<K>(input, out, seam::to_kernel<K>(seam::to_doubles<K>(r.curves)), 1.0);
      seam_test::TempDir dir("seam_test_check_embed");
      const long pairs = seam_test::tetgen_intersecting_pairs({soup}, dir);
      INFO("tetgen: " << pairs << " pairs; check: " << report.conflict_faces.size() << " faces in conflict");
      CHECK((pairs > 0) == !report.conflict_faces.empty());
      ++cases;
      intersecting += pairs > 0 ? 1 : 0;
    }
  }
  CHECK(cases == 8);
  CHECK(intersecting >= 2);  // both verdicts are reached
}
