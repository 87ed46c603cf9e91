// seam::volume_mesh: a tetrahedral model of a unit cell (tows + matrix) for finite elements.
//
// Input: closed triangle surfaces (tows) that do not overlap but may touch, along shared faces
// (the same three bit-identical corners in two tows: the contact patches `seam resolve` makes),
// along shared edges or at shared vertices; and an axis-aligned matrix box that contains them.
// Steps:
//   1. Checks (InvalidInput naming the tow): every tow is closed; every tow lies in the closed
//      default box (a given box cuts the tows that cross it, see below); the tows meet each other (and themselves) only in common vertices, edges and faces.
//      That test is exact (CGAL predicates on the doubles, box_intersection_d candidates).
//   2. One piecewise-linear complex: vertices merged by exact coordinate equality, each shared
//      triangle once, and the box's six faces, each triangulated (a constrained Delaunay
//      triangulation of a grid of points plus every tow vertex and edge that lies in that face,
//      so that a tow touching the box, e.g. a tow's end cap in a face of the unit cell, is
//      part of the box's boundary; the grid (VolumeMeshOptions::box_face_spacing) keeps the
//      matrix tets along the box from being bounded by two huge triangles per face, which -Y
//      would not let TetGen split).
//   3. TetGen 1.5 (as a library): -p (PLC), -q (radius-edge bound), -a (volume bound, optional),
//      -A (a region attribute per tow: a seed point strictly inside each connected component of
//      each tow, found by moving a face centroid inwards and checked exactly with
//      CGAL::Side_of_triangle_mesh), -Y (no Steiner point on any input face: the tow surfaces
//      and the box faces are exactly the triangles given), -M (no merging of coplanar facets:
//      each input triangle stays a triangle of the mesh). Tets in regions without a tow seed are
//      the matrix.
//      Debian's TetGen 1.5.0 stops on one of its own assertions on some valid inputs, and whether
//      it does changes with the box faces' grid, chaotically: there the grid is made again finer
//      (x 0.97, 0.94, 0.91, 0.88, 0.85), and the spacing used is reported (no retry without a
//      grid); after six stops, InternalError.
//   4. Verification of the result (verify_volume_mesh below): if it fails, InternalError.
// Tows that cross a given box (a periodic unit cell whose tows the cell faces cut) are first cut
// by it (before step 2): exact cuts, the pieces Delaunay-triangulated (the same in two tows that
// share a face), the cut points rounded onto the box planes; the box faces' triangles inside a
// cut tow become its caps, so each cut tow is closed again by triangles of the box's boundary
// (see internal/volume_plc.h). The default box never cuts (it is the tows' bounding box).
//
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <seam/io.h>

#include <array>
#include <cstddef>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace seam {

/// An axis-aligned box.
struct AxisBox {
  Point3d min{0, 0, 0}, max{0, 0, 0};
};

struct VolumeMeshOptions {
  /// The matrix box. Default (none): the bounding box of all tows enlarged by `margin`.
  std::optional<AxisBox> box;
  /// Added on every side of the default box (absolute length, >= 0). Ignored with `box`.
  double margin = 0.0;
  /// TetGen's radius-edge bound (-q): a tet whose circumradius / shortest edge exceeds it is
  /// refined, where it can be without points on the input faces. 0: no quality refinement.
  /// TetGen needs > about 1.1 to terminate; values below 1.2 are refused.
  double radius_edge = 2.0;
  /// Largest tet volume (-a); 0: no bound.
  double max_volume = 0.0;
  /// Spacing of the points added to the box faces; 0: automatic (the mean edge length of the
  /// tows, or 1/20 of the box's longest side if that is larger); a negative value: none (each face's triangulation has only the corners and the
  /// tow vertices lying in it).
  double box_face_spacing = 0.0;
  /// Where a given box cuts tows: tow vertices closer than this fraction of the tows' mean edge
  /// length to a box plane move onto it first (no cut then passes that close to a vertex, which
  /// would leave a sliver piece); 0: none. A move that would put a face in a box plane, make it
  /// degenerate or turn it over is not made.
  double cut_snap = 0.1;
  /// Let TetGen put Steiner points on the input faces (drops -Y). The tow surfaces then change
  /// (split triangles); the checks that every input triangle is a mesh face are skipped.
  bool steiner_on_surfaces = false;
};

/// A tetrahedral mesh with one region per tet: 0 is the matrix, i + 1 is tow i.
struct TetMesh {
  std::vector<Point3d> points;
  /// Corner indices, positively oriented (CGAL::orientation is POSITIVE: the fourth corner lies
  /// on the side of the first three's counter-clockwise normal), as VTK, Gmsh and Abaqus want.
  std::vector<std::array<std::size_t, 4>> tets;
  std::vector<int> region;
  /// Region names: [0] "matrix", then one per tow.
  std::vector<std::string> region_names;
};

/// A contact patch: the faces shared by two tows (as index triples into TetMesh::points), with
/// for each face the tet of region `a` that has it (for Abaqus surface sets).
struct ContactPatch {
  int a = 0, b = 0;  ///< regions (tow i is region i + 1), a < b
  std::vector<std::array<std::size_t, 3>> faces;
  std::vector<std::size_t> tet_a;  ///< per face
};

struct RegionStats {
  std::string name;
  std::size_t tets = 0;
  /// Sum of the tets' volumes, and the volume enclosed by the region's surfaces (for the matrix:
  /// the box minus the tows), both summed exactly and then rounded.
  double volume = 0, surface_volume = 0;
  /// |volume - surface_volume| / surface_volume, from the exact sums (0 when they tile exactly).
  double relative_error = 0;
};

struct VolumeMeshStats {
  AxisBox box;
  std::size_t input_points = 0, input_triangles = 0;  ///< the PLC (box faces included)
  std::size_t tow_triangles = 0, shared_triangles = 0, box_triangles = 0;
  /// Tows that crossed the box and were cut by it (their caps are box triangles); tow vertices
  /// moved onto a box plane first (VolumeMeshOptions::cut_snap), and the longest such move.
  std::size_t clipped_tows = 0, cut_snapped_vertices = 0;
  double cut_snap_max_move = 0;
  /// Why the tows were cut without moving vertices onto the box planes, when moved they failed
  /// the checks (empty otherwise).
  std::string cut_snap_undone;
  std::size_t points = 0, tets = 0;
  std::size_t steiner_points = 0;  ///< points TetGen added (none on the input faces with -Y)
  std::vector<RegionStats> regions;
  double min_dihedral_deg = 0, max_dihedral_deg = 0;
  double max_radius_edge = 0;  ///< circumradius / shortest edge, the largest over all tets
  /// Tets whose radius-edge ratio exceeds the bound asked for (TetGen cannot refine those whose
  /// bad shape is forced by the input faces under -Y).
  std::size_t tets_above_radius_edge = 0;
  std::string tetgen_switches;
  /// The box faces' grid spacing used (0: no grid). Where TetGen stopped on one of its own
  /// assertions, the grid was made again finer (at most five times): each stop's message.
  double box_face_spacing = 0;
  std::vector<std::string> tetgen_aborts;
  std::map<std::string, double> stage_seconds;  ///< "check", "plc", "tetgen", "verify"
};

struct VolumeMeshResult {
  TetMesh mesh;
  std::vector<ContactPatch> contacts;
  VolumeMeshStats stats;
};

/// Meshes the tows and the matrix box (see the top of this file). `names` name the tows in
/// messages and region names (same size as `tows`). Throws InvalidInput (options out of range,
/// a tow not closed, outside the box, overlapping another; the message starts with the tow's
/// name), InternalError (TetGen failed, or the result failed verify_volume_mesh).
VolumeMeshResult volume_mesh(const std::vector<TriangleSoup>& tows, const std::vector<std::string>& names,
                             const VolumeMeshOptions& options = {});

/// The invariants of a volume mesh, checked with exact arithmetic on its double coordinates:
///  - no tet is inverted or flat (CGAL::orientation POSITIVE);
///  - each region's tets sum to the volume enclosed by its surfaces (tow i: the volume of
///    tows[i]; the matrix: the box minus all tows), both sums exact, relative error <= 1e-9;
///  - unless `steiner_on_surfaces`: every tow triangle is a face of the mesh, with a tet of that
///    tow on one side and a tet of another region (or another tow's, for a shared face) on the
///    other; every shared face has tets of both its tows.
/// Returns one line per problem (empty: all hold) and fills the per-region figures of `stats`.
std::vector<std::string> verify_volume_mesh(const TetMesh& mesh, const std::vector<TriangleSoup>& tows,
                                            const AxisBox& box, bool steiner_on_surfaces, VolumeMeshStats& stats);

/// Writes the mesh by `format` ("vtu", "inp", "msh", with or without the dot, any case):
///  - vtu: VTK XML unstructured grid, ASCII, cell data `region` (Int32), for ParaView;
///  - inp: Abaqus input: *NODE, one *ELEMENT block of C3D4 per region with ELSET=<region name>,
///    and per contact patch an element-based *SURFACE (NAME=contact_<a>_<b>, the faces seen from
///    tow a's tets);
///  - msh: Gmsh 4.1 ASCII, one volume entity and one physical group (dimension 3) per region.
/// Coordinates with 17 significant digits. Throws InvalidInput for another format.
void write_volume_mesh(const TetMesh& mesh, const std::vector<ContactPatch>& contacts, std::ostream& out,
                       const std::string& format);

/// The lower-case extension of `path` (".vtu", ".inp" or ".msh"); InvalidInput naming `path`
/// for any other. Touches no file.
std::string volume_mesh_format(const std::string& path);

}  // namespace seam
