// seam::resolve: the overlap of two conforming tows given to one of them, so that they no longer
// overlap and touch along a shared contact surface (`seam resolve`).
//
// Input: A2 and B2 as seam::pair writes them: closed triangle meshes whose intersection curves
// are embedded in both (every curve point a vertex of both with identical coordinates, every curve
// segment an edge of both), flat contacts one common triangulation (shared faces), and no other
// contact between them. The "curves" are read off the meshes: an edge of A2 whose two ends are
// vertices of B2 and which is an edge of B2 too is shared; a face whose three corners are a face of
// the other is shared (in the same or the opposite orientation).
//
// Method (src/resolve.cpp):
//   1. validate  A2 and B2 closed, and seam::check_pair's checks 1-3 on them with the shared
//                edges as curves (valid meshes, no self-intersection, meeting only along shared
//                edges, shared vertices and shared faces). Anything else: InvalidInput ("not
//                conforming: run seam pair first").
//   2. patches   the shared edges cut each mesh into patches: the components of its non-shared
//                faces, joined across non-shared edges. A patch meets the other surface only on its
//                border, so all of it lies on one side of the other surface.
//   3. classify  one exact test per patch: the centroid of one of its faces (exact, strictly inside
//                the face) against the other closed surface (CGAL::Side_of_triangle_mesh under
//                the exact kernel, whatever K). ON_BOUNDARY is impossible for conforming inputs
//                and is reported as InvalidInput. A shared face is classified by orientation: in
//                the opposite orientation the two volumes lie on either side of it (the tows
//                touch there: it is contact); in the same orientation they lie on the same side
//                (they overlap behind it).
//   4. volumes   exact signed volumes (sums of det(p, q, r) / 6 over faces, in exact rationals)
//                of A2, B2 and of the overlap A2 ∩ B2, whose boundary is A2's faces inside B2,
//                B2's faces inside A2 and the same-orientation shared faces (once).
//   5. build     the keeper stays whole; the loser L becomes the regularised difference L − keeper:
//                L's faces outside the keeper, L's opposite-orientation shared faces, and the
//                keeper's faces inside L, reversed; L's same-orientation shared faces and its faces
//                inside the keeper are dropped. Every vertex of the result is a vertex of A2 or B2
//                (no point is constructed: the outputs have the inputs' coordinates bit for bit).
//                The result must be a closed 2-manifold (every edge in exactly two faces, in
//                opposite directions; every vertex one fan) and not empty, else InvalidInput says
//                where (a pinch where two curves touch, say, or the loser inside the keeper).
//
// Guarantees, for inputs that pass step 1: the two outputs are closed 2-manifolds; they meet only
// in the contact surface (the keeper's faces that were inside the loser plus the opposite-
// orientation shared faces: faces of both outputs with the same three vertices, opposite
// orientations) and along the curves; their interiors are disjoint; vol(A3) + vol(B3) =
// vol(A2 ∪ B2) = vol(A2) + vol(B2) − overlap, exactly (the reported doubles are the exact values
// rounded). seam::check_resolved verifies such a pair independently.
//
// Kernels: every decision (point equality, side tests, orientations) and every volume is exact
// under all three kernels: the meshes are converted to the exact kernel for steps 1-4 (their
// points are doubles under Filtered and Float, so the conversion is exact). K only sets the type
// of the meshes.
//
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <seam/kernels.h>
#include <seam/types.h>

#include <cstddef>
#include <map>
#include <string>
#include <utility>
#include <vector>

namespace seam {

/// Which tow keeps the overlap (stays whole); the other loses it.
enum class Keeper {
  a,
  b,
  /// The tow that would lose the larger fraction of its volume keeps the overlap: the overlap
  /// goes to the smaller tow (exact comparison of the volumes; A on a tie), so that the tow that
  /// gives it up loses the smaller fraction of its own volume (overlap / volume). If giving the
  /// overlap up would leave nothing of that tow (it lies inside the other), the other is chosen.
  automatic
};

/// "a", "b" or "auto".
const char* keeper_name(Keeper k);

struct ResolveOptions {
  Keeper keeper = Keeper::automatic;
  /// Step 1 (seam::check_pair's checks 1-3 on the inputs). Off only when the caller has checked
  /// them already (seam::pair's verified outputs): wrong inputs then give wrong outputs.
  bool validate_input = true;
  /// Names for messages ("tow_a.off").
  std::string name_a = "A", name_b = "B";
};

struct ResolveStats {
  Keeper keeper = Keeper::a;  ///< a or b: the tow that kept the overlap (its mesh is unchanged)
  /// Exact volumes, rounded to doubles: before (A2, B2) and after (A3, B3), and of A2 ∩ B2.
  double volume_a_before = 0, volume_b_before = 0, volume_a_after = 0, volume_b_after = 0;
  double overlap_volume = 0;
  /// Faces of both outputs (the same three vertices): the shared contact surface.
  std::size_t contact_faces = 0;
  /// Edges and faces shared by the inputs; of the faces, those in the same orientation (the tows
  /// overlap behind them: dropped from the loser).
  std::size_t shared_edges = 0, shared_faces = 0, shared_faces_same_orientation = 0;
  /// Patches of each input (step 2) and those inside the other tow.
  std::size_t patches_a = 0, patches_b = 0, patches_a_inside = 0, patches_b_inside = 0;
  /// The loser's faces removed (inside the keeper, or shared in the same orientation) and the
  /// keeper's faces added to it (reversed).
  std::size_t faces_removed = 0, faces_added = 0;
  std::string note;  ///< a sentence for the report (no overlap, nested tows, ...)
  std::map<std::string, double> stage_seconds;  ///< validate, classify, volumes, build
};

/// Gives the overlap of `a` and `b` to one of them (options.keeper); the other is replaced by its
/// part outside the keeper. See the header comment.
/// \pre a and b are closed, conforming triangle meshes (checked when options.validate_input).
/// Throws InvalidInput (not closed, not conforming, a result that would not be a closed
/// 2-manifold or would be empty), InternalError; on a throw `a` and `b` are unchanged.
template <class K> ResolveStats resolve(Mesh<K>& a, Mesh<K>& b, const ResolveOptions& options = {});

/// The independent check of a resolved pair (shares no code with seam::resolve): both meshes
/// non-empty and closed; seam::check_pair's checks 1-3 with the shared edges (and lone shared
/// vertices) as the curves: valid triangle meshes without self-intersection that meet only along
/// shared edges, shared vertices and shared faces (exact predicates); every shared face in
/// opposite orientations in the two; and every connected piece of each mesh's non-shared faces
/// (joined across non-shared edges) strictly outside the other mesh (one exact side test of one
/// face's centroid per piece, CGAL::Side_of_triangle_mesh under the exact kernel). Together: two
/// closed surfaces with disjoint interiors that touch only on shared faces, edges and vertices.
struct ResolvedCheckReport {
  std::vector<std::string> problems;  ///< empty when every check holds
  std::size_t shared_faces = 0, shared_edges = 0, pieces_a = 0, pieces_b = 0;
  bool ok() const { return problems.empty(); }
};
/// Every decision exact under every kernel (the meshes are converted to the exact kernel).
template <class K> ResolvedCheckReport check_resolved(const Mesh<K>& a3, const Mesh<K>& b3);

/// A whole textile (`seam textile --resolve`): the overlap of each pair (i, j) of `pairs` (the
/// intersecting pairs of seam::textile, say) given to one of its two tows, pair by pair in the
/// order given, each as seam::resolve with `keeper` (automatic: the smaller tow keeps it). A tow
/// only shrinks (loser minus keeper), so pairs made disjoint stay disjoint, and the faces a loser
/// takes from its keeper carry the keeper's curves with the other tows, so the later pairs are
/// still conforming. Then every pair is checked with seam::check_resolved. `names` name the tows
/// in messages (one per tow). Throws InvalidInput naming the pair that seam::resolve refuses,
/// InternalError naming the pair that fails the check; on a throw `tows` are unchanged.
template <class K>
std::vector<ResolveStats> resolve_pairs(std::vector<Mesh<K>>& tows,
                                        const std::vector<std::pair<std::size_t, std::size_t>>& pairs,
                                        const std::vector<std::string>& names, Keeper keeper = Keeper::automatic);

}  // namespace seam
