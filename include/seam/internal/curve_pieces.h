// seam internal: the curves of several pairs of tows cut into pieces that share no segment, for
// the quality stage (seam::textile step 5).
//
// Where a tow C crosses an area over which two tows A and B coincide (a flat contact), its curve
// with A and its curve with B run along the same segments there: each such segment is an edge of
// A, B and C, and a segment of two curves. The quality stage (seam/improve.h) takes each segment
// in one curve, held by every mesh that holds it, so that a split or a merge changes it in all
// of them at once. So each curve is cut where the set of tows holding its segments changes, and
// each stretch goes to the stage once, as a piece held by that set; the pairs' curves are joined
// again from the pieces afterwards. A curve sharing no segment is one piece, unchanged (the stage
// then sees exactly the curves it saw before).
//
// Cuts are made at points, which the stage does not remove: an end of an open curve is never
// merged (merge_plan), and a point of several curves is a junction, never merged either. join
// checks that the pieces still meet end to end, and throws InternalError otherwise.
//
// Exact: the pieces are made by comparing exact points; nothing is rounded.
//
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <seam/internal/improve_state.h>

#include <cstddef>
#include <vector>

namespace seam::internal {

/// One pair's curves and their vertices in each of its two tows (closed curves repeat their
/// first point and vertex).
template <class K> struct PairCurveRefs {
  std::size_t a = 0, b = 0;  ///< its two tows
  std::vector<Polyline<K>>* curves = nullptr;
  std::vector<std::vector<typename Mesh<K>::Vertex_index>>* vertices_a = nullptr;
  std::vector<std::vector<typename Mesh<K>::Vertex_index>>* vertices_b = nullptr;
};

template <class K> struct CurvePieces {
  SharedCurves<K> shared;  ///< the pieces, for the quality stage
  struct Use {
    std::size_t piece = 0;
    bool reversed = false;
  };
  std::vector<std::vector<std::vector<Use>>> uses;  ///< per pair, per curve: its pieces in order
  std::vector<std::vector<char>> whole;             ///< per pair, per curve: it is its own piece, uncut
  std::size_t shared_segments = 0;                   ///< segments of two or more curves
};

/// The curves of `pairs` as pieces held by `tows` meshes. Throws InternalError when two curves
/// share segments but not as stretches that can be cut the same way in both (one curve passing
/// twice along a segment, say).
template <class K> CurvePieces<K> cut_into_pieces(const std::vector<PairCurveRefs<K>>& pairs, std::size_t tows);

/// The pairs' curves and vertex lists again, from the pieces as the quality stage left them (a
/// closed curve that was cut starts at its first point again, if that point is still on it).
template <class K> void join_pieces(const CurvePieces<K>& pieces, const std::vector<PairCurveRefs<K>>& pairs);

}  // namespace seam::internal
