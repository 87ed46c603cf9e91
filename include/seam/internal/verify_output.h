// seam internal: the last step of seam::pair and seam::pair_with_curves. The outputs are
// checked as they will be written: every coordinate rounded to a double (after its exact value
// is computed, so that it rounds here as in the writer), the inputs as doubles, with
// seam::check_pair under the exact kernel: the verdict `seam check --tol <tol>` gives on the
// written files.
//
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <seam/check.h>
#include <seam/pair.h>

#include <string>

namespace seam::internal {

/// Checks `a2`, `b2` and `curves` against the inputs `a`, `b` as written (see above). The points
/// of `a2`, `b2` and `curves` are made exact (their values do not change).
template <class K>
PairCheckReport check_as_written(const Mesh<K>& a, const Mesh<K>& b, Mesh<K>& a2, Mesh<K>& b2,
                                 std::vector<Polyline<K>>& curves, double tol);

/// The same for one mesh with embedded curves (seam embed): seam::check_embedding under the exact
/// kernel on the output and curves rounded to doubles, the input as doubles (as it is when its
/// coordinates are not all doubles). The points of `output` and `curves` are made exact.
template <class K>
EmbedCheckReport check_embedding_as_written(const Mesh<K>& input, Mesh<K>& output, std::vector<Polyline<K>>& curves,
                                            double tol, const std::vector<Polyline<K>>* given = nullptr);

/// The tolerance seam::pair's outputs are verified at: the snapping tolerance (vertices moved by
/// up to it), the given curves' largest move, and at least 1e-9 of the pair's size.
template <class K> double verification_tolerance(const Mesh<K>& a, const Mesh<K>& b, const PairStats& st);

/// check_as_written on a pair's result at verification_tolerance; fills the result's
/// verified, verify_tolerance and seconds, and on failure `problem` (the first problem found).
/// `close_points`, when given, receives the points of the vertex pairs found too close (check 5)
/// when that is the only problem found.
template <class K>
bool verify_outputs(const Mesh<K>& a, const Mesh<K>& b, Mesh<K>& a2, Mesh<K>& b2, PairResult<K>& result,
                    std::string& problem, std::vector<std::array<double, 3>>* close_points = nullptr);

}  // namespace seam::internal
