// seam::embed_checked: `seam embed` as a whole (embed, improve, verify as written). See seam/embed.h.
// SPDX-License-Identifier: GPL-3.0-or-later
#include <seam/embed.h>
#include <seam/internal/bbox_diagonal.h>
#include <seam/internal/improve_state.h>
#include <seam/internal/message.h>
#include <seam/internal/new_face_figures.h>
#include <seam/internal/verify_output.h>
#include <seam/quality.h>

#include <cmath>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace seam {

namespace {

/// The figures of the new faces after the quality stage (rounded measurements).
template <class K>
void measure(const Mesh<K>& mesh, const std::vector<double>& input_angles, double max_area, EmbedStats& st) {
  const auto q = new_face_quality<K>(mesh, &input_angles, max_area);
  internal::record_new_face_figures(q, st);
  st.output_vertices = mesh.number_of_vertices();
  st.output_faces = mesh.number_of_faces();
  st.faces_added = q.new_faces;
  st.new_faces_below_10_unforced = q.below_10_unforced;
}

}  // namespace

template <class K>
EmbedRunResult<K> embed_checked(Mesh<K>& mesh, const std::vector<Polyline<K>>& curves, const EmbedRunOptions& options) {
  // The input as embed sees it (garbage collected: embed keeps input face i as source face i).
  Mesh<K> input = mesh;
  if (input.has_garbage()) input.collect_garbage();
  EmbedRunResult<K> result;
  static_cast<EmbedResult<K>&>(result) = embed<K>(mesh, curves, options.embed);
  EmbedStats& st = result.stats;
  const std::vector<double> input_angles = internal::face_min_angles<K>(input);
  const double diagonal = internal::bbox_diagonal<K>(input);
  result.verify_tolerance = st.snap_tol + 1e-9 * diagonal;

  // At tolerance 0 the stage may only keep the surface: on a faceted curved surface it cannot flip
  // across a crease, and its splits there make more thin faces than the re-triangulation left
  // (bundled example, --snap-tol 0: 341 new faces below 20 degrees against 44). The
  // re-triangulation, Delaunay-refined in each face's plane, is then the output.
  const bool improve =
      options.improve && st.snap_tol > 0 && !result.curves.empty();
  std::optional<std::pair<Mesh<K>, EmbedResult<K>>> embedded;  // the fallback: as embedded
  // Back to the embedded mesh and its curves; what the quality stage did and the stage times stay.
  auto back_to_embedded = [&] {
    const auto seconds = st.stage_seconds;
    mesh = std::move(embedded->first);
    static_cast<EmbedResult<K>&>(result) = std::move(embedded->second);
    st.stage_seconds = seconds;
    result.improved = false;
    embedded.reset();
  };
  if (improve) {
    if (options.verify_output) embedded.emplace(mesh, static_cast<const EmbedResult<K>&>(result));
    std::vector<internal::ImproveMesh<K>> meshes{{&mesh, &input, &input_angles}};
    internal::SharedCurves<K> shared{result.curves, {result.curve_vertices}};
    ImproveOptions io = options.quality;
    io.tolerance = st.snap_tol;
    io.min_angle_deg = options.embed.min_angle_deg;
    io.max_area = options.embed.max_area;
    io.min_separation = min_vertex_separation * diagonal;
    const auto t = std::chrono::steady_clock::now();
    try {
      result.improve = internal::improve<K>(meshes, shared, io);
      result.improved = true;
      result.curves = shared.curves;
      result.curve_vertices = shared.vertices[0];
    } catch (const InternalError& e) {  // an edit it could not make: the embedded mesh, if kept
      if (!embedded) throw;
      result.note = std::string("the quality stage stopped (") + e.what() + ")";
    }
    st.stage_seconds["improve"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
    if (!result.improved) back_to_embedded();
  }
  measure<K>(mesh, input_angles, options.embed.max_area, st);
  st.curve_nodes_out = 0;
  for (const auto& c : result.curves) st.curve_nodes_out += c.size() - (is_closed(c) && c.size() > 1 ? 1 : 0);
  if (!options.verify_output) return result;

  const auto t = std::chrono::steady_clock::now();
  auto passes = [&]() {
    try {
      // (Without the given curves' distance figures: an exact copy of 10 million given points would
      // hold gigabytes; EmbedStats::max_curve_deviation measures that already.)
      result.check = internal::check_embedding_as_written<K>(input, mesh, result.curves, result.verify_tolerance);
    } catch (const InternalError& e) {
      result.check = EmbedCheckReport();
      result.check.problems.push_back(e.what());
    }
    return result.check.ok();
  };
  bool ok = passes();
  std::string problems;
  if (!ok && embedded) {
    problems = "improved: " + result.check.problems.front();
    back_to_embedded();
    measure<K>(mesh, input_angles, options.embed.max_area, st);
    ok = passes();
    if (ok)
      internal::append_note(result.note, "the improved output failed the check (" + problems +
                                             "): this is the embedded mesh without the quality stage");
  }
  st.stage_seconds["verify_output"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
  if (!ok) {
    problems += (problems.empty() ? "" : "; as embedded: ") + result.check.problems.front();
    mesh = std::move(input);
    throw InternalError("embed: the output fails the check of an embedding, so none is given (" + problems + ")");
  }
  result.verified = true;
  return result;
}

#define SEAM_INSTANTIATE(K) \
  template EmbedRunResult<K> embed_checked<K>(Mesh<K>&, const std::vector<Polyline<K>>&, const EmbedRunOptions&);
SEAM_INSTANTIATE(Exact)
SEAM_INSTANTIATE(Filtered)
SEAM_INSTANTIATE(Float)
#undef SEAM_INSTANTIATE

}  // namespace seam
