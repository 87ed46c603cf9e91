// seam internal: the state of the quality stage (seam/improve.h) and the steps that share it.
//
//   src/improve/state.cpp    the state from the meshes and curves; the curves written back
//   src/improve/edit.cpp     edits: a disk of faces replaced by a fan from one point
//   src/improve/accept.cpp   the acceptance predicate of every edit that changes the surface
//   src/improve/refine.cpp   the refinement (flips, merges, moves onto curves, splits, insertions)
//   src/improve/curve_gap.cpp  how close the curves come at each face left below the bound
//
// Curve points are numbered across the meshes: the same point in two meshes is one point (its
// vertex in each). A curve segment is an edge of every mesh that holds its curve.
//
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <seam/improve.h>
#include <seam/internal/face_grid.h>
#include <seam/internal/surface_point.h>

#include <CGAL/Bbox_3.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <functional>
#include <memory>
#include <utility>
#include <optional>
#include <vector>

namespace seam::internal {

/// One mesh given to the quality stage, the input surface its tolerance refers to (null: the mesh
/// as it is given), and the smallest angle of each input face by source_face_property (null: not
/// known; then every face is held to the bound itself).
template <class K> struct ImproveMesh {
  Mesh<K>* mesh = nullptr;
  const Mesh<K>* input = nullptr;
  const std::vector<double>* source_min_angle = nullptr;
};

/// The curves the meshes share: for each curve its points (closed ones repeat the first) and,
/// per mesh, its vertices there (vertices[m][c] is empty when mesh m does not hold curve c).
template <class K> struct SharedCurves {
  std::vector<Polyline<K>> curves;
  std::vector<std::vector<std::vector<typename Mesh<K>::Vertex_index>>> vertices;
};

/// Runs the quality stage (seam/improve.h) on the meshes and updates `curves` (points added by
/// splits and moves, removed by merges; the same in every mesh). Throws InternalError when an
/// edit cannot be made (a bug, not an input property).
template <class K>
ImproveStats improve(std::vector<ImproveMesh<K>>& meshes, SharedCurves<K>& curves, const ImproveOptions& options);

/// For each face of `shortfalls` (faces of `meshes` as they are): Shortfall::curve_gap, the
/// distance (doubles) between the two nearest curve segments of `curves` that share no point and
/// both pass within the face's ball (about its centroid, through its farthest corner) grown by
/// feature_size (of those, the 256 nearest the centroid); infinity where no two do.
/// (src/improve/curve_gap.cpp)
template <class K>
void measure_curve_gaps(const std::vector<ImproveMesh<K>>& meshes, const SharedCurves<K>& curves, double feature_size,
                        std::vector<Shortfall>& shortfalls);

/// The feature size of the quality stage: options.feature_size, or by default the larger of the
/// tolerance and 1/64 of the mean edge length (of the finer mesh); with max_area, at most
/// sqrt(max_area) / 2. (Any triangle larger than max_area has a circumradius of at least
/// 0.87 sqrt(max_area), so its corners are never what refuses its circumcenter for the feature
/// size; other vertices near where the point lands still may.)
inline double feature_size_of(const ImproveOptions& options, double tolerance, double mean_edge) {
  if (options.feature_size >= 0) return options.feature_size;
  const double by_default = std::max(tolerance, mean_edge / 64);
  return options.max_area > 0 ? std::min(by_default, 0.5 * std::sqrt(options.max_area)) : by_default;
}

/// The smallest angle (degrees, doubles) of each face of `input`, by face index: what
/// ImproveMesh::source_min_angle points to.
template <class K> std::vector<double> face_min_angles(const Mesh<K>& input);

/// Distances to an input surface and its normals: an AABB tree on its faces, in doubles.
class InputSurface {
 public:
  explicit InputSurface(std::vector<Filtered::Triangle_3> triangles);
  ~InputSurface();
  InputSurface(const InputSurface&) = delete;
  InputSurface& operator=(const InputSurface&) = delete;
  /// The closest point of the surface, and the unit normal of the face it lies on.
  std::pair<Filtered::Point_3, Filtered::Vector_3> closest(const Filtered::Point_3& p) const;
  /// Whether the point lies within `distance` of the surface (doubles).
  bool within(const Filtered::Point_3& p, double distance) const;
  /// For a new face (p, q, r): whether its corners, edge middles and centroid lie within
  /// `distance` of the surface (a sampled test, not the Hausdorff distance; doubles), and if so
  /// the unit normal of the surface's face closest to its centroid (as `closest` gives it, but
  /// for a tie between faces equally close in doubles, which one is not the same). One tree
  /// query for all: the faces whose boxes come within the distance of the face's box, each
  /// sample then tested on those (which hold every face within the distance of a sample).
  std::optional<Filtered::Vector_3> face_within(const Filtered::Point_3& p, const Filtered::Point_3& q,
                                                const Filtered::Point_3& r, double distance) const;

 private:
  struct Tree;
  std::unique_ptr<Tree> tree_;
};

/// The surface of a mesh as an InputSurface (its faces rounded to doubles).
template <class K> std::unique_ptr<InputSurface> input_surface(const Mesh<K>& mesh);

/// See ImproveState::MeshState::crease_memo.
struct CreaseMemo {
  std::uint32_t version = 0, opposite_version = 0;
  std::int8_t crease = -1;  ///< -1: not known
};

template <class K> struct ImproveState {
  ImproveState() = default;
  /// Not copied: the grid's deferred entries refer to this state (init_state).
  ImproveState(const ImproveState&) = delete;
  ImproveState& operator=(const ImproveState&) = delete;
  using M = Mesh<K>;
  using V = typename M::Vertex_index;
  using H = typename M::Halfedge_index;
  using E = typename M::Edge_index;
  using F = typename M::Face_index;
  using Point = typename K::Point_3;

  struct MeshState {
    M* mesh = nullptr;
    std::unique_ptr<InputSurface> input;
    typename M::template Property_map<V, std::int32_t> point;  ///< curve point id, -1 for others
    /// Made by the stage (an insertion or a split): never merged away, so that no merge undoes an
    /// insertion (the termination argument of seam/improve.h).
    typename M::template Property_map<V, bool> made;
    typename M::template Property_map<F, bool> band;
    typename M::template Property_map<F, std::uint32_t> version;
    typename M::template Property_map<F, std::uint8_t> cause;  ///< 1 + ShortfallCause, 0: none recorded
    typename M::template Property_map<F, std::uint32_t> source;
    typename M::template Property_map<F, bool> is_new;
    typename M::template Property_map<F, bool> shared, frozen;  ///< valid when has_shared / has_frozen
    bool has_shared = false, has_frozen = false;
    const std::vector<double>* source_min_angle = nullptr;
    /// By source face (input face index): how many times the band grew from the band at the start
    /// to reach it. 0: it held a face of the band at the start (crossed by a curve, or touching a
    /// curve point); k: it joined the band as the face beyond a border edge of a face of reach k-1;
    /// unreached (beyond the vector, or 255): not in the band. Faces of reach 0 are held to max_area;
    /// faces of reach up to bound_reach (below) to the angle bound, faces farther
    /// to their input face's smallest angle where that is lower (target_angle; see angle_bound).
    std::vector<std::uint8_t> reach;
    static constexpr std::uint8_t unreached = 255;
    /// The largest reach recorded (farther steps count as this): as bound_reach, no limit.
    static constexpr std::uint8_t no_limit = 254;
    /// The largest reach held to the angle bound in this mesh (ImproveOptions::bound_reach,
    /// automatic resolved; no_limit: none).
    std::uint8_t bound_reach = no_limit;
    std::uint8_t reach_of(F f) const { return source[f] < reach.size() ? reach[source[f]] : unreached; }
    void set_reach(F f, std::uint8_t r) {
      if (reach.size() <= source[f]) reach.resize(std::size_t(source[f]) + 1, unreached);
      reach[source[f]] = std::min(reach[source[f]], r);
    }
    /// Whether face f is held to max_area: made by the stage or the embedding within an input face
    /// of the band at the start.
    bool area_bounded(F f) const { return is_new[f] && reach_of(f) == 0; }
    /// is_crease's last answer per halfedge, valid while both faces keep the versions it was
    /// found for (an exact coplanarity test with no tolerance: costly on curve points).
    mutable typename M::template Property_map<H, CreaseMemo> crease_memo;
  };
  struct CurvePoint {
    Point p;
    std::vector<V> vertex;  ///< per mesh; null where the mesh does not hold it (or it was merged away)
    bool removed = false;
    std::vector<int> nodes;  ///< its positions along the curves
  };
  /// A curve's point at one position along it: a node of a doubly linked list (a point can be
  /// at two positions, where a curve passes through it twice).
  struct CurveNode {
    int point = -1, prev = -1, next = -1;
    int curve = -1;
  };
  struct Curve {
    std::vector<std::size_t> meshes;  ///< the meshes that hold it
    int first = -1;                   ///< a node of it (its first while that is kept)
    bool closed = false;
  };

  std::vector<MeshState> meshes;
  std::vector<CurvePoint> points;
  std::vector<CurveNode> nodes;
  std::vector<Curve> curves;
  /// Each curve segment: (smaller point id, larger) -> the node at its start (whose next is the
  /// node at its other end).
  std::map<std::pair<int, int>, int> segment_node;
  /// Every face's box. Mutable: most faces are deferred (FaceGrid::defer), and a query inserts
  /// those it may find first, which leaves what any query finds the same.
  mutable FaceGrid grid;
  ImproveOptions options;
  double tolerance = 0, feature_size = 0, mean_edge = 0;
  /// The small curves (ImproveOptions::small_curve_limit): their boxes (doubles) and the feature
  /// size at them.
  struct SmallCurve {
    CGAL::Bbox_3 box;
    double size;
  };
  std::vector<SmallCurve> small_curves;
  ImproveStats stats;
  std::size_t insertions_left = 0;
  std::uint32_t last_version = 0;  ///< faces made by an edit are numbered on from it

  // ---- queries (inline: they are used by every step)
  /// The feature size at x: feature_size, or finer near a small curve (graded, see
  /// ImproveOptions::small_curve_limit). Doubles.
  double feature_size_at(const Filtered::Point_3& x) const {
    double size = feature_size;
    for (const SmallCurve& c : small_curves) {
      double d2 = 0;
      for (int i = 0; i < 3; ++i) {
        const double out = std::max({c.box.min(i) - x[i], x[i] - c.box.max(i), 0.0});
        d2 += out * out;
      }
      const double reach = (size - c.size) / options.small_curve_grading;  // beyond: no finer
      if (d2 < reach * reach) size = std::min(size, c.size + options.small_curve_grading * std::sqrt(d2));
    }
    return size;
  }
  M& mesh(std::size_t m) const { return *meshes[m].mesh; }
  Filtered::Point_3 fpoint(std::size_t m, V v) const { return to_filtered(mesh(m).point(v)); }
  std::array<V, 3> corners(std::size_t m, F f) const {
    const auto h = mesh(m).halfedge(f);
    return {mesh(m).source(h), mesh(m).target(h), mesh(m).target(mesh(m).next(h))};
  }
  /// The box of a face, holding it: under Exact, from the interval approximations of its corners
  /// (fpoint's doubles are their midpoints, which may lie outside; FaceGrid's overlap test needs
  /// boxes that hold the exact faces and their roundings).
  /// Whether a grid entry's face is still the face it was made for (not removed, not remade).
  bool is_live(const FaceGrid::Entry& e) const {
    const F f(e.face);
    return !mesh(e.mesh).is_removed(f) && meshes[e.mesh].version[f] == e.version;
  }
  CGAL::Bbox_3 face_box(std::size_t m, F f) const {
    CGAL::Bbox_3 box;
    for (V v : corners(m, f)) box += mesh(m).point(v).bbox();
    return box;
  }
  /// The area of a face (doubles).
  double face_area(std::size_t m, F f) const {
    const auto c = corners(m, f);
    const Filtered::Point_3 p = fpoint(m, c[0]), q = fpoint(m, c[1]), r = fpoint(m, c[2]);
    return 0.5 * std::sqrt(CGAL::cross_product(q - p, r - p).squared_length());
  }
  /// The node at the start of segment (a, b) of point ids, or -1.
  int segment_start(int a, int b) const {
    if (a < 0 || b < 0) return -1;
    const auto it = segment_node.find({std::min(a, b), std::max(a, b)});
    return it == segment_node.end() ? -1 : it->second;
  }
  /// The curve holding segment (a, b) of point ids, or -1.
  int curve_of_segment(int a, int b) const {
    const int n = segment_start(a, b);
    return n < 0 ? -1 : nodes[std::size_t(n)].curve;
  }
  /// For segment (u, w): the node of u and its neighbour away from w (-1 at an end), or (-1, -1).
  std::pair<int, int> node_away_from(int u, int w) const {
    const int start = segment_start(u, w);
    if (start < 0) return {-1, -1};
    const CurveNode& n = nodes[std::size_t(start)];
    if (n.point == u) return {start, n.prev};
    return {n.next, nodes[std::size_t(n.next)].next};
  }
  bool holds_curve(std::size_t m, int c) const {
    for (std::size_t x : curves[std::size_t(c)].meshes)
      if (x == m) return true;
    return false;
  }
  /// Edge (u, v) of mesh m is a curve segment.
  bool is_curve_edge(std::size_t m, V u, V v) const {
    const int c = curve_of_segment(meshes[m].point[u], meshes[m].point[v]);
    return c >= 0 && holds_curve(m, c);
  }
  bool face_in_band(std::size_t m, F f) const { return f != M::null_face() && meshes[m].band[f]; }
  /// A crease: an edge of two faces whose flip would move the surface by more than half the
  /// tolerance (by anything at all with no tolerance). The flip's largest move is the distance
  /// between the lines of the edge and of the two opposite corners (the height of their
  /// tetrahedron over that pair of edges): doubles, or an exact coplanarity test with no tolerance.
  bool is_crease(std::size_t m, H h) const {
    const M& g = mesh(m);
    const MeshState& ms = meshes[m];
    const std::uint32_t version = ms.version[g.face(h)], opposite_version = ms.version[g.face(g.opposite(h))];
    CreaseMemo& memo = ms.crease_memo[h];
    if (memo.crease >= 0 && memo.version == version && memo.opposite_version == opposite_version) return memo.crease;
    const bool crease = is_crease_uncached(m, h);
    memo = {version, opposite_version, std::int8_t(crease)};
    return crease;
  }
  bool is_crease_uncached(std::size_t m, H h) const {
    const M& g = mesh(m);
    const V u = g.source(h), v = g.target(h), p = g.target(g.next(h)), q = g.target(g.next(g.opposite(h)));
    if (!(tolerance > 0)) return !CGAL::coplanar(g.point(u), g.point(v), g.point(p), g.point(q));
    // (parallel diagonals: a degenerate quad, which the flip's own tests refuse)
    return flip_moves_surface(fpoint(m, u), fpoint(m, v), fpoint(m, p), fpoint(m, q)).value_or(false);
  }
  /// With a tolerance: whether flipping diagonal uv of the quad (u, v, p, q) to pq moves the
  /// surface by more than half the tolerance (the distance between the diagonals' lines,
  /// doubles); nothing where the diagonals are parallel.
  std::optional<bool> flip_moves_surface(const Filtered::Point_3& u, const Filtered::Point_3& v,
                                         const Filtered::Point_3& p, const Filtered::Point_3& q) const {
    const Filtered::Vector_3 n = CGAL::cross_product(v - u, q - p);
    const double nn = n.squared_length();
    if (!(nn > 0)) return std::nullopt;
    const double d = (p - u) * n;
    return d * d > 0.25 * tolerance * tolerance * nn;
  }
  /// The edge of halfedge h may not be flipped: a curve segment, the band's border or the mesh's,
  /// or a crease (tested last: both faces exist then).
  bool is_constraint(std::size_t m, H h) const {
    const M& g = mesh(m);
    return !face_in_band(m, g.face(h)) || !face_in_band(m, g.face(g.opposite(h))) ||
           is_curve_edge(m, g.source(h), g.target(h)) || is_crease(m, h);
  }
  /// A vertex every face of which is in the band, not a curve point: it may move or go.
  bool is_free(std::size_t m, V v) const {
    const M& g = mesh(m);
    if (meshes[m].point[v] >= 0 || g.is_border(v)) return false;
    for (auto f : CGAL::faces_around_target(g.halfedge(v), g))
      if (!face_in_band(m, f)) return false;
    return true;
  }
  /// Whether the face may join the band: not in it yet, not shared or frozen.
  bool may_join_band(std::size_t m, F f) const;
  /// The angle the input forces on a face: the bound, or its input face's smallest angle where
  /// that is less (a face left below the bound but not below that is reported as input_angle).
  double target_angle(std::size_t m, F f) const {
    const MeshState& ms = meshes[m];
    const std::uint32_t source = ms.source[f];
    if (ms.source_min_angle && source < ms.source_min_angle->size())
      return std::min(options.min_angle_deg, (*ms.source_min_angle)[source]);
    return options.min_angle_deg;
  }
};

/// Smallest angle (degrees) of face f of mesh m, in doubles.
template <class K> double face_min_angle(const ImproveState<K>& s, std::size_t m, typename ImproveState<K>::F f);

/// Builds the state: numbers the curve points, marks the band, fills the grid.
template <class K>
void init_state(ImproveState<K>& s, std::vector<ImproveMesh<K>>& meshes, const SharedCurves<K>& curves,
                const ImproveOptions& options);

/// Collects the meshes' garbage and writes the curves back from the state's points and links.
template <class K> void finish_state(ImproveState<K>& s, SharedCurves<K>& curves);

/// Removes the stage's own properties from the meshes.
template <class K> void drop_state_properties(ImproveState<K>& s);

// ---------------------------------------------------------------- edits (src/improve/edit.cpp)

/// A corner of a new face: an existing vertex, or the new vertex of the edit (`fresh`).
template <class K> struct EditCorner {
  typename Mesh<K>::Vertex_index v;  ///< null for the fresh vertex
  bool fresh = false;
  typename K::Point_3 p = typename K::Point_3(0, 0, 0);
};

/// One mesh's part of an edit: the faces removed (a disk) and the fan that replaces them.
template <class K> struct EditPart {
  std::size_t mesh = 0;
  std::vector<typename Mesh<K>::Face_index> removed;
  std::vector<std::array<EditCorner<K>, 3>> added;
  std::vector<typename Mesh<K>::Face_index> origin;  ///< per added face: the removed face it comes from
};

/// An edit of one or more meshes, made at once. `fresh_point` is the position of the fresh vertex
/// (if any); `fresh_curve_point` true when it becomes a curve point (a split of curve segment
/// (split_a, split_b)); `merged_point` merging into `merged_into` for a merge of curve points
/// (along a segment, or two points of the curves that close). `keeps_surface`: the new faces cover exactly the removed ones (no test of tolerance
/// or crossings is needed, only of shape).
template <class K> struct Edit {
  std::vector<EditPart<K>> parts;
  typename K::Point_3 fresh_point = typename K::Point_3(0, 0, 0);
  bool has_fresh = false;
  bool fresh_curve_point = false;
  int split_a = -1, split_b = -1;        ///< the curve segment a fresh curve point splits
  int merged_point = -1, merged_into = -1;  ///< a curve point merged into its neighbour
  bool keeps_surface = false;
  /// A merge of close curve points (ImproveOptions::min_separation): a new face two of whose
  /// corners are one point once written is not refused for that (another close pair, which the
  /// same step may merge next; if it does not, seam check refuses the output).
  bool coincident_corners_allowed = false;
};

/// The part that replaces `region` (faces of mesh m forming a disk) by the fan from `apex` over
/// the region's border. False (part untouched) when the region is not a disk, the apex is an
/// existing vertex not on its border, or the fan would make an edge the mesh has elsewhere.
/// `split` (for a fresh apex on an edge of the region's border: the mesh's border, say) names that
/// edge's ends; the fan skips it.
template <class K>
bool make_fan(const ImproveState<K>& s, std::size_t m, const std::vector<typename Mesh<K>::Face_index>& region,
              const EditCorner<K>& apex, EditPart<K>& part,
              std::pair<typename Mesh<K>::Vertex_index, typename Mesh<K>::Vertex_index> split = {});

/// What an edit made: the new faces (mesh, face), and per part the fresh vertex (or null).
template <class K> struct Applied {
  std::vector<std::pair<std::size_t, typename Mesh<K>::Face_index>> faces;
  std::vector<typename Mesh<K>::Vertex_index> fresh;
};

/// The links along the curves after a new point x splits segment (a, b) (point ids): in every
/// curve that runs along it, since two curves share a segment where a merge closed a lens between
/// them (before, only the curve that `segment_node` names got x, and the other kept a segment
/// that was no longer an edge).
template <class K> void split_curve_links(ImproveState<K>& s, int a, int b, int x);

/// Makes the edit: removes the faces, adds the fans (a fresh vertex in each mesh of a part),
/// updates curve points and links, marks new faces (band as their origin, new, source of their
/// origin) and puts them in the grid.
template <class K> Applied<K> apply_edit(ImproveState<K>& s, const Edit<K>& edit);

// ---------------------------------------------------------------- acceptance (src/improve/accept.cpp)

/// separation: a fresh point closer than options.min_separation to a vertex of any mesh
/// (a volume mesher takes the two for one point).
enum class Verdict { accepted, tolerance, crossing, shape, separation };

/// The acceptance predicate (seam/improve.h). Counts refusals in s.stats.
template <class K> Verdict accept_edit(ImproveState<K>& s, const Edit<K>& edit);

/// Part of the predicate: the edit removes no curve point's vertex but the merged point's (a
/// curve point inside the region it replaces, other than that one, would lose its vertex in that
/// mesh while its curve still passes there). Combinatorial, exact.
template <class K> bool keeps_curve_points(const ImproveState<K>& s, const Edit<K>& edit);

// ---------------------------------------------------------------- refinement (src/improve/refine.cpp)

}  // namespace seam::internal
