// seam::embed: embed boundary curves exactly into one triangle surface mesh.
//
// The pipeline follows the report "Embedding a boundary curve into tow surface meshes":
//   1. snap        mesh vertices within `snap_tol` of a curve node move onto that node (k-d tree)
//   2. locate      each curve node is projected onto the mesh (AABB tree, exact projection)
//   3. cross       the curve is followed from face to face; where it crosses a mesh edge a
//                  crossing point is constructed on that edge
//   4. coarsen     curve nodes between two crossings are dropped (optionally kept within
//                  `curve_tol`); crossings, snapped vertices and end points are kept
//   5. retriangulate each face touched by the curve is re-triangulated in its own plane with a
//                  constrained Delaunay triangulation (split edges + curve segments as
//                  constraints) and refined to `min_angle_deg` / `max_area` without putting any
//                  new point on an edge or on the curve
//   6. splice      the patches replace the faces; crossing points are shared by both faces of
//                  their edge
//
// What is exact:
//   Exact (Epeck):   crossing points lie exactly on their mesh edges; every new vertex lies
//                    exactly in the plane of the input face it came from; with snap_tol = 0 the
//                    output surface is the input surface (each input face's vector area equals
//                    the sum over its patch).
//   Filtered (Epick): every decision (orientation, side of plane) is exact on the rounded
//                    coordinates; constructed points are rounded to double.
//   Float:           nothing is exact; inconsistent decisions are detected and reported as
//                    seam::InternalError, never as a broken mesh.
//
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <seam/check.h>
#include <seam/errors.h>
#include <seam/improve.h>
#include <seam/kernels.h>
#include <seam/types.h>

#include <cstddef>
#include <map>
#include <string>
#include <vector>

namespace seam {

/// Options of seam::embed. Lengths are in mesh units; a negative value means "automatic",
/// computed from the mean edge length L of the input mesh as documented per field.
struct EmbedOptions {
  /// Mesh vertices closer than this to a curve node move onto it. 0 disables snapping.
  /// Automatic: 0.1 L.
  double snap_tol = -1.0;
  /// A curve node farther than this from the surface is an input error. Automatic: 1.0 L.
  double max_distance = -1.0;
  /// Keep a curve node between two crossings when dropping it would move the embedded curve by
  /// more than this (Douglas-Peucker within each face). 0: drop them all, as the report does.
  double curve_tol = 0.0;
  /// Minimum angle (degrees) Delaunay refinement aims for in the re-triangulated faces. 0: no
  /// refinement. Angles the constraints themselves force (a curve meeting an edge at a grazing
  /// angle) cannot be improved without moving the curve; they are reported, not hidden.
  double min_angle_deg = 20.0;
  /// Largest area of a new triangle; 0: no bound.
  double max_area = 0.0;
  /// Cap on Steiner points inserted per re-triangulated face (bounds the work on hostile input).
  std::size_t max_steiner_per_face = 256;
  /// Keep every curve node (no coarsening between crossings), at its own coordinates. seam::pair
  /// sets it: every point of a computed intersection curve lies on the mesh and is a crossing
  /// point of one of the two meshes.
  bool keep_all_nodes = false;
};

/// Counts and measurements of one run; the keys of the CLI's JSON report.
struct EmbedStats {
  std::string kernel;
  std::size_t input_vertices = 0, input_faces = 0;
  std::size_t output_vertices = 0, output_faces = 0;
  double mean_edge_length = 0, snap_tol = 0, max_distance = 0;
  std::size_t vertices_snapped = 0;   ///< mesh vertices moved onto a curve node
  std::size_t snaps_refused = 0;      ///< moves refused because a face would flip or flatten
  double max_snap_move = 0;           ///< largest distance a vertex moved
  std::size_t curves = 0;
  std::size_t curve_nodes_in = 0;     ///< input curve nodes (closing repeats not counted)
  std::size_t curve_nodes_out = 0;    ///< vertices of the embedded curves
  std::size_t crossing_points = 0;    ///< new vertices on input edges (where the curve crosses)
  std::size_t curve_vertices_at_mesh_vertices = 0;  ///< curve passes through an input vertex
  std::size_t faces_crossed = 0;      ///< input faces re-triangulated
  std::size_t faces_added = 0;        ///< new faces (patch triangles)
  std::size_t steiner_points = 0;     ///< points inserted by Delaunay refinement
  std::size_t faces_refinement_fallback = 0;  ///< faces whose refinement was undone (kept the CDT)
  double min_angle_deg_new = 0;       ///< smallest angle among new faces
  double min_angle_deg_input = 0;     ///< smallest angle among the input faces that were replaced
  std::size_t new_faces_below_10 = 0, new_faces_below_20 = 0;
  /// new faces below 10 degrees whose source face's own smallest angle is larger (not forced)
  std::size_t new_faces_below_10_unforced = 0;
  /// The largest area of a new face, and with max_area every new face larger than it: faces the
  /// refinement could not bring below it (ImproveStats::above_max_area_after counts those), and
  /// faces made where the quality stage's band grew beyond the faces the curve crosses or
  /// touches, which are graded to the input's size (held to the angle bound only).
  double largest_new_area = 0;
  std::size_t new_faces_above_max_area = 0;
  double max_curve_deviation = 0;     ///< largest distance from an input curve node to the embedded curve
  std::map<std::string, double> stage_seconds;  ///< snap, locate, cross, coarsen, retriangulate, splice
};

/// Result of seam::embed. The mesh is modified in place.
template <class K> struct EmbedResult {
  /// The embedded, coarsened curves (closed ones repeat their first point at the end). Every
  /// point is a vertex of the output mesh and every segment an edge of it.
  std::vector<Polyline<K>> curves;
  /// For each embedded curve, its vertices as mesh vertex indices.
  std::vector<std::vector<typename Mesh<K>::Vertex_index>> curve_vertices;
  EmbedStats stats;
};

/// Embeds `curves` into `mesh`.
/// \pre `mesh` is a valid triangle mesh (seam::validate_triangle_mesh); every curve has at
///      least two points.
/// After the call, `mesh` has the face properties source_face_property (index of the input
/// face each face came from) and new_face_property; it has no garbage; input vertex i keeps
/// index i (snapped vertices have new coordinates).
/// Throws InvalidInput (a curve node farther than max_distance, bad options) or InternalError.
template <class K>
EmbedResult<K> embed(Mesh<K>& mesh, const std::vector<Polyline<K>>& curves,
                     const EmbedOptions& options = {});

/// Options of `seam embed` as a whole (seam::embed_checked).
struct EmbedRunOptions {
  /// The embedding's options; snap_tol is also the quality stage's tolerance (how far a changed
  /// face may lie from the input surface) and min_angle_deg its bound.
  EmbedOptions embed;
  /// Run the quality stage (seam/improve.h) on the faces around the curves, to min_angle_deg and
  /// max_area. Not run when snap_tol is 0: keeping the surface exactly it cannot flip across the
  /// creases of a faceted curved surface, and made more thin faces than the re-triangulation
  /// leaves.
  bool improve = true;
  /// The quality stage's other options (its tolerance and bound come from `embed`).
  ImproveOptions quality;
  /// Check the output as it will be written (seam::check_embedding on the coordinates rounded to
  /// doubles, at verify_tolerance). Off only for measurements.
  bool verify_output = true;
};

template <class K> struct EmbedRunResult : EmbedResult<K> {
  bool improved = false;  ///< the quality stage's edits are in the output
  ImproveStats improve;   ///< what the quality stage did (also when its edits were not kept)
  bool verified = false;  ///< the output as written passed seam::check_embedding
  /// The tolerance of that check: snap_tol (snapped vertices and the quality stage's faces stay
  /// within it of the input surface) plus 1e-9 of the mesh's diagonal (rounding).
  double verify_tolerance = 0;
  EmbedCheckReport check;  ///< the check's figures
  std::string note;        ///< what was tried before the output given, if anything
};

/// `seam embed` as a whole: seam::embed, then the quality stage on the band around the curves
/// (the input surface is its reference; curve segments may be split at their middle, and curve
/// points closer than feature_size merged along them), then the output checked as it will be
/// written. If the improved output fails the check, the embedded one without the quality stage is
/// checked instead (the note says so). If that fails too, `mesh` is restored and InternalError
/// says what failed: a result is only ever given verified (with verify_output).
/// Throws InvalidInput as seam::embed.
template <class K>
EmbedRunResult<K> embed_checked(Mesh<K>& mesh, const std::vector<Polyline<K>>& curves,
                                const EmbedRunOptions& options = {});

/// Throws InvalidInput naming the first option out of range (lengths finite, curve_tol and
/// max_area >= 0, min_angle_deg in [0, 60]). embed() calls it; a CLI can call it before reading.
void validate_options(const EmbedOptions& options);

/// Mean edge length of a mesh (rounded), the unit of the automatic options.
template <class K> double mean_edge_length(const Mesh<K>& mesh);

}  // namespace seam
