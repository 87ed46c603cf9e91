// seam pair: make two interpenetrating tow meshes conforming along their intersection curves.
// SPDX-License-Identifier: GPL-3.0-or-later
#include "common.h"

#include <seam/pair.h>
#include <seam/vtk.h>

#include <tbb/parallel_invoke.h>

#include <iostream>
#include <memory>

namespace seam_cli {

namespace {

struct PairArgs {
  std::string a, b, out_a, out_b, curves, curves_out, report, vtk, kernel = "exact";
  NumberText snap_tol, min_angle, max_area, bound_reach;
  seam::PairOptions options;
};

int run_pair(PairArgs& args) {
  // Every option before any work.
  seam::EmbedOptions& o = args.options.embed;
  o.snap_tol = number_option("--snap-tol", args.snap_tol, NumberRange::non_negative_or_auto(), o.snap_tol);
  o.min_angle_deg = number_option("--min-angle", args.min_angle, NumberRange::between(0, 60, "degrees"), o.min_angle_deg);
  o.max_area = number_option("--max-area", args.max_area, NumberRange::non_negative(), o.max_area);
  read_bound_reach_option(args.bound_reach, args.options.quality.bound_reach);
  seam::validate_options(args.options.embed);
  // Every output path before any work: formats, no input overwritten, temporary files created
  // (renamed in this order at the end: meshes, curves, VTK, report).
  std::vector<std::string> inputs{args.a, args.b};
  if (!args.curves.empty()) inputs.push_back(args.curves);
  refuse_overwrite(inputs, {args.out_a, args.out_b, args.curves_out, args.vtk, args.report});
  seam::check_mesh_extension(args.out_a);
  seam::check_mesh_extension(args.out_b);
  const std::string vtk_format = args.vtk.empty() ? std::string() : seam::vtk_format(args.vtk);
  seam::OutputFiles files;
  const auto out = add_outputs(files, {args.out_a, args.out_b, args.curves_out, args.vtk, args.report});
  const auto t0 = Clock::now();
  // The two files are read concurrently (parsing dominates), then checked for self-intersections.
  seam::TriangleSoup soup_a, soup_b;
  tbb::parallel_invoke(
      [&] {
        soup_a = seam::read_triangle_mesh(args.a);
        seam::check_no_self_intersection(soup_a, args.a);
      },
      [&] {
        soup_b = seam::read_triangle_mesh(args.b);
        seam::check_no_self_intersection(soup_b, args.b);
      });
  std::vector<std::vector<seam::Point3d>> given;
  if (!args.curves.empty()) given = seam::read_polylines(args.curves);
  const double read_seconds = std::chrono::duration<double>(Clock::now() - t0).count();

  return seam::with_kernel(parse_kernel(args.kernel), [&](auto kernel) {
    using K = decltype(kernel);
    seam::Mesh<K> a, b;
    tbb::parallel_invoke([&] { a = seam::mesh_from_soup<K>(soup_a, args.a); },
                         [&] { b = seam::mesh_from_soup<K>(soup_b, args.b); });
    seam::PairResult<K> result;
    if (args.curves.empty()) {
      result = seam::pair<K>(a, b, args.options);
    } else {
      try {
        result = seam::pair_with_curves<K>(a, b, seam::to_kernel<K>(given), args.options);
      } catch (const seam::InvalidInput& e) {
        throw seam::InvalidInput(args.curves + ": " + e.what());
      }
    }
    auto& st = result.stats;
    st.stage_seconds["read"] = read_seconds;
    const auto t1 = Clock::now();
    // Both meshes are formatted concurrently (formatting dominates), each into its temporary file.
    tbb::parallel_invoke(
        [&] {
          const seam::TriangleSoup soup = seam::soup_from_mesh<K>(a);
          files.write(out[0], [&](std::ostream& os) { seam::write_triangle_mesh(soup, os, fs::path(args.out_a).extension().string()); });
        },
        [&] {
          const seam::TriangleSoup soup = seam::soup_from_mesh<K>(b);
          files.write(out[1], [&](std::ostream& os) { seam::write_triangle_mesh(soup, os, fs::path(args.out_b).extension().string()); });
        });
    if (out[2] != no_output)
      files.write(out[2], [&](std::ostream& os) { seam::write_polylines(seam::to_doubles<K>(result.curves), os); });
    if (out[3] != no_output)
      files.write(out[3], [&](std::ostream& os) { seam::write_pair_vtk<K>(os, vtk_format, a, b, result.curves); });
    {
      st.stage_seconds["write"] = std::chrono::duration<double>(Clock::now() - t1).count();
      if (!args.report.empty()) {
        nlohmann::json j = pair_report_json(seam::kernel_traits<K>::kind, st, result.a.stats, result.b.stats,
                                            curve_summaries<K>(result.curves));
        j["files"] = {{"a", args.a}, {"b", args.b}, {"out_a", args.out_a}, {"out_b", args.out_b}};
        if (!args.curves.empty()) j["files"]["curves"] = args.curves;
        files.write(out[4], [&](std::ostream& os) { write_json(j, os); });
      }
    }
    files.commit();
    const auto& qa = result.a.stats;
    const auto& qb = result.b.stats;
    std::cout << "seam pair: " << st.curves << " curve(s) (" << st.closed_curves << " closed), " << st.curve_vertices
              << " shared vertices; A: "
              << qa.faces_crossed << " faces -> " << qa.faces_added << " (min angle " << qa.min_angle_deg_new
              << "), B: " << qb.faces_crossed << " faces -> " << qb.faces_added << " (min angle "
              << qb.min_angle_deg_new << ")";
    if (st.improved) {
      std::size_t flat = 0;
      for (const auto& s : st.improve.shortfalls) flat += s.cause == seam::ShortfallCause::flat_contact ? 1 : 0;
      std::cout << "; quality stage (tolerance " << st.snap_tol << "): " << st.improve.below_bound_after
                << " of the band's faces below " << args.options.embed.min_angle_deg << " degrees ("
                << st.improve.shortfalls.size() - flat << " new ones)";
      if (flat > 0) std::cout << ", and " << flat << " faces of flat contacts (shared by both, refined before this stage)";
    }
    if (st.curve_ends.unexplained > 0)
      std::cout << "; " << st.curve_ends.unexplained << " curve end(s) where the intersection is not a closed curve for no known reason";
    if (st.shared_faces > 0)
      std::cout << "; " << st.shared_faces << " faces shared by both (" << st.contact_patches << " flat contacts)";
    if (st.verified) std::cout << "; verified (seam check --tol " << tolerance_text(st.verify_tolerance) << ")";
    if (st.given_curves) std::cout << "; curve vertices moved onto the given curves by at most " << st.max_curve_move;
    if (!st.note.empty()) std::cout << "; " << st.note;
    std::cout << "\n";
    return 0;
  });
}

}  // namespace

Command add_pair_command(CLI::App& app) {
  auto args = std::make_shared<PairArgs>();
  PairArgs& pa = *args;
  auto* cmd = app.add_subcommand(
      "pair",
      "Make two interpenetrating triangle meshes conforming: compute their intersection curves exactly, embed the "
      "same curves into both, refine the faces next to them to an angle bound, so that both outputs share every curve vertex "
      "(bit-identical coordinates) and every curve edge.");
  cmd->add_option("A", pa.a, "First input mesh (.off, .obj, .ply, .stl)")->required();
  cmd->add_option("B", pa.b, "Second input mesh")->required();
  cmd->add_option("--out-a", pa.out_a, "Output for A (format by extension; OFF with 17 significant digits)")->required();
  cmd->add_option("--out-b", pa.out_b, "Output for B")->required();
  cmd->add_option("--curves", pa.curves,
                  "Given curves near both surfaces (polylines file) instead of the computed intersection: both "
                  "meshes' crossings are collected on them and both receive the same curve (shared vertices)");
  cmd->add_option("--curves-out", pa.curves_out, "Write the shared curves here, one polyline per line");
  cmd->add_option("--report", pa.report, "Write a JSON report: per-mesh sections as seam embed's, plus the curves");
  cmd->add_option("--vtk", pa.vtk,
                  "Also write both outputs and the curves into one ParaView file (.vtu, or legacy .vtk) with cell "
                  "fields tow, source_face, new and min_angle");
  cmd->add_option("--kernel", pa.kernel, "exact (Epeck, default), filtered (Epick) or float (double)")
      ->check(CLI::IsMember({"exact", "filtered", "float"}));
  add_number_option(cmd, "--snap-tol", pa.snap_tol,
                    "Tolerance of the quality stage: how far a changed face may lie from its input surface and a "
                    "vertex may move (merged into a curve point, say); 0: only edits that keep the surfaces (default: "
                    "auto, 0.1 x the smaller mean edge length)");
  add_number_option(cmd, "--min-angle", pa.min_angle,
                    "The angle bound (degrees, 0..60): faces next to the curves below it are refined (default: 20)");
  add_number_option(cmd, "--max-area", pa.max_area,
                    "Largest area of a new triangle: the re-triangulation and the quality stage refine to it; 0: no bound (default: 0)");
  add_bound_reach_option(cmd, pa.bound_reach);
  cmd->add_flag_callback(
      "--no-improve,--no-remesh", [&pa] { pa.options.improve = false; },
      "Keep the curves as embedded, without the quality stage");
  return {cmd, [args] { return run_pair(*args); }};
}

}  // namespace seam_cli
