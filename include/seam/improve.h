// seam::improve: the quality stage. One algorithm, one acceptance predicate, a stated bound.
//
// Input: meshes whose shared curves are embedded (every curve point a vertex of each mesh the
// curve belongs to, every curve segment an edge of each). Output: the same invariant, every
// changed face within `tolerance` of its input surface, and a report.
//
// The band. Faces that touch a curve vertex or were made by the embedding, minus faces shared by
// two meshes (flat contacts) and frozen faces. It grows when a new point falls beyond its border
// or encroaches it: the face there joins it (nothing in the surface changes), however far from
// the curves, unless it is shared or frozen. So the band's border is never what holds a face
// below the bound; only curve segments, shared and frozen faces and the mesh's own border are
// fixed. (How far it grows is not bounded by a distance: each face joins at most once, so at
// most the whole mesh.) Every face the stage makes is in the band. Constraints: curve segments
// and the band's border (a mesh's own border included). Old mesh edges inside the band are not
// constraints: grazing crossings stop being forced. Each input face records its reach: 0 in the
// band at the start, k + 1 when it joins from a face of reach k. Beyond `bound_reach`, a face whose
// input face is below the bound is held to that input face's smallest angle instead (on a mesh
// whose faces are mostly below the bound, each face the band reaches would otherwise need the
// next; by default per mesh, see ImproveOptions::bound_reach).
//
// The algorithm: Ruppert's Delaunay refinement, on the surface.
//   0. Curve points closer than `min_separation` merge (the curves may then pass twice through a
//      point); where no edge joins them, the edge between is flipped first, or, where that flip is
//      refused (a lens between two curves), flipped and merged in one edit; a free vertex as
//      close that sits between them goes in the same edit. Then flips (max-min angle: Lawson's
//      flips in the plane) over the band's edges.
//   1. Constraints encroached by a vertex of the band (it sees them at more than 90 degrees) are
//      split at their middle: a curve segment in every mesh holding it (its middle lies on all of
//      their surfaces), a border edge by letting the face beyond join the band.
//   2. Each face below `min_angle_deg`, worst first, then each face larger than `max_area` among
//      those made within the input faces of the band at the start (a face only too large goes
//      to b at once). Faces made within faces that joined the band later are held to the angle
//      bound only: the area bound would refine each face the band reaches, whose border then
//      needs the next face, and the band would spread over the whole mesh.
//      a. an edge of it shorter than `feature_size` goes (never at a vertex the stage made): a free vertex merges into the other end
//         (onto a curve point: the report's snapping of nodes near the curve), or two curve points
//         merge along their segment, in every mesh holding the curve. An edge shorter than
//         `min_separation` whose ends do not merge (the fan would be flat) loses a free end: its
//         star is fanned from another neighbour (still a merge, of an input vertex);
//      b. otherwise Lawson's flip of its longest edge that is no constraint, where it raises the
//         two faces' smallest angle and the predicate accepts it (the face beyond may have joined
//         the band, or changed, since the flips of step 0);
//      c. otherwise Üngör's off-center of the face (on the bisector of its shortest edge, at most
//         as far from it as the apex of a triangle with the bound's angle there; the circumcenter
//         where that is nearer) is found by walking over the surface from the face, each face
//         unfolded into the plane of the last. If the walk meets a constraint, or the point
//         encroaches one, that constraint is split as in 1. Otherwise the point is inserted in the
//         face it lands in (put on the input surface, rounded to doubles; or, if the predicate
//         refuses that, exactly in the face), then Lawson's flips around it (the rounded point
//         and its flips, found first without the predicate, are judged as one edit: the point's
//         fan over the faces the flips remove, every edge they make ending at the point; where
//         that is refused, the point alone, then each flip; splits alike). Where the constraint
//         met cannot be split, for what lies beyond it (a flat contact's shared faces, frozen
//         faces, the mesh's own border; curves_fixed) or for being shorter than twice
//         feature_size, or where the point lands nearer than feature_size to a vertex, points
//         nearer the shortest edge on the same bisector are tried instead (0.7, 0.5 and 0.35 of
//         the distance, not nearer than half the edge x tan(bound), where the new face on that
//         edge has the bound's angles): each lies inside the face's circumcircle, so the face
//         goes as well. At most four tries per attempt.
//      d. where all of c's points lay nearer than feature_size to a vertex: an edge of it shorter
//         than `merge_reach` x feature_size merges as in a, if that raises its smallest angle.
//   Splits and exact insertions keep the surface; flips, merges and rounded insertions change it
//   and pass the acceptance predicate first.
//   The feature size in 1, a, c and d is `feature_size`, except near a small curve: a curve
//   smaller than it across, with no other curve near (two tows that barely overlap make one, far
//   smaller than a face). There it is the curve's size / small_curve_divisions (or half the gap
//   between its sides, but not below its size / small_curve_divisions^2 nor twice
//   min_separation), growing by small_curve_grading per unit of distance up to feature_size: Ruppert's
//   spacing at the local feature size, which such a curve sets by its own size. At the global
//   scale every point near it lies nearer than feature_size to its vertices, and its faces stay
//   slivers from its few points to the corners of the face it lies in.
//
// The acceptance predicate (one, for every edit that changes the surface): the new faces are
// not degenerate (exact), turn less than 80 degrees from their input surface (doubles; not asked
// of a face thinner than `min_separation`, whose normal the rounding decides), lie
// within `tolerance` of it (corners, edge middles and centroid, doubles), and meet no face of any
// mesh except where seam check allows it (exact under the exact and filtered kernels): a common
// vertex or edge of the same mesh, or a curve point or curve segment of another mesh; a new
// point lies at least `min_separation` from every vertex of every mesh (as
// rounded to doubles). An edit that fails it is not made.
//
// Termination. A vertex the stage made (an insertion or a split) is never merged away, so a
// merge removes a vertex of the input or of the embedding: at most as many merges as those
// vertices, and no insertion is undone. Insertions and splits each use one of
// `max_insertions_per_face` x (band faces at the start), plus, with `max_area`, the band's area at
// the start over max_area (n points make about 2n faces); between two changes of the vertices
// flips strictly raise the sorted vector of angles, of which there are finitely many: the stage
// ends. A face left when that budget runs out is reported as `budget`. Why the budget is rarely
// reached: every inserted point lies at least the feature size there from the vertices around
// the face it goes into (tested where it is finally placed: rounded onto the input surface, or
// exactly in the face), and only curve segments at least twice that long are split, so the
// points packed into the band are bounded by its area over about feature_size^2, plus, near each
// small curve (whose scale grows linearly from at least its size / small_curve_divisions^2 and
// twice min_separation), a number that grows with the logarithm of feature_size over that scale
// (a local test: not a proof of spacing from every vertex, which Lawson's flips may join to the
// new point).
//
// The bound. In the plane, Ruppert's algorithm with diametral balls ends with every angle at
// least arcsin(1/(2 sqrt 2)) = 20.7 degrees where the input's angles between constraints are at
// least 60 degrees. Every face of the band is held to `min_angle_deg` (or, beyond `bound_reach`,
// to its input face's smaller angle); every new face of the band
// below it at the end is reported with its cause (ImproveStats::shortfalls):
//   input_angle       it is no worse than the input face it comes from, which is below the bound;
//   constraint_angle  its smallest angle lies between two constraints (two curve segments, a curve
//                     segment and a fixed border, two fixed border edges), or the fix meets a
//                     border that cannot move (a flat contact, a frozen face, the mesh's border);
//   feature_size      the off-center and the nearer points were all refused, the last for lying
//                     closer than feature_size to a vertex or needing a segment shorter than twice
//                     that split, and no edge merged (step d): curves or vertices that close, which
//                     no merge within the tolerance could remove (on CT tows, lenses between two
//                     curves thinner than it, and wedges where two curves meet at a few degrees);
//   tolerance         the edit that would fix it leaves the tolerance;
//   crossing          the edit would make a face meet another surface, or its own, off the curves;
//   shape             the edit would make a degenerate or folded face;
//   budget            max_insertions_per_face ran out;
//   flat_contact      a face of a flat contact's common triangulation (in both meshes: seam pair's
//                     flat contacts), which the stage leaves as it is (not a face of the band).
// Each face reported also carries its curve gap (Shortfall::curve_gap, measured on the output
// after the stage, from its curves and faces alone): how close two curve segments with no common
// point come within feature_size of it. Below feature_size, a face there meets the bound only
// with points closer together than the stage makes (Ruppert's bound needs spacing at the local
// feature size, here the gap): the curves force it at that scale, and a smaller feature_size
// meshes it finer, at more faces. Where the gap is larger, the cause names why the stage stopped.
// A face held to `max_area` and left larger (its refinement was refused: feature_size, a fixed
// constraint, the acceptance predicate, or the budget) is counted in
// ImproveStats::above_max_area_after; the callers' figures (EmbedStats::new_faces_above_max_area)
// count every new face larger, those of the graded zone and of flat contacts included.
//
// What is exact: decisions on intersections and degeneracy use the kernel's predicates (exact
// under Exact and Filtered, on the coordinates as they are); curve splits use the exact middle of
// the segment (on both surfaces under Exact); inserted points are rounded
// to doubles (the predicate checks them), or, if that fails, put exactly on their face. Angles,
// distances and the walk are in doubles.
//
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <seam/kernels.h>
#include <seam/types.h>

#include <cstddef>
#include <limits>
#include <string>
#include <vector>

namespace seam {

struct ImproveOptions {
  /// The angle bound: faces of the band below it are refined (degrees). 20 is the bound
  /// Ruppert's algorithm guarantees in the plane (20.7); higher values need not end before
  /// max_insertions.
  double min_angle_deg = 20.0;
  /// How far a changed face may lie from its input surface (sampled), and how far an edit may
  /// move a vertex. 0: only edits that keep the surface (insertions, splits, coplanar flips),
  /// apart from the merges of curve points closer than min_separation.
  double tolerance = 0.0;
  /// Points closer than this are not made; edges shorter than it are merged where the tolerance
  /// allows (finer near small curves, below). Negative: the larger of `tolerance` and 1/64 of the
  /// mean edge length.
  double feature_size = -1.0;
  /// A curve smaller than this many feature sizes across (the diagonal of its points' box), with
  /// no other curve within max(2, 1 / small_curve_grading) feature sizes, is a small curve: near
  /// it the stage works at a finer scale, its size / small_curve_divisions (or half the gap
  /// between its sides, not below size / small_curve_divisions^2 nor 2 x min_separation), growing
  /// by small_curve_grading per unit of distance from its box up to feature_size (0 or a
  /// grading <= 0 or divisions < 1: no small curves; a graded size, as Ruppert's refinement spaces
  /// points at the local feature size, which an isolated curve sets by its own size). So a curve
  /// much smaller than a face (tows that barely overlap) gets points around it instead of
  /// slivers from its few points to the face's corners. Elsewhere: feature_size.
  double small_curve_limit = 1.0;
  double small_curve_divisions = 4.0;
  double small_curve_grading = 0.5;
  /// Where no point can be inserted for a face below the bound (each lies nearer than
  /// feature_size to a vertex), an edge of it shorter than merge_reach x feature_size merges, if
  /// that raises the face's smallest angle (step 2d). 2: an input vertex left between one and two
  /// feature sizes from a curve point (the snapping missed it) goes, rather than hold a thin face;
  /// the acceptance predicate still holds the merge to the tolerance. 1: only step 2a's merges.
  double merge_reach = 2.0;
  /// Largest area of a face made within the input faces of the band at the start (the faces the
  /// curves cross or touch); larger ones are refined like faces below the angle bound (after
  /// them: worst angle first). 0: no bound.
  double max_area = 0.0;
  /// How far the angle bound holds where the band grows, in steps from the faces the curves cross
  /// or touch (1: the faces beyond their border edges; 2: the faces beyond those). A face the
  /// band reaches farther is held to its input face's smallest angle where that is below the
  /// bound; faces at or above the bound in the input are held to it at any reach. A face below
  /// the bound is mended by splitting its edges, which changes the faces beyond: where those are
  /// below the bound in the input too (an anisotropic mesh, as tows swept with many more sections
  /// than points around), the bound at every reach remeshes each such face connected to the
  /// curves. A small reach keeps the change near the curves at the cost of new faces below the
  /// bound (no worse than their input faces; reported as input_angle). 254 or more: no limit.
  /// Negative (the default): per mesh, no limit where at least half of its input faces meet the
  /// bound (their smallest angle), 1 where most do not (the mesh's own faces are anisotropic; a
  /// mesh with no input angles given: no limit). ImproveStats::bound_reach gives what was used.
  long bound_reach = -1;
  /// At most this many insertions and splits per face of the initial band (and, with max_area,
  /// one more per max_area of the initial band's area).
  std::size_t max_insertions_per_face = 16;
  /// The curves stay as they are: no curve segment is split, no curve point merged along a segment
  /// (given curves, after the meshes moved onto them: every curve point stays on them).
  bool curves_fixed = false;
  /// Curve points closer than this (and joined by an edge in every mesh holding them) merge first,
  /// whatever the tolerance: a volume mesher takes them for one point. 0: none.
  double min_separation = 0;
};

/// Why a face of the band is still below the bound (see the header comment).
enum class ShortfallCause {
  input_angle,
  constraint_angle,
  feature_size,
  tolerance,
  crossing,
  shape,
  budget,
  flat_contact
};
const char* shortfall_cause_name(ShortfallCause cause);

/// A new face below the bound at the end: of the band, or of a flat contact (flat_contact).
struct Shortfall {
  std::size_t mesh = 0;  ///< index of the mesh (0: A, 1: B)
  std::size_t face = 0;  ///< face index in the output mesh
  double min_angle_deg = 0;
  ShortfallCause cause = ShortfallCause::constraint_angle;
  /// For a flat_contact face: why the contact's refinement (internal/flat_contacts.h) left it,
  /// constraint_angle, feature_size, shape or budget as above, or flat_contact where it meets the
  /// bound in the projection that refinement works in. For the others: `cause`.
  ShortfallCause reason = ShortfallCause::constraint_angle;
  /// How close two curve segments with no common point come near the face: the smallest distance
  /// between two such segments both within feature_size of its ball (about its centroid, through
  /// its farthest corner), in doubles; infinity where no two are. Below feature_size: the face
  /// lies where the curves are closer than the stage's scale (see the header comment).
  double curve_gap = std::numeric_limits<double>::infinity();
};

struct ImproveStats {
  std::size_t band_faces = 0;  ///< faces in the band at the start (all meshes)
  /// Edits made: flips, points inserted, curve segments split (in every mesh holding them), edges of
  /// a mesh's border split, merges (short edges removed).
  std::size_t flips = 0, insertions = 0, curve_splits = 0, edge_splits = 0, merges = 0;
  /// Edits the acceptance predicate refused, by reason.
  std::size_t refused_tolerance = 0, refused_crossing = 0, refused_shape = 0, refused_separation = 0;
  std::size_t faces_absorbed = 0;  ///< faces that joined the band
  /// Per mesh: the reach ImproveOptions::bound_reach came to (254: no limit).
  std::vector<std::size_t> bound_reach;
  /// Faces of the band below the bound at the start and at the end.
  std::size_t below_bound_before = 0, below_bound_after = 0;
  double min_angle_deg_before = 0, min_angle_deg_after = 0;  ///< smallest angle in the band
  /// With max_area: the faces held to it (made within the input faces of the band at the start)
  /// left larger (their refinement was refused: feature_size, a fixed constraint, the acceptance
  /// predicate, or the budget). New faces made where the
  /// band grew later are graded to the input's size and not counted here (the callers' figures,
  /// such as EmbedStats::new_faces_above_max_area, count every new face).
  std::size_t above_max_area_after = 0;
  std::vector<Shortfall> shortfalls;  ///< the faces below the bound at the end, with causes
  double feature_size = 0;            ///< the feature size the stage used (ImproveOptions::feature_size)
  std::size_t small_curves = 0;       ///< curves near which it used a finer one (small_curve_limit)
  double seconds = 0;
};

}  // namespace seam
