// seam internal: one call of TetGen 1.5 (libtet) on a piecewise-linear complex of triangles.
// The only file that includes tetgen.h is src/tetgen_call.cpp (TetGen's macros stay there).
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <seam/errors.h>
#include <seam/io.h>

#include <array>
#include <cstddef>
#include <string>
#include <vector>

namespace seam::internal {

/// TetGen stopped on one of its own assert()s (see run_tetgen): an InternalError the caller may
/// answer by another input (volume_mesh moves the box faces' grid points).
class TetgenAborted : public InternalError {
 public:
  using InternalError::InternalError;
};

struct TetgenInput {
  std::vector<Point3d> points;
  std::vector<std::array<std::size_t, 3>> triangles;  ///< one facet each
  std::vector<Point3d> seeds;                         ///< region seed points
  std::vector<int> seed_attributes;                   ///< their region attribute (> 0)
  std::string switches;                               ///< e.g. "pq2YMAzQ"
};

struct TetgenOutput {
  std::vector<Point3d> points;  ///< the input points first, unchanged, then Steiner points
  std::vector<std::array<std::size_t, 4>> tets;
  std::vector<int> attribute;  ///< per tet (the seed's; TetGen numbers unseeded regions itself)
};

/// Runs tetrahedralize() in a child process (fork) that sends the mesh back through a pipe.
/// TetGen reports failure by throwing an int (libtet is built with TETLIBRARY); it is caught and
/// thrown here as InternalError with TetGen's meaning of the code (1 out of memory: bad_alloc,
/// 2 internal error, 3 self-intersection, 4 small feature, 5 close facets, 10 input error). But
/// Debian's libtet 1.5.0 also keeps its assert()s, and some valid inputs fire one (its point
/// location walks off the mesh while refining for quality: "locate: Assertion `searchtet->ver !=
/// 4' failed", seen on a 4 x 4 weave with some box grids), which aborts the process. In the
/// child that abort ends the child only: it is thrown here as TetgenAborted quoting TetGen's
/// message, and the caller goes on.
TetgenOutput run_tetgen(const TetgenInput& input);

}  // namespace seam::internal
