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
// Flat contacts: after the embedding, the faces of both meshes in each planar contact patch are
// replaced by one common constrained Delaunay triangulation (internal/flat_contacts.h), so that
// the two outputs hold the same triangles there (shared faces, bit-identical) and the merged
// outputs are a valid piecewise-linear complex. No later step changes a shared face.
//
// Verification (PairOptions::verify_output): the outputs, rounded to doubles as they are
// written, are checked with seam::check_pair under the exact kernel at
// PairStats::verify_tolerance. If they fail, the pair is done again without snapping (still
// remeshed), then without snapping or remeshing, then snapped at the vertex separation of
// seam check (check 5) onto the curves' exact points, then onto those points rounded to
// doubles; if every run fails, the meshes are restored and InternalError says what each run
// failed. A result is therefore always one that `seam check` accepts.
//
// Snapping (report step 1), when snap_tol > 0: vertices of either mesh within snap_tol of a curve
// point move onto it (a move that would flip or flatten a face is refused), and the curves are
// computed again on the moved surfaces; crossings next to vertices become curves through vertices.
// Snapping is undone (PairStats::note says so) when it turns a crossing into a touching contact
// (a vertex a few units in the last place inside the other surface), when the curves of the
// snapped surfaces cannot be embedded, or when the snapped result fails seam check's tests
// (a moved vertex can make a surface meet itself): the run is then done again without snapping
// (first, when short curve segments were collapsed, with snapping but without the collapses).
// With snapping, the curves are then coarsened and both meshes remeshed next to them
// (PairOptions::remesh_near_curves).
//
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <seam/embed.h>

#include <string>
#include <vector>

namespace seam {

struct PairOptions {
  /// Options of the embedding into each mesh. snap_tol < 0: automatic, 0.1 x the smaller of the
  /// two mean edge lengths; 0 disables snapping. curve_tol and max_distance are not used with
  /// computed curves.
  EmbedOptions embed;
  /// With snapping (on by default): after embedding, coarsen the shared curves to about the
  /// smaller mean edge length (chords within snap_tol of the curve) and remesh both meshes next to
  /// them (see internal/improve.h). Remeshed faces that stray farther than snap_tol from their
  /// input surface get their edges split, the new vertices on the input surface; then vertices
  /// inside the band are smoothed and edges between remeshed faces flipped where that raises the
  /// smallest angle (within the tolerance). Every attempt is
  /// checked with seam::check_pair's own tests on the faces that changed (valid, no
  /// self-intersection, meeting only along the curves) and against the inputs (no remeshed face
  /// farther than snap_tol from its input surface, sampled). Where it fails, all embedded curve
  /// points near the failing faces are kept, then, if it fails there again, the curve there is
  /// frozen (left as embedded); up to 12 attempts, then the remeshing is undone altogether
  /// (PairStats::note says so). Not done when EmbedOptions::max_area is set: the remeshing works
  /// to an edge length and would undo the area bound. With the steps on thin faces that follow (see pair.cpp), measured
  /// on 72 generated crossovers (resolutions 5-24): none of 43,358 new faces below 10 degrees and
  /// 0.20% below 20, instead of 17.0% and 40.8% without remeshing (README, stop 17).
  bool remesh_near_curves = true;
  /// With snapping: collapse curve segments shorter than the snapping tolerance in both meshes
  /// where that improves the angles (see internal/collapse.h). Edges below 1e-9 of the pair's
  /// size are collapsed even when this is off: written in doubles, their faces would be flat.
  bool collapse_short_segments = true;
  /// Check the outputs as they will be written (rounded to doubles) with seam::check_pair under
  /// the exact kernel, at PairStats::verify_tolerance. If they fail and vertices were snapped,
  /// the pair is done again without snapping and checked again; if that fails too, the meshes
  /// are restored and InternalError says what failed. So a result is always one `seam check`
  /// accepts. (Off only for measurements.)
  bool verify_output = true;
};

struct PairStats {
  std::size_t curves = 0, curve_vertices = 0, closed_curves = 0;
  std::size_t vertices_snapped_a = 0, vertices_snapped_b = 0, snaps_refused = 0;
  /// Edges split to give a curve point next to them a vertex (internal::snap_edges_to_points).
  std::size_t edges_snapped_a = 0, edges_snapped_b = 0;
  /// Curve vertices removed from both meshes by collapsing a short curve segment (shorter than
  /// the snapping tolerance; internal/collapse.h), and the short segments left.
  std::size_t curve_vertices_collapsed = 0, short_segments_left = 0;
  /// New vertices off the curves merged over an edge below 1e-9 of the pair's size (with snapping).
  std::size_t tiny_edges_collapsed = 0;
  double snap_tol = 0;  ///< the snapping tolerance in effect (pass at least this to `seam check --tol`)
  /// True when the input surfaces touch (at points) without crossing; the points of contact are
  /// then the only curves (false when it is snapping that turned a slight crossing into them).
  bool touching_only = false;
  bool remeshed = false;  ///< the curves were coarsened and the meshes remeshed next to them
  /// Remeshing: attempts made, and curve points left as embedded (frozen) because remeshing next
  /// to them failed twice.
  std::size_t remesh_attempts = 0, curve_vertices_frozen = 0;
  /// Remeshing: the largest distance of a remeshed face from its input surface (sampled at
  /// corners, edge midpoints and centroid; at most snap_tol).
  double remesh_max_deviation = 0;
  /// Flat contacts (see internal/flat_contacts.h): planar patches where both surfaces coincide,
  /// made one common triangulation; its faces (each a face of both outputs); patches that could
  /// not be (their borders differ in the two meshes: seam check then fails).
  std::size_t contact_patches = 0, shared_faces = 0, contact_patches_left = 0;
  /// Isolated points of contact made a vertex of both (curves of one point).
  std::size_t contact_points = 0;
  bool given_curves = false;      ///< the curves were given (seam::pair_with_curves)
  /// Given curves: the largest move of a vertex onto (or along with) the given curves.
  double max_curve_move = 0;
  /// The outputs passed seam::check_pair as written (PairOptions::verify_output), at this tolerance.
  bool verified = false;
  double verify_tolerance = 0;
  std::string note;  ///< a sentence for the report (e.g. "the meshes do not intersect")
  std::map<std::string, double> stage_seconds;  ///< snap, intersect (or trace, merge), embed_a, embed_b, move
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
