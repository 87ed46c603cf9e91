// seam CLI and Python bindings: the JSON reports. See report.h.
// SPDX-License-Identifier: GPL-3.0-or-later
#include "report.h"

#include <algorithm>
#include <cmath>

namespace seam_cli {

double default_check_tolerance(const seam::TriangleSoup& a, const seam::TriangleSoup& b) {
  double lo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
  for (const auto* soup : {&a, &b})
    for (const auto& t : soup->triangles)
      for (auto i : t)
        for (int k = 0; k < 3; ++k) {
          lo[k] = std::min(lo[k], soup->points[i][k]);
          hi[k] = std::max(hi[k], soup->points[i][k]);
        }
  double d2 = 0;
  for (int k = 0; k < 3; ++k) d2 += (hi[k] - lo[k]) * (hi[k] - lo[k]);
  return 1e-9 * std::sqrt(d2);
}

nlohmann::json improve_json(const seam::ImproveStats& s, bool done, const std::vector<std::string>& mesh_names) {
  nlohmann::json causes = nlohmann::json::object(), flat_reasons = nlohmann::json::object(),
                 faces = nlohmann::json::array();
  std::size_t curves_closer = 0;  // faces where two curves come closer than the feature size
  for (const auto& f : s.shortfalls) {
    const std::string cause = seam::shortfall_cause_name(f.cause), reason = seam::shortfall_cause_name(f.reason);
    causes[cause] = causes.value(cause, 0) + 1;
    if (f.cause == seam::ShortfallCause::flat_contact) flat_reasons[reason] = flat_reasons.value(reason, 0) + 1;
    faces.push_back({{"mesh", f.mesh < mesh_names.size() ? mesh_names[f.mesh] : std::to_string(f.mesh)},
                     {"face", f.face},
                     {"min_angle", f.min_angle_deg},
                     {"cause", cause},
                     {"reason", reason},
                     {"curve_gap", std::isfinite(f.curve_gap) ? nlohmann::json(f.curve_gap) : nlohmann::json()}});
    if (f.curve_gap < s.feature_size) ++curves_closer;
  }
  return {{"done", done},
          {"band_faces", s.band_faces},
          {"flips", s.flips},
          {"insertions", s.insertions},
          {"curve_splits", s.curve_splits},
          {"edge_splits", s.edge_splits},
          {"merges", s.merges},
          {"faces_absorbed", s.faces_absorbed},
          {"bound_reach", s.bound_reach},
          {"refused", {{"tolerance", s.refused_tolerance}, {"crossing", s.refused_crossing}, {"shape", s.refused_shape}, {"separation", s.refused_separation}}},
          {"below_bound_before", s.below_bound_before},
          {"below_bound_after", s.below_bound_after},
          {"min_angle_before", s.min_angle_deg_before},
          {"min_angle_after", s.min_angle_deg_after},
          {"above_max_area_after", s.above_max_area_after},
          {"shortfalls", causes},
          {"flat_contact_reasons", flat_reasons},
          {"shortfall_faces", faces},
          {"feature_size", s.feature_size},
          {"small_curves", s.small_curves},
          {"shortfalls_where_curves_closer_than_feature_size", curves_closer},
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
                  {"below_10_unforced", s.new_faces_below_10_unforced},
                  {"largest_area", s.largest_new_area},
                  {"above_max_area", s.new_faces_above_max_area}};
  j["seconds"] = s.stage_seconds;
  return j;
}

nlohmann::json pair_report_json(seam::KernelKind kernel, const seam::PairStats& st, const seam::EmbedStats& a,
                                 const seam::EmbedStats& b, const std::vector<CurveSummary>& curves) {
  nlohmann::json j;
  j["kernel"] = seam::kernel_name(kernel);
  j["a"] = stats_json(a);
  j["b"] = stats_json(b);
  nlohmann::json list = nlohmann::json::array();
  for (const auto& c : curves) list.push_back({{"vertices", c.vertices}, {"closed", c.closed}});
  j["curves"] = {{"count", st.curves}, {"vertices", st.curve_vertices}, {"closed", st.closed_curves}, {"list", list}};
  j["curves"]["open_ends"] = {{"junction", st.curve_ends.junction},
                              {"touching", st.curve_ends.touching},
                              {"border", st.curve_ends.border},
                              {"unexplained", st.curve_ends.unexplained}};
  j["tolerance"] = st.snap_tol;
  j["separate"] = {{"vertices_closed", st.vertices_closed},
                   {"curve_vertices_collapsed", st.curve_vertices_collapsed},
                   {"tiny_edges_collapsed", st.tiny_edges_collapsed}};
  j["touching_only"] = st.touching_only;
  j["given_curves"] = st.given_curves;
  j["max_curve_move"] = st.max_curve_move;
  j["improve"] = improve_json(st.improve, st.improved, {"A", "B"});
  j["contact"] = {{"patches", st.contact_patches},
                  {"shared_faces", st.shared_faces},
                  {"patches_left", st.contact_patches_left},
                  {"points_inserted", st.contact_points_inserted},
                  {"segments_split", st.contact_segments_split},
                  {"points_dropped", st.contact_points_dropped},
                  {"faces_below_bound", st.contact_faces_below_bound},
                  {"points", st.contact_points}};
  j["verified"] = st.verified;
  j["verify_tolerance"] = st.verify_tolerance;
  j["note"] = st.note;
  j["seconds"] = st.stage_seconds;
  return j;
}

nlohmann::json check_report_json(const seam::PairCheckReport& r, const std::string& kernel) {
  nlohmann::json j;
  j["ok"] = r.ok();
  j["problems"] = r.problems;
  j["kernel"] = kernel;
  j["tolerance"] = r.tolerance;
  j["curves"] = {{"curves", r.curves}, {"vertices", r.curve_vertices}, {"segments", r.curve_segments}};
  j["face_pairs"] = {{"candidates", r.candidate_face_pairs},
                     {"intersecting_on_curves", r.face_pairs_on_curve},
                     {"intersecting_off_curves", r.intersecting_face_pairs_off_curve}};
  j["shared_faces"] = r.shared_faces;
  j["vertex_separation"] = {{"required", r.min_separation}, {"closer_pairs", r.close_vertex_pairs}};
  j["coverage"] = {{"samples", r.intersection_samples},
                   {"uncovered", r.uncovered_samples},
                   {"max_uncovered_distance", r.max_uncovered_distance}};
  j["a2"] = {{"vertices", r.vertices_a2},       {"faces", r.faces_a2},        {"new_faces", r.new_faces_a},
             {"max_distance", r.max_distance_a}, {"min_angle_deg", r.min_angle_deg_a},
             {"new_below_10", r.below_10_a},     {"new_below_20", r.below_20_a}};
  j["b2"] = {{"vertices", r.vertices_b2},       {"faces", r.faces_b2},        {"new_faces", r.new_faces_b},
             {"max_distance", r.max_distance_b}, {"min_angle_deg", r.min_angle_deg_b},
             {"new_below_10", r.below_10_b},     {"new_below_20", r.below_20_b}};
  return j;
}

nlohmann::json textile_report_json(seam::KernelKind kernel, const seam::TextileStats& st,
                                   const std::vector<seam::TextilePairStats>& pairs,
                                   const std::vector<seam::EmbedStats>& tows, const std::vector<std::string>& names) {
  const auto name = [&](std::size_t i) { return i < names.size() ? names[i] : std::to_string(i); };
  nlohmann::json j;
  j["kernel"] = seam::kernel_name(kernel);
  j["threads"] = st.threads;
  j["candidate_pairs"] = st.candidate_pairs;
  j["intersecting_pairs"] = st.intersecting_pairs;
  j["touching_pairs"] = st.touching_pairs;
  j["triple_points"] = st.triple_points;
  j["flat_crossing_points"] = st.flat_crossing_points;
  j["vertices_closed"] = st.vertices_closed;
  j["max_close_move"] = st.max_close_move;
  j["improve"] = improve_json(st.improve, st.improved, names);
  j["improve_tolerance"] = st.improve_tolerance;
  j["verified"] = st.verified;
  j["verify_tolerance"] = st.verify_tolerance;
  if (!st.note.empty()) j["note"] = st.note;
  nlohmann::json tow_list = nlohmann::json::array();
  for (std::size_t i = 0; i < tows.size(); ++i) tow_list.push_back({{"name", name(i)}, {"embed", stats_json(tows[i])}});
  j["tows"] = tow_list;
  const auto quality = [](const seam::CurveFaceQuality& q) {
    return nlohmann::json{
        {"new_faces", q.faces}, {"min_angle_deg", q.min_angle_deg}, {"below_10", q.below_10}, {"below_20", q.below_20}};
  };
  nlohmann::json pair_list = nlohmann::json::array();
  for (const auto& s : pairs)
    pair_list.push_back({{"a", name(s.a)},
                         {"b", name(s.b)},
                         {"curves", s.curves},
                         {"closed_curves", s.closed_curves},
                         {"curve_vertices", s.curve_vertices},
                         {"touching_only", s.touching_only},
                         {"contact",
                          {{"patches", s.contact_patches},
                           {"shared_faces", s.shared_faces},
                           {"patches_left", s.contact_patches_left},
                           {"points", s.contact_points}}},
                         {"quality", {{"a", quality(s.quality_a)}, {"b", quality(s.quality_b)}}},
                         {"intersect_seconds", s.intersect_seconds},
                         {"copy_seconds", s.copy_seconds}});
  j["pairs"] = pair_list;
  j["seconds"] = st.stage_seconds;
  return j;
}

nlohmann::json resolve_report_json(seam::KernelKind kernel, const seam::ResolveStats& st,
                                   const seam::ResolvedCheckReport& check) {
  return {{"kernel", seam::kernel_name(kernel)},
          {"keeper", seam::keeper_name(st.keeper)},
          {"volume",
           {{"a_before", st.volume_a_before},
            {"b_before", st.volume_b_before},
            {"a_after", st.volume_a_after},
            {"b_after", st.volume_b_after},
            {"overlap", st.overlap_volume}}},
          {"contact_faces", st.contact_faces},
          {"shared_in_input",
           {{"edges", st.shared_edges}, {"faces", st.shared_faces}, {"faces_same_orientation", st.shared_faces_same_orientation}}},
          {"patches",
           {{"a", st.patches_a}, {"a_inside_b", st.patches_a_inside}, {"b", st.patches_b}, {"b_inside_a", st.patches_b_inside}}},
          {"loser_faces", {{"removed", st.faces_removed}, {"added", st.faces_added}}},
          {"verified", check.ok()},
          {"check",
           {{"shared_faces", check.shared_faces},
            {"shared_edges", check.shared_edges},
            {"pieces_a", check.pieces_a},
            {"pieces_b", check.pieces_b}}},
          {"note", st.note},
          {"seconds", st.stage_seconds}};
}

}  // namespace seam_cli
