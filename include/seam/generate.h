// seam: generated tow geometry for tests, examples and benchmarks.
//
// A tow is a tube whose cross-section (elliptical or lenticular) is swept along a crimped
// (sinusoidal) path, like one yarn of a woven unit cell, closed with flat end caps. The smooth
// surface is known analytically, so curves sampled on it lie near, not on, the faceted mesh:
// exactly the situation of the report, where the boundary curve comes from smooth surfaces.
//
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <seam/io.h>

#include <string>
#include <vector>

namespace seam {

enum class Section { elliptical, lenticular };

struct TowOptions {
  double length = 10.0;            ///< length of the path along x
  double half_width = 1.0;         ///< semi-axis of the section along the path's normal in the xy plane
  double half_height = 0.35;       ///< semi-axis of the section along z (the path's normal in xz);
                                   ///< a lenticular section needs half_height <= half_width
  Section section = Section::elliptical;
  double crimp_amplitude = 0.3;    ///< z amplitude of the sinusoidal path
  double crimp_wavelength = 10.0;  ///< wavelength of the path
  /// When not empty, replaces the sinusoid: the path's height is heights[k % n] at
  /// s = (k + 0.5) * heights_spacing (k any integer, so the pattern repeats), with zero slope
  /// there, and the cosine blend z0 + (z1 - z0) (1 - cos(pi t)) / 2 in between (a woven tow's
  /// crimp: up over one crossing, down under the next). crimp_amplitude and crimp_wavelength are
  /// then unused; heights_spacing must be positive.
  std::vector<double> heights;
  double heights_spacing = 1.0;
  int segments_along = 60;         ///< number of rings - 1 along the path
  int segments_around = 24;        ///< vertices per ring
  bool capped = true;              ///< close the ends with fan caps (the mesh is then closed)
  /// Rigid transform applied last: rotation about z then x (radians), then translation.
  double rotate_z = 0.0, rotate_x = 0.0;
  Point3d translate = {0.0, 0.0, 0.0};
};

/// The faceted tow: a closed (if capped) consistently oriented triangle mesh, outward normals.
/// (segments_along + 1) rings of segments_around vertices, ring i at s = i * length /
/// segments_along, vertex j at phi = 2 pi j / segments_around (so every vertex lies on the
/// smooth surface and the facets lie inside it, up to the path's curvature), then, if capped,
/// the centres of the start and end caps. Triangles: 2 per quad (alternating diagonals), then
/// 2 * segments_around cap triangles. Throws InvalidInput for invalid options (non-positive
/// sizes, segments_along < 1, segments_around < 3, non-finite values).
TriangleSoup make_tow(const TowOptions& options);

/// Points of the intersection of the smooth surfaces of two tows (not of their meshes), one near
/// each point of `near` (points of the meshes' intersection, say): Gauss-Newton on the surface
/// parameters (s, phi) of both tows from the parameters of the seed, to a point on both surfaces
/// within 1e-13 of the section size. The curve through them lies off both meshes by up to their
/// chordal error: what a NURBS/NURBS intersection (SISL) gives for faceted tows, the given curves
/// of the report. Throws InvalidInput when a point does not converge.
std::vector<Point3d> smooth_intersection_points(const TowOptions& a, const TowOptions& b,
                                                const std::vector<Point3d>& near);

/// One crossover of a plain weave, the pair the tests and benchmarks use: an elliptical weft
/// along x (the default tow, its path from x = -5 to 5) and a warp along y (turned by pi/2,
/// crimped the other way, amplitude -0.3) whose path is lifted to `warp_height`: the weft is 0.7
/// thick at the crossing, so the two interpenetrate by 0.7 - warp_height there. Resolutions
/// (TowOptions::segments_along, segments_around) per tow.
struct CrossoverTows {
  TowOptions weft, warp;
};
CrossoverTows make_crossover(int weft_along, int weft_around, int warp_along, int warp_around,
                             Section warp_section, double warp_height);

/// The point of the smooth tow surface at path parameter s in [0, length] and angle phi.
/// phi = 0 is the +y side of the section (before the transform), phi = pi/2 its top (towards +z).
/// Elliptical: (a cos phi, b sin phi); lenticular: x = a cos phi and the lens profile
/// |y| = sqrt(R^2 - x^2) - (R - b), R = (a^2 + b^2) / (2 b), with the sign of sin phi.
Point3d tow_surface_point(const TowOptions& options, double s, double phi);

/// A dense closed curve on the smooth tow surface, going once around it: at angle phi it sits
/// at path parameter s_center + tilt * cos(phi) (a tilted ring). `samples` distinct points;
/// the polyline returned is closed (last point equals first). Sample k is at phi = 2 pi k / samples.
/// Throws InvalidInput if samples < 3 or [s_center - |tilt|, s_center + |tilt|] leaves [0, length].
std::vector<Point3d> make_ring_curve(const TowOptions& options, double s_center, double tilt,
                                     int samples);

/// A woven unit cell (TexGen-like): `wefts` tows along x (weft j centred on y = (j + 0.5) *
/// spacing) and `warps` tows along y (warp i centred on x = (i + 0.5) * spacing), each as long as
/// the cell (warps * spacing, resp. wefts * spacing) and capped. At the crossing of warp i and
/// weft j the weft passes over when (i + j) mod (over + under) < over, under otherwise: over =
/// under = 1 is a plain weave, over = 2, under = 1 a 2/1 twill, 2 and 2 a 2/2 twill. Each tow is
/// crimped (see TowOptions::heights) between the heights +-a at its crossings, a = half_height -
/// overlap / 2, so that at every crossing the two tows interpenetrate by `overlap` (their
/// vertical extents overlap by that much); overlap < 0 leaves a gap. This is the deepest
/// interpenetration (the tows first meet at the centre of the crossing) only while the crimp
/// bends less than the section: a pi^2 / spacing^2 < half_height / half_width^2 for elliptical
/// sections (the defaults: 0.33 < 0.42); otherwise they also meet off centre. Parallel tows touch
/// only when half_width >= spacing / 2.
struct WeaveOptions {
  int warps = 2, wefts = 2;    ///< N x M tows
  int over = 1, under = 1;     ///< weave pattern (1, 1: plain weave)
  double spacing = 2.0;        ///< distance between neighbouring parallel tows
  double half_width = 0.6;     ///< section semi-axes (see TowOptions)
  double half_height = 0.15;
  double overlap = 0.03;       ///< interpenetration depth at each crossing
  Section section = Section::elliptical;
  int segments_per_crossing = 12;  ///< wefts: segments along per spacing; warps get one more
  /// Wefts: vertices per ring, raised to the next value equal to 2 mod 4 (no vertex line along a
  /// tow's top or bottom, where the crossing tow's rings would nearly meet it); warps: the
  /// weft count + 4 (so 16 gives 18 and 22).
  int segments_around = 16;
};

/// One generated tow of a unit cell, with its name ("weft0", ..., "warp0", ...).
struct NamedTow {
  std::string name;
  TowOptions options;
};

/// The tows of the cell, wefts first (weft0, weft1, ...), then warps. Throws InvalidInput for
/// invalid options (counts < 1, over or under < 1, non-positive or non-finite sizes,
/// |overlap| >= 2 half_height).
std::vector<NamedTow> make_weave(const WeaveOptions& options);

}  // namespace seam
