// seam::textile: every interpenetration among N tows of a unit cell embedded at once, in parallel.
//
//   1. Candidates: CGAL::box_intersection_d on the tows' bounding boxes.
//   2. Pairs (concurrently): the intersection curves of each candidate pair, exactly as
//      seam::intersection_curves computes them for `seam pair` (touching runs kept as curves,
//      isolated touching points kept for 4a, flat contact reduced to its boundary, see 4b). A
//      candidate with no curve is no pair.
//   2c. Thin features (exact kernel): where a pair's curve point has a vertex or another curve
//      point closer than the pair's vertex separation (min_vertex_separation x the diagonal of
//      its two tows), the vertices of both tows next to it move onto the curve, as seam::pair's
//      stage 1 closes them, and the pairs of a moved tow are computed again.
//   3. Triple overlaps: where the curves of tow A with B and of A with C meet on A, the three tows
//      overlap in one place, and the meeting point lies exactly on the three surfaces. Under the
//      exact kernel it is made a vertex of all three tows (the face or edge holding it is cut;
//      the surfaces are unchanged) and the curves of their pairs are computed again: they then
//      all pass through that common vertex, where the embeddings meet. A point where two tows
//      touch (4a) inside a curve segment of one of them with a third is such a meeting too.
//      A meeting point that lies on no curve of B and C (nor is a point of contact of theirs),
//      as inside an area over which B and C coincide (a flat contact), becomes a vertex of A
//      only: no curve of B and C needs it there, B and C get it as a point of their curves with
//      A, and a vertex of B there would cut C's coplanar faces at new points.
//      Where A crosses such an area, its curves with B and with C run along the same segments
//      there (every point of either lies on the three surfaces). Under the exact kernel every end
//      of two such segments on their overlap becomes a vertex of A; computed again, both curves
//      then pass through all of them, and the overlap is a chain of segments common to both,
//      between vertices of A. (Where A crosses a planar contact, A's new edges from such a point
//      meet the common plane at that point only, so no other point joins either curve and one
//      round does it; where the contact bends inside a face of A, or A lies in its plane, more
//      rounds may follow.) Two such points closer than the vertex separation (edges of B and C
//      crossing A almost at one place) stop the run with InvalidInput naming the three tows, as
//      do three curves along one segment (the three tows coinciding over an area) and overlaps
//      left after the last round.
//      Under the rounded kernels a meeting, or an overlap, stops the run with InvalidInput naming
//      the three tows (no output is produced); curves of a rounded kernel that meet within
//      rounding can also go unseen and stop the embedding of the tow with an InternalError naming
//      it. Making the meeting points vertices is repeated while new ones appear, at most 4 rounds.
//   4. Tows (concurrently): each tow receives every curve that involves it in one seam::embed
//      call (curve points kept at their own coordinates, as in seam::pair), so that for every
//      pair both outputs share the pair's curves vertex for vertex and edge for edge.
//   4a. Points of contact: a pair's isolated points of contact (touching, no curve through them)
//      are made a vertex of both tows and a curve of one point, as in seam::pair.
//   4b. Flat contacts (one pair at a time, in order): where two tows coincide over an area, the
//      inside is made one common triangulation in both, as seam::pair does
//      (internal/flat_contacts.h), refined to the angle bound (and max_area) when step 5 runs; a
//      tow's curves with its other neighbours follow the renumbering (their segments inside the
//      contact, where a third tow crosses it, are constraints it never splits), and faces it
//      shares with one neighbour stay as they are in its contacts with the others.
//   5. Improve: the quality stage (seam/improve.h) on all tows at once, every curve of every pair
//      shared by its two tows, within `quality.tolerance` of the input tows (automatic: a tenth
//      of the smallest mean edge length, as seam::pair). Its acceptance predicate tests every
//      edit against every tow, so no edit makes two tows cross. Curves of two pairs that share
//      segments (step 3's overlaps) go to it as pieces that share none, each held by every tow
//      holding its segments (internal/curve_pieces.h), and are joined again after it. Should
//      the stage fail (InternalError), step 6 verifies the tows as they were before it.
//   6. Verify: every pair's outputs and curves, rounded to doubles as written, checked with
//      seam::check_pair (exact kernel) at TextileStats::verify_tolerance (the snapping's and the
//      closing's moves, plus step 5's tolerance or the closing's, whichever is larger, and at
//      least 1e-9 of the pair's diagonal). If one fails, the tows
//      as they were before step 5 are verified instead; if one fails then too, InternalError
//      names the pair and the problem (the meshes are left modified).
//
// Snapping: where an intersection point falls extremely close to a vertex, the new faces are
// slivers whose orientation rounding to double (writing the outputs) can flip, so that the
// written pair crosses next to its curve. Each tow is therefore snapped once against all its
// curves together (internal::snap_vertices_to_segments: vertices within snap_tol of a curve move
// onto it), and then the curves of every pair with a moved tow are computed again on the moved
// surfaces, so every curve is still the exact intersection of its two tows. The automatic
// tolerance is tiny, 1e-10 x the smallest bounding-box diagonal among the tow and its neighbours:
// below the default tolerance of `seam check` (1e-9 x the diagonal of the pair), so the outputs
// pass it without --tol. Snapping by a larger tolerance, as seam::pair does by default for mesh
// quality, is not done: moving a tow towards one neighbour's curve changes its intersections with
// the others and would need more rounds (a larger snap_tol can be given; pass it to
// `seam check --tol`).
//
// Determinism: every pair and every tow is computed by a task that owns its inputs (copies made
// from exact values, see src/textile.cpp), and results are stored by index, so the output is the
// same, bit for bit, for any number of threads. Errors are reported for the first failing pair
// (then tow) in input order, whatever the thread count.
//
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <seam/embed.h>
#include <seam/improve.h>

#include <cstddef>
#include <functional>
#include <map>
#include <string>
#include <vector>

namespace seam {

/// Reported after each finished pair and each finished tow (one call at a time).
struct TextileProgress {
  const char* stage = "";  ///< "pairs" or "tows"
  std::size_t done = 0, total = 0;
  double elapsed_seconds = 0;  ///< since textile() started
  double stage_seconds = 0;    ///< since this stage started
};

struct TextileOptions {
  /// Options of the embedding into each tow: min_angle_deg, max_area, max_steiner_per_face are
  /// used; snap_tol < 0 is the automatic tolerance above (exact kernel; 0 under the rounded
  /// kernels, which do not cope with a vertex snapped onto another tow), 0 disables snapping,
  /// > 0 is used as given; the others are set as seam::pair does.
  EmbedOptions embed;
  /// Worker threads (oneTBB task arena); 0: oneTBB's default (every core).
  int threads = 0;
  /// Called after each finished pair and tow, from worker threads but never concurrently.
  std::function<void(const TextileProgress&)> progress;
  /// Step 5, the quality stage (min_angle_deg is embed.min_angle_deg; tolerance < 0: automatic).
  bool improve = true;
  ImproveOptions quality = automatic_quality();
  /// Step 6: every pair checked as written; off, nothing is checked.
  bool verify_output = true;

  static ImproveOptions automatic_quality() {
    ImproveOptions q;
    q.tolerance = -1;
    return q;
  }
};

/// Quality of the new faces of one tow next to one pair's curves (faces with a curve vertex).
struct CurveFaceQuality {
  std::size_t faces = 0, below_10 = 0, below_20 = 0;
  double min_angle_deg = 0;  ///< 0 when there is no such face
};

struct TextilePairStats {
  std::size_t a = 0, b = 0;  ///< tow indices, a < b
  std::size_t curves = 0, closed_curves = 0;
  std::size_t curve_vertices = 0;  ///< closing repeats not counted
  /// The surfaces touch without crossing: no curves (nothing is embedded for this pair).
  bool touching_only = false;
  CurveFaceQuality quality_a, quality_b;
  double intersect_seconds = 0;  ///< the pair's task: copies of both tows and their intersection
  double copy_seconds = 0;       ///< of which making the task's own copies of both tows
  /// Step 4b: flat contacts of the two tows made one common triangulation (patches), its faces
  /// (in both tows), and patches left as they were (seam check then rejects the pair).
  std::size_t contact_patches = 0, shared_faces = 0, contact_patches_left = 0;
  /// Step 4a: isolated points of contact made a vertex of both tows (each a curve of one point,
  /// after the `curves` intersection curves).
  std::size_t contact_points = 0;
};

template <class K> struct TextilePair {
  /// The curves as embedded into both tows (closed ones repeat their first point): every point a
  /// vertex of both outputs, every segment an edge of both.
  std::vector<Polyline<K>> curves;
  TextilePairStats stats;
};

struct TextileStats {
  std::size_t tows = 0;
  std::size_t candidate_pairs = 0;     ///< bounding boxes overlap
  std::size_t intersecting_pairs = 0;  ///< with curves
  std::size_t touching_pairs = 0;      ///< touching without crossing
  std::size_t triple_points = 0;       ///< points where three tows meet, made vertices of all three
  /// Points where a tow crosses a flat contact of two others (ends of its two curves' common
  /// segments, meetings inside the contact), made vertices of the crossing tow only (step 3).
  std::size_t flat_crossing_points = 0;
  /// Step 2c: vertices moved onto a curve to close a feature thinner than the vertex separation,
  /// the largest move, and (when any moved) how far a part of an intersection could move with
  /// them: verify_tolerance includes the move and that tolerance.
  std::size_t vertices_closed = 0;
  double max_close_move = 0, close_tolerance = 0;
  int threads = 0;                     ///< threads of the task arena
  /// Step 5: done (some pair has curves and options.improve), its figures over all tows (mesh
  /// indices are tow indices), and its tolerance.
  bool improved = false;
  ImproveStats improve;
  double improve_tolerance = 0;
  /// Step 6: every pair passed seam::check_pair as written at this tolerance (pass it to
  /// `seam check --tol`); a note when the tows before step 5 were given instead, or a pair's flat
  /// contacts were left as they were or not refined (step 4b).
  bool verified = false;
  double verify_tolerance = 0;
  std::string note;
  /// prepare, boxes, pairs, snap, close, triples, tows, compare, contact_points, flat_contacts,
  /// improve, verify
  std::map<std::string, double> stage_seconds;
};

template <class K> struct TextileResult {
  /// The candidate pairs whose surfaces meet (with curves, or touching only), ordered by (a, b).
  std::vector<TextilePair<K>> pairs;
  /// Per tow, the statistics of its embedding (as seam::embed's).
  std::vector<EmbedStats> tows;
  TextileStats stats;
};

/// Makes every pair of `meshes` that interpenetrates conforming along its intersection curves
/// (the meshes are modified in place). `names` (one per mesh) are used in messages.
/// \pre every mesh is a valid triangle mesh without self-intersections (seam::validate_triangle_mesh).
/// Throws InvalidInput (sizes differ, a triple overlap that cannot be made a vertex, naming the three tows, bad
/// options) or InternalError. On a throw the meshes may have been modified.
template <class K>
TextileResult<K> textile(std::vector<Mesh<K>>& meshes, const std::vector<std::string>& names,
                         const TextileOptions& options = {});

}  // namespace seam
