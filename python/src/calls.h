// seam Python bindings: the library's operations on plain arrays. This header includes neither
// pybind11 nor CGAL: calls.cpp holds every use of the library (its kernels instantiated once, in
// the library), module.cpp every use of pybind11, and each compiles without the other's headers.
//
// Inputs are views of the caller's arrays (C-contiguous float64 (n, 3) vertices, int64 (m, 3)
// faces, valid for the call and copied at its start); outputs are vectors the module hands to
// NumPy without another copy. Errors are seam's exceptions (seam/errors.h): InvalidInput naming
// the array ("VA: vertex 5 has a non-finite coordinate"), InternalError (a CGAL failure too).
// No function here touches Python: the module calls them with the GIL released.
//
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace seam_python {

/// A mesh given by the caller: `nv` x 3 doubles and `nf` x 3 vertex indices, with the names of
/// the two arrays for messages ("VA", "FA").
struct MeshView {
  const void* vertices = nullptr;  ///< nv x 3 float64, C order (any alignment)
  std::size_t nv = 0;
  const void* faces = nullptr;  ///< nf x 3 int64, C order (any alignment)
  std::size_t nf = 0;
  std::string vertices_name, faces_name;
};

/// A curve given by the caller: `n` x 3 doubles.
struct CurveView {
  const void* points = nullptr;  ///< n x 3 float64, C order (any alignment)
  std::size_t n = 0;
};

using Point = std::array<double, 3>;
using Curve = std::vector<Point>;

/// A mesh returned. Per face: the index of the input face it lies in (-1 for a face remeshed
/// next to the curves, which no single input face contains), and whether seam made it.
struct MeshOut {
  std::vector<Point> vertices;
  std::vector<std::array<std::int64_t, 3>> faces;
  std::vector<std::int64_t> source_face;
  std::vector<std::uint8_t> new_face;
};

/// "exact", "filtered" or "float"; anything else is InvalidInput.
struct Kernel {
  std::string name = "exact";
};

// Options: the CLI's, with its defaults; a negative length is "auto" (seam/embed.h).

struct PairArgs {
  Kernel kernel;
  double snap_tol = -1, min_angle = 20, max_area = 0;
  long bound_reach = -1;  ///< ImproveOptions::bound_reach; -1: auto
  bool improve = true;
  bool given_curves = false;  ///< use `curves` (seam::pair_with_curves) instead of the computed ones
  std::vector<CurveView> curves;
};
struct PairOut {
  MeshOut a, b;
  std::vector<Curve> curves;  ///< shared by both, bit for bit; closed ones repeat their first point
  std::string report;         ///< JSON, the keys of `seam pair --report` without "files"
};
PairOut pair(const MeshView& a, const MeshView& b, const PairArgs& args);

struct EmbedArgs {
  Kernel kernel;
  double snap_tol = -1, min_angle = 20, max_area = 0, max_distance = -1, curve_tol = 0;
};
struct EmbedOut {
  MeshOut mesh;
  std::vector<Curve> curves;                              ///< as embedded
  std::vector<std::vector<std::int64_t>> curve_vertices;  ///< each curve's vertices, by index
  std::string report;                                     ///< JSON, `seam embed --report` without "files"
};
EmbedOut embed(const MeshView& mesh, const std::vector<CurveView>& curves, const EmbedArgs& args);

struct CheckOut {
  bool ok = false;
  std::vector<std::string> problems;
  std::string report;  ///< JSON, `seam check --report` without "files" and "seconds"
};
/// `tol` < 0: 1e-9 x the diagonal of the bounding box of A and B, as `seam check`.
CheckOut check(const MeshView& a, const MeshView& b, const MeshView& a2, const MeshView& b2,
               const std::vector<CurveView>& curves, double tol, const Kernel& kernel);

struct TextileArgs {
  Kernel kernel;
  double snap_tol = -1, min_angle = 20, max_area = 0;
  long bound_reach = -1;  ///< ImproveOptions::bound_reach; -1: auto
  bool improve = true;
  int threads = 0;
};
struct TextilePairOut {
  std::size_t a = 0, b = 0;  ///< tow indices, a < b
  std::vector<Curve> curves;
};
struct TextileOut {
  std::vector<MeshOut> tows;
  std::vector<TextilePairOut> pairs;
  std::string report;  ///< JSON, `seam textile --report` without the file names
};
TextileOut textile(const std::vector<MeshView>& tows, const std::vector<std::string>& names, const TextileArgs& args);

/// seam::make_crossover and seam::make_tow: the weft and the warp (faces, no provenance).
std::array<MeshOut, 2> make_crossover(int weft_along, int weft_around, int warp_along, int warp_around,
                                      const std::string& warp_section, double warp_height);

}  // namespace seam_python
