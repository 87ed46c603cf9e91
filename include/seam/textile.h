// seam::textile: every interpenetration among N tows of a unit cell embedded at once, in parallel.
//
//   1. Candidates: CGAL::box_intersection_d on the tows' bounding boxes.
//   2. Pairs (concurrently): the intersection curves of each candidate pair, exactly as
//      seam::intersection_curves computes them for `seam pair` (touching-only contact dropped,
//      flat contact reduced to its boundary). A candidate with no curve is no pair.
//   3. Triple overlaps: where the curves of tow A with B and of A with C meet on A, the three tows
//      overlap in one place. Embedding both would split a curve on A at a point that B (or C)
//      does not have, so the outputs would not conform: the run stops with InvalidInput naming
//      the three tows (no output is produced). Shared triple points are not supported yet.
//   4. Tows (concurrently): each tow receives every curve that involves it in one seam::embed
//      call (curve points kept at their own coordinates, as in seam::pair), so that for every
//      pair both outputs share the pair's curves vertex for vertex and edge for edge.
//
// No snapping (textile v1): snapping a tow onto the curves of one neighbour moves its surface and
// so changes its intersections with every other neighbour; doing it soundly needs every curve of
// the tow recomputed after each move. Without it, under the exact kernel every output surface is
// its input surface (new vertices lie exactly in their input face), so the curves of every pair
// are exactly the intersection of the two outputs. The price is mesh quality next to the curves
// (see seam::pair's snapping). EmbedOptions::snap_tol must therefore be 0 or negative.
//
// Determinism: every pair and every tow is computed by a task that owns its inputs (copies made
// from exact values, see src/textile.cpp), and results are stored by index, so the output is the
// same, bit for bit, for any number of threads. Errors are reported for the first failing pair
// (then tow) in input order, whatever the thread count.
//
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <seam/embed.h>

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
};

struct TextileOptions {
  /// Options of the embedding into each tow: min_angle_deg, max_area, max_steiner_per_face are
  /// used; snap_tol must be <= 0 (no snapping, see above); the others are set as seam::pair does.
  EmbedOptions embed;
  /// Worker threads (oneTBB task arena); 0: oneTBB's default (every core).
  int threads = 0;
  /// Called after each finished pair and tow, from worker threads but never concurrently.
  std::function<void(const TextileProgress&)> progress;
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
  double intersect_seconds = 0;
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
  int threads = 0;                     ///< threads of the task arena
  std::map<std::string, double> stage_seconds;  ///< prepare, boxes, pairs, tows, compare
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
/// Throws InvalidInput (sizes differ, snap_tol > 0, a triple overlap naming the three tows, bad
/// options) or InternalError. On a throw the meshes may have been modified.
template <class K>
TextileResult<K> textile(std::vector<Mesh<K>>& meshes, const std::vector<std::string>& names,
                         const TextileOptions& options = {});

}  // namespace seam
