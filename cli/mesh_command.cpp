// seam mesh: tows that touch but do not overlap, plus a matrix box, as one tetrahedral model.
// SPDX-License-Identifier: GPL-3.0-or-later
#include "common.h"

#include <seam/volume_mesh.h>

#include <iostream>
#include <memory>

namespace seam_cli {

namespace {

struct MeshArgs {
  std::vector<std::string> tows, outputs, box;
  std::string report;
  NumberText margin, radius_edge, max_volume, box_spacing, cut_snap;
  bool steiner_on_surfaces = false;
};

/// --box: six finite numbers, each minimum below its maximum.
seam::AxisBox parse_box(const std::vector<std::string>& text) {
  seam::AxisBox box;
  const auto range = NumberRange::between(-seam::SupportedCoordinates::max_magnitude,
                                          seam::SupportedCoordinates::max_magnitude, "a coordinate");
  for (int k = 0; k < 6; ++k) {
    const double x = number_option("--box", NumberText{text[static_cast<std::size_t>(k)], true}, range, 0);
    (k < 3 ? box.min : box.max)[k % 3] = x;
  }
  static const char* axis = "xyz";
  for (int k = 0; k < 3; ++k)
    if (!(box.min[k] < box.max[k]))
      throw seam::InvalidInput(std::string("--box: ") + axis[k] + "min " + text[static_cast<std::size_t>(k)] +
                               " must be below " + axis[k] + "max " + text[static_cast<std::size_t>(k + 3)]);
  return box;
}

nlohmann::json mesh_report(const MeshArgs& args, const seam::VolumeMeshOptions& o, const seam::VolumeMeshResult& r) {
  const auto& st = r.stats;
  nlohmann::json j;
  j["files"] = {{"tows", args.tows}, {"outputs", args.outputs}};
  j["options"] = {{"radius_edge", o.radius_edge}, {"max_volume", o.max_volume}, {"margin", o.margin},
                  {"box_face_spacing", o.box_face_spacing}, {"cut_snap", o.cut_snap},
                  {"steiner_on_surfaces", o.steiner_on_surfaces},
                  {"tetgen_switches", st.tetgen_switches}};
  j["box"] = {{"min", st.box.min}, {"max", st.box.max}};
  j["input"] = {{"points", st.input_points}, {"triangles", st.input_triangles}, {"tow_triangles", st.tow_triangles},
                {"shared_triangles", st.shared_triangles}, {"box_triangles", st.box_triangles},
                {"clipped_tows", st.clipped_tows}, {"cut_snapped_vertices", st.cut_snapped_vertices},
                {"cut_snap_max_move", st.cut_snap_max_move}, {"cut_snap_undone", st.cut_snap_undone},
                {"box_face_spacing", st.box_face_spacing}, {"tetgen_aborts", st.tetgen_aborts}};
  j["output"] = {{"points", st.points}, {"tets", st.tets}, {"steiner_points", st.steiner_points}};
  j["regions"] = nlohmann::json::array();
  for (std::size_t i = 0; i < st.regions.size(); ++i) {
    const auto& rs = st.regions[i];
    j["regions"].push_back({{"id", i}, {"name", r.mesh.region_names[i]}, {"tets", rs.tets}, {"volume", rs.volume},
                            {"surface_volume", rs.surface_volume}, {"relative_error", rs.relative_error}});
  }
  j["contacts"] = nlohmann::json::array();
  for (const auto& c : r.contacts) j["contacts"].push_back({{"regions", {c.a, c.b}}, {"faces", c.faces.size()}});
  j["quality"] = {{"min_dihedral_deg", st.min_dihedral_deg}, {"max_dihedral_deg", st.max_dihedral_deg},
                  {"max_radius_edge", st.max_radius_edge}, {"tets_above_radius_edge", st.tets_above_radius_edge}};
  j["verified"] = true;
  j["seconds"] = st.stage_seconds;
  return j;
}

int run_mesh(MeshArgs& args) {
  // Every option before any work.
  seam::VolumeMeshOptions o;
  o.margin = number_option("--margin", args.margin, NumberRange::non_negative(), o.margin);
  o.radius_edge = number_option("--radius-edge", args.radius_edge, NumberRange::between(0, 100, "0: no quality bound; else >= 1.2"),
                                o.radius_edge);
  if (o.radius_edge != 0 && o.radius_edge < 1.2)
    throw seam::InvalidInput("--radius-edge " + args.radius_edge.text + ": out of range (0, or from 1.2 to 100: TetGen does not terminate below about 1.1)");
  o.max_volume = number_option("--max-volume", args.max_volume, NumberRange::non_negative(), o.max_volume);
  o.box_face_spacing = number_option("--box-spacing", args.box_spacing, NumberRange::non_negative_or_auto(), 0.0, 0.0);
  if (args.box_spacing.given && args.box_spacing.text != "auto" && o.box_face_spacing == 0) o.box_face_spacing = -1;  // 0: no grid
  o.cut_snap = number_option("--cut-snap", args.cut_snap, NumberRange::between(0, 0.5, "a fraction from 0 to 0.5"), o.cut_snap);
  if (!args.box.empty()) o.box = parse_box(args.box);
  o.steiner_on_surfaces = args.steiner_on_surfaces;
  std::vector<std::string> formats;
  for (const auto& path : args.outputs) formats.push_back(seam::volume_mesh_format(path));
  std::vector<std::string> outputs = args.outputs;
  outputs.push_back(args.report);
  refuse_overwrite(args.tows, outputs);
  seam::OutputFiles files;
  const auto out = add_outputs(files, outputs);

  const auto t0 = Clock::now();
  std::vector<seam::TriangleSoup> tows;
  for (const auto& path : args.tows) tows.push_back(seam::read_triangle_mesh(path));
  const double read_seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  seam::VolumeMeshResult result = seam::volume_mesh(tows, args.tows, o);  // messages name the files
  for (std::size_t i = 0; i < args.tows.size(); ++i) result.mesh.region_names[i + 1] = fs::path(args.tows[i]).stem().string();
  auto& st = result.stats;
  st.stage_seconds["read"] = read_seconds;

  const auto t1 = Clock::now();
  for (std::size_t i = 0; i < args.outputs.size(); ++i)
    files.write(out[i], [&](std::ostream& os) { seam::write_volume_mesh(result.mesh, result.contacts, os, formats[i]); });
  st.stage_seconds["write"] = std::chrono::duration<double>(Clock::now() - t1).count();
  if (out.back() != no_output) files.write(out.back(), [&](std::ostream& os) { write_json(mesh_report(args, o, result), os); });
  files.commit();

  std::cout << "seam mesh: " << st.tets << " tets, " << st.points << " points (" << st.steiner_points
            << " added inside); " << tows.size() << " tows + matrix";
  if (st.clipped_tows > 0)
    std::cout << " (" << st.clipped_tows << " tow(s) cut by the box, " << st.cut_snapped_vertices
              << " vertices moved onto its planes first, by at most " << st.cut_snap_max_move << ")";
  std::cout << ", region volumes equal their surfaces' (exact sums), "
            << st.shared_triangles << " shared faces in " << result.contacts.size() << " contact patch(es); min dihedral "
            << st.min_dihedral_deg << " deg, max radius-edge " << st.max_radius_edge;
  if (st.tets_above_radius_edge > 0) std::cout << " (" << st.tets_above_radius_edge << " tets above " << o.radius_edge << ")";
  if (!st.tetgen_aborts.empty())
    std::cout << "; TetGen stopped on its own assertion " << st.tetgen_aborts.size()
              << " time(s), box grid spacing made finer to " << st.box_face_spacing;
  std::cout << "; verified\n";
  return 0;
}

}  // namespace

Command add_mesh_command(CLI::App& app) {
  auto args = std::make_shared<MeshArgs>();
  MeshArgs& ma = *args;
  auto* cmd = app.add_subcommand(
      "mesh",
      "Mesh tows that touch but do not overlap (the output of seam resolve) and the matrix box around them into one "
      "tetrahedral model with a region per tow and one for the matrix, without changing the tow surfaces (TetGen -Y), "
      "verified, and write it for ParaView (.vtu), Abaqus (.inp) or Gmsh (.msh 4.1).");
  cmd->add_option("TOWS", ma.tows, "Closed tow surfaces (.off, .obj, .ply, .stl); shared faces must be bit-identical")
      ->required();
  cmd->add_option("-o,--out", ma.outputs, "Output, format by extension: .vtu, .inp or .msh (repeat for several)")
      ->required();
  cmd->add_option("--box", ma.box, "Matrix box: xmin ymin zmin xmax ymax zmax (default: the tows' bounding box); tows crossing it are cut by it "
                  "(a periodic unit cell)")
      ->expected(6)
      ->allow_extra_args(false);
  add_number_option(cmd, "--margin", ma.margin, "Grow the default box by this length on every side (default 0)");
  add_number_option(cmd, "--radius-edge", ma.radius_edge,
                    "TetGen's radius-edge bound (-q), 0 for none, else 1.2 to 100 (default 2)");
  add_number_option(cmd, "--max-volume", ma.max_volume, "Largest tet volume (-a); 0: no bound (default)");
  add_number_option(cmd, "--box-spacing", ma.box_spacing,
                    "Spacing of the points put on the box faces; 0: none (default: auto, the tows' mean edge length or 1/20 of the box's longest side, the larger)");
  add_number_option(cmd, "--cut-snap", ma.cut_snap,
                    "Where --box cuts tows: vertices closer than this fraction of the mean edge length to a box plane "
                    "move onto it first, so that no cut leaves a sliver; 0: none (default 0.1)");
  cmd->add_flag("--steiner-on-surfaces", ma.steiner_on_surfaces,
                "Let TetGen split the tow surfaces (no -Y): better tets, but the surfaces are no longer seam's");
  cmd->add_option("--report", ma.report, "Write a JSON report (regions, volumes, quality, seconds per stage)");
  return {cmd, [args] { return run_mesh(*args); }};
}

}  // namespace seam_cli
