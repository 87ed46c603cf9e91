// seam CLI: pieces shared by the subcommands.
// SPDX-License-Identifier: GPL-3.0-or-later
#include "common.h"

#include <ostream>

namespace seam_cli {

seam::KernelKind parse_kernel(const std::string& k) {
  if (k == "filtered") return seam::KernelKind::filtered;
  if (k == "float") return seam::KernelKind::float_;
  return seam::KernelKind::exact;
}

/// Same existing file, or the same normalised absolute path (an error computing either, e.g. a
/// permission problem, is not a match).
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


void write_all_or_nothing(const std::function<void(std::vector<std::string>& written)>& write) {
  std::vector<std::string> written;
  try {
    write(written);
  } catch (...) {
    std::error_code ignored;
    for (const auto& path : written) fs::remove(path, ignored);
    throw;
  }
}

nlohmann::json improve_json(const seam::ImproveStats& s, bool done, const std::vector<std::string>& mesh_names) {
  nlohmann::json causes = nlohmann::json::object(), faces = nlohmann::json::array();
  for (const auto& f : s.shortfalls) {
    const std::string cause = seam::shortfall_cause_name(f.cause);
    causes[cause] = causes.value(cause, 0) + 1;
    faces.push_back({{"mesh", f.mesh < mesh_names.size() ? mesh_names[f.mesh] : std::to_string(f.mesh)},
                     {"face", f.face},
                     {"min_angle", f.min_angle_deg},
                     {"cause", cause}});
  }
  return {{"done", done},
          {"band_faces", s.band_faces},
          {"flips", s.flips},
          {"insertions", s.insertions},
          {"curve_splits", s.curve_splits},
          {"edge_splits", s.edge_splits},
          {"merges", s.merges},
          {"faces_absorbed", s.faces_absorbed},
          {"refused", {{"tolerance", s.refused_tolerance}, {"crossing", s.refused_crossing}, {"shape", s.refused_shape}}},
          {"below_bound_before", s.below_bound_before},
          {"below_bound_after", s.below_bound_after},
          {"min_angle_before", s.min_angle_deg_before},
          {"min_angle_after", s.min_angle_deg_after},
          {"shortfalls", causes},
          {"shortfall_faces", faces},
          {"seconds", s.seconds}};
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

void write_json(const nlohmann::json& j, const std::string& path) {
  const std::string text = j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace);
  seam::write_file_atomically(path, [&](std::ostream& os) { os << text << "\n"; });
}

}  // namespace seam_cli
