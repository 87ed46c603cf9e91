// seam embed: embed polylines into one triangle mesh.
// SPDX-License-Identifier: GPL-3.0-or-later
#include "common.h"

#include <iostream>
#include <memory>

namespace seam_cli {

namespace {

struct EmbedArgs {
  std::string mesh, curves, out, curves_out, report, kernel = "exact";
  NumberText snap_tol, min_angle, max_area, max_distance, curve_tol, bound_reach;
  seam::EmbedRunOptions run;
};

int run_embed(EmbedArgs& a) {
  // Every option before any work.
  seam::EmbedOptions& o = a.run.embed;
  o.snap_tol = number_option("--snap-tol", a.snap_tol, NumberRange::non_negative_or_auto(), o.snap_tol);
  o.min_angle_deg = number_option("--min-angle", a.min_angle, NumberRange::between(0, 60, "degrees"), o.min_angle_deg);
  o.max_area = number_option("--max-area", a.max_area, NumberRange::non_negative(), o.max_area);
  o.max_distance = number_option("--max-distance", a.max_distance, NumberRange::non_negative_or_auto(), o.max_distance);
  o.curve_tol = number_option("--curve-tol", a.curve_tol, NumberRange::non_negative(), o.curve_tol);
  read_bound_reach_option(a.bound_reach, a.run.quality.bound_reach);
  seam::validate_options(o);
  // Every output path before any work: its format, no input overwritten, and its temporary file
  // created (a missing folder, a directory, a FIFO are found now).
  refuse_overwrite({a.mesh, a.curves}, {a.out, a.curves_out, a.report});
  seam::check_mesh_extension(a.out);
  seam::OutputFiles files;
  const auto out = add_outputs(files, {a.out, a.curves_out, a.report});

  const auto t0 = Clock::now();
  seam::TriangleSoup soup = seam::read_triangle_mesh(a.mesh);
  seam::check_no_self_intersection(soup, a.mesh);
  auto polylines = seam::read_polylines(a.curves);
  const double read_seconds = std::chrono::duration<double>(Clock::now() - t0).count();

  return seam::with_kernel(parse_kernel(a.kernel), [&](auto kernel) {
    using K = decltype(kernel);
    auto mesh = seam::mesh_from_soup<K>(soup, a.mesh);
    const auto curves = seam::to_kernel<K>(polylines);
    // The doubles are not needed any more: a curve of 10 million points holds 240 MB of them.
    std::vector<std::vector<seam::Point3d>>().swap(polylines);
    seam::TriangleSoup().points.swap(soup.points);
    seam::EmbedRunResult<K> result;
    try {
      result = seam::embed_checked<K>(mesh, curves, a.run);
    } catch (const seam::InvalidInput& e) {
      throw seam::InvalidInput(a.curves + ": " + e.what());
    }
    const auto t1 = Clock::now();
    auto stats = result.stats;
    stats.stage_seconds["read"] = read_seconds;
    const seam::TriangleSoup out_soup = seam::soup_from_mesh<K>(mesh);
    files.write(out[0], [&](std::ostream& os) { seam::write_triangle_mesh(out_soup, os, fs::path(a.out).extension().string()); });
    if (out[1] != no_output)
      files.write(out[1], [&](std::ostream& os) { seam::write_polylines(seam::to_doubles<K>(result.curves), os); });
    stats.stage_seconds["write"] = std::chrono::duration<double>(Clock::now() - t1).count();
    if (out[2] != no_output) {
      nlohmann::json j = stats_json(stats);
      j["improve"] = improve_json(result.improve, result.improved, {"mesh"});
      j["verify"] = {{"verified", result.verified},
                     {"tolerance", result.verify_tolerance},
                     {"max_distance", result.check.max_distance},
                     {"close_vertex_pairs_in_input", result.check.close_vertex_pairs_in_input}};
      j["note"] = result.note;
      j["files"] = {{"mesh", a.mesh}, {"curves", a.curves}, {"out", a.out}};
      files.write(out[2], [&](std::ostream& os) { write_json(j, os); });
    }
    files.commit();
    const auto& s = stats;
    std::cout << "seam embed: " << s.curves << " curve(s), " << s.curve_nodes_in << " nodes -> " << s.curve_nodes_out
              << " embedded vertices (" << s.crossing_points << " crossing points); " << s.vertices_snapped
              << " vertices snapped (" << s.snaps_refused << " refused); " << s.faces_crossed << " faces -> "
              << s.faces_added << " new faces, min angle " << s.min_angle_deg_new << " deg (" << s.new_faces_below_20
              << " below 20, " << s.new_faces_below_10 << " below 10)";
    if (a.run.embed.max_area > 0)
      std::cout << "; largest new face " << s.largest_new_area << " (" << s.new_faces_above_max_area
                << " above --max-area)";
    if (result.improved)
      std::cout << "; quality stage (tolerance " << s.snap_tol << "): " << result.improve.below_bound_after
                << " of the band's faces below " << a.run.embed.min_angle_deg << " degrees";
    if (result.verified)
      std::cout << "; verified (seam check-embed --tol " << tolerance_text(result.verify_tolerance) << ")";
    if (!result.note.empty()) std::cout << "; " << result.note;
    std::cout << "; wrote " << a.out << "\n";
    return 0;
  });
}

}  // namespace

Command add_embed_command(CLI::App& app) {
  auto args = std::make_shared<EmbedArgs>();
  EmbedArgs& ea = *args;
  auto* embed = app.add_subcommand(
      "embed",
      "Embed polylines into one triangle mesh: snap nearby vertices onto the curve, follow the curve across the "
      "faces, keep its crossing points, re-triangulate every crossed face with the curve as a constraint, improve "
      "the faces around the curve (the quality stage), and check the output as written (as seam check-embed). "
      "Exit 0 only with a verified output; 3 (nothing written) when the check fails.");
  embed->add_option("MESH", ea.mesh, "Input triangle mesh (.off, .obj, .ply, .stl)")->required();
  embed->add_option("--curves", ea.curves,
                    "Curves file, one polyline per line: 'n x1 y1 z1 ... xn yn zn'; closed when the last point "
                    "equals the first")
      ->required();
  embed->add_option("-o,--out", ea.out, "Output mesh (format by extension; OFF with 17 significant digits)")
      ->required();
  embed->add_option("--curves-out", ea.curves_out, "Write the embedded (coarsened) curves here, same format");
  embed->add_option("--report", ea.report, "Write a JSON report (counts per stage, quality, timings) here");
  embed->add_option("--kernel", ea.kernel, "exact (Epeck, default), filtered (Epick) or float (double)")
      ->check(CLI::IsMember({"exact", "filtered", "float"}));
  add_number_option(embed, "--snap-tol", ea.snap_tol,
                    "Move mesh vertices within this distance of a curve node onto it, and let the quality stage "
                    "change faces within it of the input surface; 0 disables snapping (default: auto, 0.1 x mean "
                    "edge length)");
  add_number_option(embed, "--min-angle", ea.min_angle,
                    "The angle bound (degrees, 0..60): Delaunay refinement of the re-triangulated faces and the "
                    "quality stage aim for it (default: 20)");
  add_number_option(embed, "--max-area", ea.max_area, "Largest area of a new triangle: the re-triangulation and the quality stage refine to it; 0: no bound (default: 0)");
  add_bound_reach_option(embed, ea.bound_reach);
  add_number_option(embed, "--max-distance", ea.max_distance,
                    "A curve node farther than this from the surface is an error (default: auto, 1.0 x mean edge "
                    "length)");
  add_number_option(embed, "--curve-tol", ea.curve_tol,
                    "Keep a curve node between two crossings when dropping it would move the curve by more than "
                    "this; 0 drops them all, as the report does (default: 0)");

  embed->add_flag_callback(
      "--no-improve", [&ea] { ea.run.improve = false; },
      "Keep the faces as the re-triangulation made them, without the quality stage");
  return {embed, [args] { return run_embed(*args); }};
}

}  // namespace seam_cli
