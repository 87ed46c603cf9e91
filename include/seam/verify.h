// seam: independent checks of an embedding, used by the tests (and by `seam check` later).
// Each returns the list of problems found, empty when the property holds. Topological checks are
// exact; geometric ones are exact under the exact kernel and use a relative tolerance otherwise.
//
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <seam/embed.h>

#include <string>
#include <vector>

namespace seam {

/// The output is a valid triangle mesh, closed when the input was.
template <class K> std::vector<std::string> check_valid_mesh(const Mesh<K>& output, bool expect_closed);

/// Every point of every embedded curve is a vertex of `output` with the same coordinates and
/// every segment is an edge.
template <class K>
std::vector<std::string> check_curves_embedded(const Mesh<K>& output, const EmbedResult<K>& result);

/// Without snapping the output is the input surface: for every input face, the new faces that
/// came from it lie in its plane, have its orientation, and their vector areas add up to its
/// vector area (exactly under the exact kernel, which also makes the total area exactly equal).
/// Where a flat contact's common triangulation spans several input faces of one plane, the
/// input faces that do not add up on their own are grouped by plane and each group must.
template <class K> std::vector<std::string> check_same_surface(const Mesh<K>& input, const Mesh<K>& output);

/// Input vertices moved at most `tolerance` (vertex i of the input is vertex i of the output).
template <class K>
std::vector<std::string> check_vertex_moves(const Mesh<K>& input, const Mesh<K>& output, double tolerance);

}  // namespace seam
