// seam: the command-line tool.
//
// Exit codes: 0 success; 2 bad input or usage (one line on stderr: "seam: FILE: problem");
// 3 internal failure ("seam: internal error: ..."). Outputs are written to a temporary file and
// renamed, and a failed run removes the outputs it already wrote, so it leaves no output; an
// output path equal to an input or to another output is refused.
//
// SPDX-License-Identifier: GPL-3.0-or-later
#include <seam/embed.h>
#include <seam/io.h>

#include <CGAL/exceptions.h>
#include <CLI/CLI.hpp>
#include <nlohmann/json.hpp>

#include <chrono>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

struct EmbedArgs {
  std::string mesh, curves, out, curves_out, report, kernel = "exact";
  seam::EmbedOptions options;
};

seam::KernelKind parse_kernel(const std::string& k) {
  if (k == "filtered") return seam::KernelKind::filtered;
  if (k == "float") return seam::KernelKind::float_;
  return seam::KernelKind::exact;
}

/// Whether two paths name the same file: the same existing file, or the same normalised absolute
/// path (an error computing either, e.g. a permission problem, is not a match).
bool same_path(const std::string& a, const std::string& b) {
  std::error_code ec;
  if (fs::exists(a, ec) && fs::exists(b, ec) && fs::equivalent(a, b, ec)) return true;
  // weakly_canonical leaves a relative path none of whose prefixes exists relative: make it absolute.
  const auto normal = [](const std::string& p, std::error_code& e) {
    const fs::path abs = fs::absolute(p, e);
    return e ? fs::path() : fs::weakly_canonical(abs, e);
  };
  std::error_code ea, eb;
  const fs::path ca = normal(a, ea), cb = normal(b, eb);
  return !ea && !eb && ca == cb;
}

/// Refuses an output path that names one of the inputs (never overwrite an input), or another
/// output (one would silently replace the other).
void refuse_overwrite(const std::vector<std::string>& inputs, const std::vector<std::string>& outputs) {
  for (std::size_t i = 0; i < outputs.size(); ++i) {
    const auto& out = outputs[i];
    if (out.empty()) continue;
    for (const auto& in : inputs)
      if (same_path(in, out))
        throw seam::InvalidInput(out + ": output path is the input " + in + " (refusing to overwrite an input)");
    for (std::size_t j = 0; j < i; ++j)
      if (!outputs[j].empty() && same_path(outputs[j], out))
        throw seam::InvalidInput(out + ": the same path is given for two outputs (" + outputs[j] + ")");
  }
}


nlohmann::json stats_json(const seam::EmbedStats& s) {
  nlohmann::json j;
  j["kernel"] = s.kernel;
  j["input"] = {{"vertices", s.input_vertices}, {"faces", s.input_faces}, {"mean_edge_length", s.mean_edge_length}};
  j["output"] = {{"vertices", s.output_vertices}, {"faces", s.output_faces}};
  j["options"] = {{"snap_tol", s.snap_tol}, {"max_distance", s.max_distance}};
  j["snap"] = {{"vertices_snapped", s.vertices_snapped}, {"snaps_refused", s.snaps_refused},
               {"max_move", s.max_snap_move}};
  j["curve"] = {{"curves", s.curves},
                {"nodes_in", s.curve_nodes_in},
                {"nodes_out", s.curve_nodes_out},
                {"crossing_points", s.crossing_points},
                {"at_mesh_vertices", s.curve_vertices_at_mesh_vertices},
                {"max_deviation", s.max_curve_deviation}};
  j["faces"] = {{"crossed", s.faces_crossed},
                {"added", s.faces_added},
                {"steiner_points", s.steiner_points},
                {"refinement_undone", s.faces_refinement_fallback}};
  j["quality"] = {{"min_angle_deg", s.min_angle_deg_new},
                  {"input_min_angle_deg", s.min_angle_deg_input},
                  {"below_10", s.new_faces_below_10},
                  {"below_20", s.new_faces_below_20},
                  {"below_10_unforced", s.new_faces_below_10_unforced}};
  j["seconds"] = s.stage_seconds;
  return j;
}

int run_embed(const EmbedArgs& a) {
  seam::validate_options(a.options);  // before reading anything
  refuse_overwrite({a.mesh, a.curves}, {a.out, a.curves_out, a.report});
  const auto t0 = Clock::now();
  seam::TriangleSoup soup = seam::read_triangle_mesh(a.mesh);
  const auto polylines = seam::read_polylines(a.curves);
  const double read_seconds = std::chrono::duration<double>(Clock::now() - t0).count();

  return seam::with_kernel(parse_kernel(a.kernel), [&](auto kernel) {
    using K = decltype(kernel);
    auto mesh = seam::mesh_from_soup<K>(soup, a.mesh);
    const auto curves = seam::to_kernel<K>(polylines);
    seam::EmbedResult<K> result;
    try {
      result = seam::embed<K>(mesh, curves, a.options);
    } catch (const seam::InvalidInput& e) {
      throw seam::InvalidInput(a.curves + ": " + e.what());
    }
    const auto t1 = Clock::now();
    auto stats = result.stats;
    stats.stage_seconds["read"] = read_seconds;
    // A failed run leaves no output: if one output cannot be written, remove those already written.
    std::vector<std::string> written;
    try {
      seam::write_triangle_mesh(seam::soup_from_mesh<K>(mesh), a.out);
      written.push_back(a.out);
      if (!a.curves_out.empty()) {
        seam::write_polylines(seam::to_doubles<K>(result.curves), a.curves_out);
        written.push_back(a.curves_out);
      }
      stats.stage_seconds["write"] = std::chrono::duration<double>(Clock::now() - t1).count();
      if (!a.report.empty()) {
        nlohmann::json j = stats_json(stats);
        j["files"] = {{"mesh", a.mesh}, {"curves", a.curves}, {"out", a.out}};
        // File names need not be UTF-8: replace invalid bytes rather than throw.
        const std::string text = j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace);
        seam::write_file_atomically(a.report, [&](std::ostream& os) { os << text << "\n"; });
      }
    } catch (...) {
      std::error_code ignored;
      for (const auto& path : written) fs::remove(path, ignored);
      throw;
    }
    const auto& s = stats;
    std::cout << "seam embed: " << s.curves << " curve(s), " << s.curve_nodes_in << " nodes -> " << s.curve_nodes_out
              << " embedded vertices (" << s.crossing_points << " crossing points); " << s.vertices_snapped
              << " vertices snapped (" << s.snaps_refused << " refused); " << s.faces_crossed << " faces -> "
              << s.faces_added << " new faces, min angle " << s.min_angle_deg_new << " deg (" << s.new_faces_below_20
              << " below 20); wrote " << a.out << "\n";
    return 0;
  });
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"seam: embed boundary curves exactly into triangle tow surface meshes, so that two "
               "interpenetrating tows share the curve vertex for vertex and edge for edge."};
  app.require_subcommand(1);
  app.set_help_all_flag("--help-all", "Print help for every subcommand");

  EmbedArgs ea;
  auto* embed = app.add_subcommand(
      "embed",
      "Embed polylines into one triangle mesh: snap nearby vertices onto the curve, follow the curve across the "
      "faces, keep its crossing points, and re-triangulate every crossed face with the curve as a constraint.");
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
  embed->add_option("--snap-tol", ea.options.snap_tol,
                    "Move mesh vertices within this distance of a curve node onto it; 0 disables snapping "
                    "(default: 0.1 x mean edge length)");
  embed->add_option("--min-angle", ea.options.min_angle_deg,
                    "Minimum angle (degrees, 0..60) Delaunay refinement aims for in re-triangulated faces; 0 "
                    "disables refinement (default: 20)");
  embed->add_option("--max-area", ea.options.max_area, "Largest area of a new triangle; 0: no bound (default: 0)");
  embed->add_option("--max-distance", ea.options.max_distance,
                    "A curve node farther than this from the surface is an error (default: 1.0 x mean edge length)");
  embed->add_option("--curve-tol", ea.options.curve_tol,
                    "Keep a curve node between two crossings when dropping it would move the curve by more than "
                    "this; 0 drops them all, as the report does (default: 0)");

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : 2;
  }

  try {
    if (*embed) return run_embed(ea);
    return 2;
  } catch (const seam::InvalidInput& e) {
    std::cerr << "seam: " << e.what() << "\n";
    return 2;
  } catch (const seam::IOError& e) {
    std::cerr << "seam: " << e.what() << "\n";
    return 2;
  } catch (const seam::InternalError& e) {
    std::cerr << "seam: internal error: " << e.what() << "\n";
    return 3;
  } catch (const CGAL::Failure_exception& e) {
    std::cerr << "seam: internal error: CGAL: " << e.message() << " (" << e.expression() << ")\n";
    return 3;
  } catch (const std::bad_alloc&) {
    std::cerr << "seam: internal error: out of memory\n";
    return 3;
  } catch (const std::exception& e) {
    std::cerr << "seam: internal error: " << e.what() << "\n";
    return 3;
  }
}
