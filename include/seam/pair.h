// seam::pair: make two interpenetrating tow meshes conforming along their intersection curves.
//
// Computed curves (the default): the intersection of the two surfaces, computed exactly under the
// exact kernel (CGAL::Polygon_mesh_processing::surface_intersection), chained into one polyline
// per connected curve (closed where both surfaces are closed), duplicate points merged, each
// closed curve starting at its lexicographically smallest point, each curve running along
// n_A x n_B (the normals of the faces of A and B that contain it, as the inputs orient them; the
// boundary of a flat contact, where these are parallel, runs from its smaller end, or neighbour
// of its first point), the curves sorted by first point: the same output, run after run,
// whatever order CGAL returns the pieces in. Every curve point lies on both
// surfaces, so embedding keeps all of them (they are the crossing points of one mesh or the
// other) and both meshes receive the identical curve. Each piece is classified from the faces of
// each mesh that contain it (exact tests): where the surfaces cross it is kept; where they only
// touch along an edge (an edge of one lying in a face of the other) it is kept too: the outputs
// meet along it, so it must be a curve of both; an isolated point of contact is a curve of one
// point, inserted into both meshes as a vertex (PairStats::touching_only when the inputs only
// touch, PairStats::contact_points); of a flat contact (coplanar
// faces overlapping) the boundary of the contact region is kept, and the ridges where it bends
// (where two flat contacts meet at an angle). Pieces are chained into closed curves through
// points where an even number of them meet (two curves touching); a curve ends only where an odd
// number meet (the corner of a flat contact, say).
//
// The pipeline, one stage after the other (src/pair.cpp):
//   1. intersect   the exact intersection curves (above);
//   2. embed       into both meshes at once (seam::embed, every curve point kept), and the isolated
//                  points of contact made vertices of both;
//   3. contacts    each flat contact becomes one common constrained Delaunay triangulation in both
//                  meshes (internal/flat_contacts.h): the same triangles there (shared faces,
//                  bit-identical), so that the merged outputs are a valid piecewise-linear complex;
//                  no later stage changes a shared face;
//   4. improve     the quality stage (seam/improve.h) on both meshes at once, within the snapping
//                  tolerance: Delaunay refinement of the band around the curves with a stated
//                  bound, every edit checked by one acceptance predicate; curve segments split in
//                  both meshes alike, short edges merged (a vertex into a curve point next to it:
//                  the report's step 1, done where it mends a face);
//   5. separate    edges shorter than min_vertex_separation of the pair's size collapse (TetGen
//                  merges points that close);
//   6. verify      the outputs, rounded to doubles as they are written, checked with
//                  seam::check_pair under the exact kernel at PairStats::verify_tolerance. If they
//                  fail, the meshes as they were before stage 4 are verified instead (the exact
//                  embedding, no quality stage); if those fail too, stages 1-5 run again on the
//                  inputs with features thinner than min_vertex_separation of the pair's size
//                  closed (a vertex of one mesh that close to the curves, not on them, moves onto
//                  them, and the curves are computed again: a crossing that thin can be neither
//                  written in doubles nor meshed by TetGen), verified with and without stage 4:
//                  first, where the improved outputs fail on that alone, only the vertices next
//                  to the pairs of vertices they left closer than the separation (check 5),
//                  again while that finds new pairs (at most 3 rounds: each adds points or
//                  ends); then every such vertex.
//                  If every one fails, the inputs are restored and InternalError says what each
//                  failed. A result is therefore always one that `seam check` accepts.
//
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <seam/embed.h>
#include <seam/improve.h>

#include <string>
#include <vector>

namespace seam {

struct PairOptions {
  /// Options of the embedding into each mesh: min_angle_deg (also the quality stage's bound),
  /// max_area, max_steiner_per_face. snap_tol is the quality stage's tolerance (how far a changed
  /// face may lie from its input surface): < 0 automatic, 0.1 x the smaller of the two mean edge
  /// lengths; 0: only edits that keep the surfaces. curve_tol and max_distance are not used with
  /// computed curves.
  EmbedOptions embed;
  /// Run the quality stage (seam/improve.h), to EmbedOptions::min_angle_deg and max_area.
  bool improve = true;
  /// The quality stage's other options (its tolerance and angle bound come from `embed`).
  ImproveOptions quality;
  /// Check the outputs as they will be written (stage 6). Off only for measurements.
  bool verify_output = true;
};

/// Where the open curves end, and why (one count per end of an open curve). Two closed surfaces
/// that cross transversally meet in closed curves; a curve ends only where the intersection is not
/// such a curve:
///   - junction: an odd number (3 or more) of curve pieces meet there, such as where a crossing
///     reaches the border of a flat contact (its boundary comes in and goes out);
///   - touching: the last piece is where the surfaces only touch (an edge of one lying in a face
///     of the other, both on one side of each other), and a touching contact can stop anywhere;
///   - border: the end lies on a border edge of an open input;
///   - unexplained: none of these; part of the intersection would be missing (seam check's
///     curve-cover test then fails too).
/// Decided on the intersection curves as computed (exact tests under the exact kernel).
struct CurveEnds {
  std::size_t junction = 0, touching = 0, border = 0, unexplained = 0;
};

struct PairStats {
  std::size_t curves = 0, curve_vertices = 0, closed_curves = 0;
  CurveEnds curve_ends;  ///< why each open curve ends where it does
  double snap_tol = 0;  ///< the quality stage's tolerance (pass at least this to `seam check --tol`)
  /// Stage 6's last fallback: vertices moved onto the curves, closer to them than
  /// min_vertex_separation, and the largest move (verify_tolerance includes it).
  std::size_t vertices_closed = 0;
  double max_close_move = 0;
  /// Stage 5 (and edges below 1e-9 of the pair's size after the embedding): curve vertices
  /// removed from both meshes, and vertices off the curves merged over such an edge.
  std::size_t curve_vertices_collapsed = 0, tiny_edges_collapsed = 0;
  /// True when the input surfaces touch (at points) without crossing; the points of contact are
  /// then the only curves.
  bool touching_only = false;
  bool improved = false;  ///< the quality stage ran and its result is the one given
  ImproveStats improve;   ///< what it did, and the faces below its bound with their causes
  /// Flat contacts (see internal/flat_contacts.h): planar patches where both surfaces coincide,
  /// made one common triangulation; its faces (each a face of both outputs); patches that could
  /// not be (their borders differ in the two meshes: seam check then fails).
  std::size_t contact_patches = 0, shared_faces = 0, contact_patches_left = 0;
  /// The refinement of the flat contacts (when the quality stage runs): points inserted inside
  /// them, curve segments split (in both meshes, with the faces beyond), vertices of one mesh only
  /// dropped from inside them (both meshes), their faces left below the bound (in the projection).
  std::size_t contact_points_inserted = 0, contact_segments_split = 0, contact_points_dropped = 0,
              contact_faces_below_bound = 0;
  /// Isolated points of contact made a vertex of both (curves of one point).
  std::size_t contact_points = 0;
  bool given_curves = false;      ///< the curves were given (seam::pair_with_curves)
  /// Given curves: the largest move of a vertex onto (or along with) the given curves.
  double max_curve_move = 0;
  /// The outputs passed seam::check_pair as written (PairOptions::verify_output), at this tolerance.
  bool verified = false;
  double verify_tolerance = 0;
  std::string note;  ///< a sentence for the report (e.g. "the meshes do not intersect")
  /// intersect, embed_a, embed_b, flat_contacts, improve, separate, verify_output (and read, write)
  std::map<std::string, double> stage_seconds;
};

template <class K> struct PairResult {
  std::vector<Polyline<K>> curves;  ///< the shared curves (closed ones repeat their first point)
  EmbedResult<K> a, b;              ///< per-mesh results (curves identical in both)
  PairStats stats;
};

/// The intersection curves of two triangle meshes, chained (see the header comment).
/// `touching_points`, when given, receives the number of isolated points where the surfaces only
/// touch (they are not curves).
template <class K>
std::vector<Polyline<K>> intersection_curves(const Mesh<K>& a, const Mesh<K>& b,
                                             std::size_t* touching_points = nullptr);

/// Makes `a` and `b` conforming along their intersection curves (modified in place).
/// \pre both are valid closed or open triangle meshes without self-intersections.
template <class K> PairResult<K> pair(Mesh<K>& a, Mesh<K>& b, const PairOptions& options = {});

/// Stage 4 of seam::pair on meshes whose curves are embedded (result.curves, with their vertices
/// in result.a and result.b): the quality stage at result.stats.snap_tol, the meshes as they are
/// taken as the input surfaces. `input_a` and `input_b` (may be null), the meshes the faces'
/// source_face_property refers to: a face is held to the bound or to its input face's smallest
/// angle where that is less. Updates the curves and result.stats.improve.
template <class K>
void improve_pair(Mesh<K>& a, Mesh<K>& b, PairResult<K>& result, const PairOptions& options,
                  const Mesh<K>* input_a = nullptr, const Mesh<K>* input_b = nullptr);

/// Given curves (from another tool, lying only near both surfaces, such as the intersection of
/// the smooth tow surfaces, 0.001-0.01 off the facets; src/pair_given.cpp). First method: the
/// meshes' exact intersection is embedded by seam::pair (snapping and remeshing as the options
/// say), then every curve vertex moves, in both meshes alike, to the closest point of the given
/// curves (exactly on a given segment), and the vertices around it by a blend of those moves,
/// so that the faces move with the curve instead of folding. Both outputs share the moved curve
/// by construction, bit for bit. Tried with the options' snapping, then without it (or, asked for
/// none, with the default snapping). Second method, where the first fails (the meshes do not
/// intersect near the curves, say): both meshes are snapped onto the curve nodes, the curves are
/// followed on each, the crossing points of both collected in curve order and embedded into both,
/// and the curve vertices moved onto the given curves. Every result is verified as for seam::pair
/// (PairOptions::verify_output) at PairStats::verify_tolerance: the snapping tolerance plus the
/// largest move (PairStats::max_curve_move). Throws InvalidInput when a curve is farther than
/// options.embed.max_distance (default: the mesh's mean edge length) from a mesh, or so far that
/// moving a mesh onto it would fold a face; InternalError when no result passes.
template <class K>
PairResult<K> pair_with_curves(Mesh<K>& a, Mesh<K>& b, const std::vector<Polyline<K>>& curves,
                               const PairOptions& options = {});

}  // namespace seam
