// seam check: verify a conforming pair independently of the code that produced it.
//
// Exit codes: 0 every check holds; 1 verification failed (one "FAIL: ..." line per problem on
// stdout, then the summary); 2 bad input or usage (a file that cannot be read or is not a valid
// triangle mesh / polyline file, named on stderr); 3 internal error.
//
// SPDX-License-Identifier: GPL-3.0-or-later
#include "common.h"

#include <seam/check.h>

#include <cmath>
#include <fstream>
#include <iostream>
#include <limits>
#include <memory>
#include <sstream>

namespace seam_cli {

namespace {

struct CheckArgs {
  std::string a, b, a2, b2, curves, report, kernel = "exact";
  NumberText tol_text;  // "auto" or not given: 1e-9 x the bounding-box diagonal of A and B
  double tol = -1;      // < 0: automatic
};

/// True when the file holds no polyline at all: only blank lines and '#' comments.
bool has_no_polyline(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  std::string line;
  while (std::getline(in, line)) {
    const auto first = line.find_first_not_of(" \t\r\f\v");
    if (first != std::string::npos && line[first] != '#') return false;
  }
  return !in.bad();
}

nlohmann::json report_json(const seam::PairCheckReport& r, const CheckArgs& a) {
  nlohmann::json j = check_report_json(r, a.kernel);
  j["files"] = {{"a", a.a}, {"b", a.b}, {"a2", a.a2}, {"b2", a.b2}, {"curves", a.curves}};
  return j;
}

void print_summary(std::ostream& os, const seam::PairCheckReport& r, const CheckArgs& a) {
  os << "seam check: " << (r.ok() ? "OK" : "FAILED") << " (" << r.problems.size() << " problem"
     << (r.problems.size() == 1 ? "" : "s") << ", kernel " << a.kernel << ")\n";
  os << "  curves:      " << r.curves << " (" << r.curve_vertices << " vertices, " << r.curve_segments
     << " segments)\n";
  os << "  face pairs:  " << r.candidate_face_pairs << " with overlapping boxes, " << r.face_pairs_on_curve
     << " meeting on the curves, " << r.intersecting_face_pairs_off_curve << " intersecting off the curves; "
     << r.shared_faces << " shared faces\n";
  os << "  coverage:    " << r.intersection_samples << " points sampled on the intersection of A and B, "
     << r.uncovered_samples << " farther than the tolerance from the curves; " << r.close_vertex_pairs
     << " vertex pairs closer than " << r.min_separation << "\n";
  os << "  tolerance:   " << r.tolerance << " (largest distance from the input: A2 " << r.max_distance_a << ", B2 "
     << r.max_distance_b << ")\n";
  auto mesh_line = [&](const char* name, std::size_t v, std::size_t f, std::size_t nf, double angle, std::size_t b10,
                       std::size_t b20) {
    os << "  " << name << ":          " << v << " vertices, " << f << " faces (" << nf
       << " not in the input); min angle " << angle << " deg; new faces below 10 deg: " << b10
       << ", below 20 deg: " << b20 << "\n";
  };
  mesh_line("A2", r.vertices_a2, r.faces_a2, r.new_faces_a, r.min_angle_deg_a, r.below_10_a, r.below_20_a);
  mesh_line("B2", r.vertices_b2, r.faces_b2, r.new_faces_b, r.min_angle_deg_b, r.below_10_b, r.below_20_b);
}

int run_check(CheckArgs a) {
  a.tol = number_option("--tol", a.tol_text, NumberRange::non_negative_or_auto(), -1.0);
  refuse_overwrite({a.a, a.b, a.a2, a.b2, a.curves}, {a.report});
  seam::OutputFiles files;  // the report's temporary file, created before any work
  const auto out = add_outputs(files, {a.report});
  const auto t0 = Clock::now();
  const seam::TriangleSoup sa = seam::read_triangle_mesh(a.a), sb = seam::read_triangle_mesh(a.b),
                           sa2 = seam::read_triangle_mesh(a.a2), sb2 = seam::read_triangle_mesh(a.b2);
  std::vector<std::vector<seam::Point3d>> polylines;
  try {
    polylines = seam::read_polylines(a.curves);
  } catch (const seam::InvalidInput&) {
    if (!has_no_polyline(a.curves)) throw;  // an empty curves file means: no curves
  }
  if (a.tol < 0) a.tol = default_check_tolerance(sa, sb);
  const double read_seconds = std::chrono::duration<double>(Clock::now() - t0).count();

  return seam::with_kernel(parse_kernel(a.kernel), [&](auto kernel) {
    using K = decltype(kernel);
    const auto ma = seam::mesh_from_soup<K>(sa, a.a), mb = seam::mesh_from_soup<K>(sb, a.b);
    const auto ma2 = seam::mesh_from_soup<K>(sa2, a.a2), mb2 = seam::mesh_from_soup<K>(sb2, a.b2);
    const auto curves = seam::to_kernel<K>(polylines);
    const auto t1 = Clock::now();
    const seam::PairCheckReport r = seam::check_pair<K>(ma, mb, ma2, mb2, curves, a.tol);
    const double check_seconds = std::chrono::duration<double>(Clock::now() - t1).count();

    for (const auto& p : r.problems) std::cout << "FAIL: " << p << "\n";
    print_summary(std::cout, r, a);
    std::cout.flush();
    if (!a.report.empty()) {
      nlohmann::json j = report_json(r, a);
      j["seconds"] = {{"read", read_seconds}, {"check", check_seconds}};
      files.write(out[0], [&](std::ostream& os) { write_json(j, os); });
      files.commit();
    }
    return r.ok() ? 0 : 1;
  });
}

struct CheckEmbedArgs {
  std::string mesh, out, curves, given, report, kernel = "exact";
  NumberText tol_text;
};

int run_check_embed(CheckEmbedArgs a) {
  double tol = number_option("--tol", a.tol_text, NumberRange::non_negative_or_auto(), -1.0);
  refuse_overwrite({a.mesh, a.out, a.curves, a.given}, {a.report});
  seam::OutputFiles files;
  const auto out = add_outputs(files, {a.report});
  const seam::TriangleSoup input = seam::read_triangle_mesh(a.mesh), output = seam::read_triangle_mesh(a.out);
  std::vector<std::vector<seam::Point3d>> polylines, given;
  try {
    polylines = seam::read_polylines(a.curves);
  } catch (const seam::InvalidInput&) {
    if (!has_no_polyline(a.curves)) throw;
  }
  if (!a.given.empty()) given = seam::read_polylines(a.given);
  if (tol < 0) tol = default_check_tolerance(input, input);

  return seam::with_kernel(parse_kernel(a.kernel), [&](auto kernel) {
    using K = decltype(kernel);
    const auto min = seam::mesh_from_soup<K>(input, a.mesh), mout = seam::mesh_from_soup<K>(output, a.out);
    const auto curves = seam::to_kernel<K>(polylines), given_curves = seam::to_kernel<K>(given);
    const seam::EmbedCheckReport r =
        seam::check_embedding<K>(min, mout, curves, tol, a.given.empty() ? nullptr : &given_curves);
    for (const auto& p : r.problems) std::cout << "FAIL: " << p << "\n";
    std::cout << "seam check-embed: " << (r.ok() ? "OK" : "FAILED") << " (" << r.problems.size() << " problem"
              << (r.problems.size() == 1 ? "" : "s") << ", kernel " << a.kernel << ")\n"
              << "  curves:    " << r.curves << " (" << r.curve_vertices << " vertices, " << r.curve_segments
              << " segments)\n"
              << "  tolerance: " << r.tolerance << " (largest distance from the input: " << r.max_distance << "); "
              << r.close_vertex_pairs << " vertex pairs closer than " << r.min_separation << "\n"
              << "  output:    " << r.vertices << " vertices, " << r.faces << " faces (" << r.new_faces
              << " not in the input); min angle " << r.min_angle_deg << " deg; new faces below 10 deg: " << r.below_10
              << ", below 20 deg: " << r.below_20 << "\n";
    if (!a.given.empty())
      std::cout << "  given:     largest distance from a given curve point to the curves " << r.given_to_embedded
                << ", from a curve point to the given curves " << r.embedded_to_given << "\n";
    std::cout.flush();
    if (!a.report.empty()) {
      nlohmann::json j;
      j["ok"] = r.ok();
      j["kernel"] = a.kernel;
      j["problems"] = r.problems;
      j["curves"] = {{"curves", r.curves}, {"vertices", r.curve_vertices}, {"segments", r.curve_segments}};
      j["tolerance"] = r.tolerance;
      j["max_distance"] = r.max_distance;
      j["separation"] = {{"min_separation", r.min_separation},
                         {"close_vertex_pairs", r.close_vertex_pairs},
                         {"close_vertex_pairs_in_input", r.close_vertex_pairs_in_input}};
      j["output"] = {{"vertices", r.vertices}, {"faces", r.faces}, {"new_faces", r.new_faces}};
      j["quality"] = {{"min_angle_deg", r.min_angle_deg}, {"below_10", r.below_10}, {"below_20", r.below_20}};
      j["given"] = {{"given_to_embedded", r.given_to_embedded}, {"embedded_to_given", r.embedded_to_given}};
      j["files"] = {{"mesh", a.mesh}, {"out", a.out}, {"curves", a.curves}, {"given", a.given}};
      files.write(out[0], [&](std::ostream& os) { write_json(j, os); });
      files.commit();
    }
    return r.ok() ? 0 : 1;
  });
}

}  // namespace

Command add_check_embed_command(CLI::App& app) {
  auto args = std::make_shared<CheckEmbedArgs>();
  CheckEmbedArgs& ca = *args;
  auto* cmd = app.add_subcommand(
      "check-embed",
      "Verify one mesh with embedded curves (the output of seam embed), independently of the code that produced it: "
      "OUT is a valid triangle mesh (no degenerate face, no two vertices at one point, no self-intersection, closed "
      "when MESH is), every curve point is a vertex with identical coordinates and every curve segment an edge, "
      "every vertex lies within --tol of MESH's surface, and distinct vertices are at least 2e-8 of the diagonal "
      "apart. Exit 0 when all hold, 1 when a check fails ('FAIL: ...' lines), 2 on bad input, 3 on an internal "
      "error.");
  cmd->add_option("MESH", ca.mesh, "The input mesh (.off, .obj, .ply, .stl)")->required();
  cmd->add_option("OUT", ca.out, "The output mesh (seam embed -o)")->required();
  cmd->add_option("CURVES", ca.curves, "The embedded curves (seam embed --curves-out)")->required();
  cmd->add_option("--given", ca.given,
                  "The curves as given to seam embed: prints the largest distances between them and CURVES");
  add_number_option(cmd, "--tol", ca.tol_text,
                    "Largest allowed distance of a vertex of OUT from the surface of MESH (default: auto, 1e-9 x the "
                    "bounding-box diagonal of MESH; with snapping use at least the snap tolerance: seam embed prints "
                    "the value)");
  cmd->add_option("--kernel", ca.kernel, "exact (default: the reference), filtered or float")
      ->check(CLI::IsMember({"exact", "filtered", "float"}));
  cmd->add_option("--report", ca.report, "Write a JSON report (problems and figures) here");
  return {cmd, [args] { return run_check_embed(*args); }};
}

Command add_check_command(CLI::App& app) {
  auto args = std::make_shared<CheckArgs>();
  CheckArgs& ca = *args;
  auto* check = app.add_subcommand(
      "check",
      "Verify a conforming pair, independently of the code that produced it: A2 and B2 are valid triangle meshes "
      "(no degenerate face, no self-intersection, closed when the input is), every curve point is a vertex of both "
      "with identical coordinates and every curve segment an edge of both, A2 and B2 intersect nowhere but along "
      "the curves, and every vertex of A2 (B2) lies within --tol of A (B); prints the quality figures. Exit 0 when "
      "all hold, 1 when a check fails (verification failed: 'FAIL: ...' lines on stdout), 2 on bad input, 3 on an "
      "internal error.");
  check->add_option("A", ca.a, "Input mesh A (.off, .obj, .ply, .stl)")->required();
  check->add_option("B", ca.b, "Input mesh B")->required();
  check->add_option("A2", ca.a2, "Output mesh A2 (A made conforming)")->required();
  check->add_option("B2", ca.b2, "Output mesh B2 (B made conforming)")->required();
  check->add_option("CURVES", ca.curves,
                    "The shared curves, one polyline per line: 'n x1 y1 z1 ... xn yn zn'; a file with no polyline "
                    "(empty, or comments only) means no curves: A2 and B2 must then not meet at all")
      ->required();
  add_number_option(check, "--tol", ca.tol_text,
                    "Largest allowed distance of a vertex of A2 (B2) from the surface of A (B) (default: auto, 1e-9 x the "
                    "bounding-box diagonal of A and B; with snapping use at least the snap tolerance)");
  check->add_option("--kernel", ca.kernel,
                    "exact (Epeck, default: the reference), filtered (Epick: exact predicates on the coordinates as "
                    "read) or float (double)")
      ->check(CLI::IsMember({"exact", "filtered", "float"}));
  check->add_option("--report", ca.report, "Write a JSON report (problems and figures) here");
  return {check, [args] { return run_check(*args); }};
}

}  // namespace seam_cli
