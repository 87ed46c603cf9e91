// seam: reading and validating triangle meshes and polylines, writing results atomically.
//
// Everything here works on plain double coordinates (what files hold); conversion to a kernel
// is exact (a double is representable in every kernel), see mesh_from_soup / soup_from_mesh.
//
// Every reader throws seam::InvalidInput (the content is wrong) or seam::IOError (the file
// cannot be opened or read) with a one-line message that starts with the file name, e.g.
//   "tow_a.off: face 17 has a vertex index 90 out of range (mesh has 64 vertices)".
//
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <seam/errors.h>
#include <seam/types.h>

#include <array>
#include <cstddef>
#include <functional>
#include <memory>
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

namespace seam {

using Point3d = std::array<double, 3>;

/// A triangle mesh as read from or written to a file.
struct TriangleSoup {
  std::vector<Point3d> points;
  std::vector<std::array<std::size_t, 3>> triangles;
};

/// Reads a triangle mesh, format chosen by extension (case-insensitive): .off, .obj, .ply,
/// .stl (ASCII or binary). Identical points of an STL file are merged. Then validates it with
/// validate_triangle_mesh(). Throws InvalidInput / IOError with a message naming `path`.
TriangleSoup read_triangle_mesh(const std::string& path);

/// The same on a file's content held in memory: `format` is the extension ("off" or ".off", ...,
/// case-insensitive), `name` starts every message. Parses and validates; never reads a file.
TriangleSoup parse_triangle_mesh(std::string_view data, const std::string& format, const std::string& name);

/// The coordinates seam computes with (README, "Supported coordinates"). Exact predicates and
/// constructions start from interval arithmetic on doubles; products of up to about ten
/// coordinate differences must stay finite and normal there, or GMP is handed an infinity.
/// So: no coordinate beyond 1e30 in magnitude, no mesh smaller than 1e-30 across, and no mesh
/// smaller than 1e-7 of its distance from the origin (there a double's unit in the last place
/// is above 1e-9 of the mesh's size: rounding the outputs to doubles could move a vertex by
/// more than half the vertex separation of seam check).
struct SupportedCoordinates {
  static constexpr double max_magnitude = 1e30;
  static constexpr double min_extent = 1e-30;
  static constexpr double min_extent_to_position = 1e-7;
};

/// Throws InvalidInput naming `name` when `points` lie outside SupportedCoordinates: a
/// coordinate beyond max_magnitude; when `whole_mesh`, also a bounding box diagonal below
/// min_extent or below min_extent_to_position of the largest coordinate's magnitude.
void check_coordinate_range(const std::vector<Point3d>& points, const std::string& name, bool whole_mesh = true);

/// The same on a mesh (coordinates rounded to doubles), and on curves (magnitude only).
template <class K> void check_coordinate_range(const Mesh<K>& mesh, const std::string& name);
template <class K> void check_coordinate_range(const std::vector<Polyline<K>>& curves, const std::string& name);

/// Checks that `soup` is a valid oriented 2-manifold triangle mesh (with or without boundary):
/// at least one triangle; finite coordinates within SupportedCoordinates; indices in range; no repeated index in a
/// triangle; no zero-area (collinear, exact test) triangle; every edge used by at most two
/// triangles, in opposite directions (consistent orientation); every vertex's triangles form
/// one fan (no non-manifold vertex); no unreferenced vertex is an error either (they are
/// dropped by mesh_from_soup). `name` starts every message.
void validate_triangle_mesh(const TriangleSoup& soup, const std::string& name);

/// Checks that the faces of a valid mesh (see validate_triangle_mesh) meet only in their common
/// vertices and edges (CGAL::Polygon_mesh_processing::self_intersections, exact predicates on the
/// doubles). Throws InvalidInput naming two faces that intersect, by their index in `soup`
/// (the file's numbering): "tow.off: faces 12 and 873 intersect (the surface intersects itself)".
/// seam embed and seam pair run it on their input meshes (not part of read_triangle_mesh:
/// seam check reports a self-intersecting output as a failed check).
void check_no_self_intersection(const TriangleSoup& soup, const std::string& name);

/// Reads polylines in CGAL's text format: one polyline per non-empty line,
/// "n x1 y1 z1 ... xn yn zn". Lines starting with '#' are comments. Errors (naming the file
/// and line): wrong count, no point, non-numeric or non-finite values, no polyline. A polyline of
/// one point is an isolated point of contact (seam pair writes them).
std::vector<std::vector<Point3d>> read_polylines(const std::string& path);

/// The same on a file's content held in memory; `name` starts every message.
std::vector<std::vector<Point3d>> parse_polylines(std::string_view data, const std::string& name);

/// Throws InvalidInput naming `path` unless its extension (case-insensitive) is a mesh format
/// write_triangle_mesh writes: .off, .obj, .ply or .stl. Touches no file.
void check_mesh_extension(const std::string& path);

/// Writes `soup` by extension (.off, .obj, .ply, .stl; OFF and OBJ with 17 significant digits,
/// so that doubles round-trip bit-exactly). Atomic: an OutputFiles of one file.
void write_triangle_mesh(const TriangleSoup& soup, const std::string& path);

/// The same into a stream; `format` is the extension ("off" or ".off", ..., case-insensitive).
void write_triangle_mesh(const TriangleSoup& soup, std::ostream& out, const std::string& format);

/// Writes polylines in the format read_polylines reads, 17 significant digits. Atomic.
void write_polylines(const std::vector<std::vector<Point3d>>& polylines, const std::string& path);

/// The same into a stream.
void write_polylines(const std::vector<std::vector<Point3d>>& polylines, std::ostream& out);

/// Writes a text file atomically: `write` fills the stream of a temporary file in the same
/// directory, which is then renamed to `path` (an OutputFiles of one file).
void write_file_atomically(const std::string& path, const std::function<void(std::ostream&)>& write);

/// A set of output files that replace their targets together, or not at all.
///
/// 1. add(path), before any work: checks the path and creates the output's temporary file at
///    once, "DIR/.seam-XXXXXX" (mkstemp) in the target's directory (a short name: a target name
///    of up to NAME_MAX bytes works). So a missing or unwritable directory, a name too long, a
///    target that is a directory, a FIFO or a device (refused: only regular files are replaced)
///    are found before any work, with the system's reason ("No such file or directory").
///    A symbolic link is followed to its final target, which is replaced; the link stays.
/// 2. write(i, fill): fills output i's temporary file. Any write error, e.g. a full disk, throws
///    IOError naming the output and the reason ("No space left on device").
/// 3. commit(): renames every temporary file onto its target, in the order of add(), all under
///    one lock that remove_temporary_outputs() takes too.
/// Until commit() every existing target is untouched; the destructor, discard() and
/// remove_temporary_outputs() remove the temporary files (and the directories create_directory()
/// made, if still empty). A signal handled through remove_temporary_outputs() therefore lands
/// before the first rename (old outputs intact, no temporary file left) or after the last (all
/// new). Not covered: SIGKILL or a power loss between two renames, and a rename failing after
/// earlier ones succeeded (the target replaced by a directory meanwhile, a device error): the
/// IOError then names the outputs already replaced.
///
/// add(), create_directory() and commit() are for one thread; write() may run concurrently for
/// distinct outputs. Errors: IOError (the path cannot be written), InvalidInput (an empty path,
/// two outputs with the same target).
class OutputFiles {
 public:
  OutputFiles();
  ~OutputFiles();
  OutputFiles(const OutputFiles&) = delete;
  OutputFiles& operator=(const OutputFiles&) = delete;

  /// Creates `dir` and its missing parents now; the ones created are removed again (if empty)
  /// when the set is discarded.
  void create_directory(const std::string& dir);
  /// Checks `path` and creates its temporary file; returns the output's index. Outputs added with
  /// `last` are renamed after all the others (a report that describes them).
  std::size_t add(const std::string& path, bool last = false);
  /// Fills output `i` (once).
  void write(std::size_t i, const std::function<void(std::ostream&)>& fill);
  /// Renames every output onto its target, in the order added (those added with `last` at the
  /// end). Every output must be written.
  void commit();
  /// Removes every temporary file not yet renamed (and the directories made, if empty).
  void discard() noexcept;
  /// The number of outputs added.
  std::size_t size() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// The checks of OutputFiles::add() without creating anything: throws IOError naming `path` when
/// it cannot be examined or names a directory, a FIFO, a device (not a regular file, also through
/// symbolic links).
void check_output_path(const std::string& path);

/// Removes the temporary files of every OutputFiles of the process that is not committed or
/// discarded (and the directories they made, if empty), and makes every later add() and commit()
/// fail. For a thread that handles SIGINT / SIGTERM before the process ends (the CLI's): it waits
/// for a commit() in progress to finish.
void remove_temporary_outputs() noexcept;

/// Builds a Surface_mesh from a validated soup (exact conversion of the coordinates).
/// Unreferenced points are dropped. Throws InvalidInput if a face cannot be added.
template <class K> Mesh<K> mesh_from_soup(const TriangleSoup& soup, const std::string& name);

/// The mesh's vertices (rounded to double, exact for points that came from doubles) and faces.
template <class K> TriangleSoup soup_from_mesh(const Mesh<K>& mesh);

/// Conversion of polylines between double triples and kernel points.
template <class K> std::vector<Polyline<K>> to_kernel(const std::vector<std::vector<Point3d>>& polylines);
template <class K> std::vector<std::vector<Point3d>> to_doubles(const std::vector<Polyline<K>>& polylines);

}  // namespace seam
