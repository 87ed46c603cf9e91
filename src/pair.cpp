// seam::pair: two tows, one interface. See seam/pair.h.
// SPDX-License-Identifier: GPL-3.0-or-later
#include <seam/io.h>
#include <seam/internal/bbox_diagonal.h>
#include <seam/internal/flat_contacts.h>
#include <seam/internal/collapse.h>
#include <seam/internal/contact_points.h>
#include <seam/internal/embed_known_sites.h>
#include <seam/internal/intersection_curves.h>
#include <seam/internal/improve_state.h>
#include <seam/internal/local_edits.h>
#include <seam/internal/message.h>
#include <seam/internal/new_face_figures.h>
#include <seam/internal/snap.h>
#include <seam/internal/verify_output.h>
#include <seam/quality.h>
#include <seam/check.h>
#include <seam/pair.h>

#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <exception>
#include <map>
#include <new>
#include <optional>
#include <set>
#include <sstream>

namespace seam {

namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

/// The quality stage's options in a pair run: options.quality, with the angle bound and the area
/// bound of options.embed and the given tolerance (improve_pair adds the vertex separation).
ImproveOptions stage_options(const PairOptions& options, double tolerance) {
  ImproveOptions io = options.quality;
  io.tolerance = tolerance;
  io.min_angle_deg = options.embed.min_angle_deg;
  io.max_area = options.embed.max_area;
  return io;
}

/// The curve counts of a result from its curves.
template <class K> void count_curves(PairResult<K>& result) {
  auto& st = result.stats;
  st.curves = result.curves.size();
  st.closed_curves = st.curve_vertices = 0;
  for (const auto& c : result.curves) {
    const bool closed = is_closed(c);
    st.closed_curves += closed ? 1 : 0;
    st.curve_vertices += closed ? c.size() - 1 : c.size();
  }
}

/// The per-mesh figures (sizes, new faces and their angles) from the meshes as they are;
/// `input_angles` holds the smallest angle of each input face of A and of B (the faces'
/// source_face_property), for the count of new faces below 10 degrees their input face does not
/// force.
template <class K>
void measure_meshes(const Mesh<K>& a, const Mesh<K>& b, PairResult<K>& result, double max_area,
                    const std::array<std::vector<double>, 2>& input_angles) {
  for (auto* r : {&result.a, &result.b}) {
    const Mesh<K>& m = r == &result.a ? a : b;
    const auto q = new_face_quality<K>(m, &input_angles[r == &result.a ? 0 : 1], max_area);
    internal::record_new_face_figures(q, r->stats);
    r->stats.new_faces_below_10_unforced = q.below_10_unforced;
    r->curves = result.curves;
    r->stats.output_vertices = m.number_of_vertices();
    r->stats.output_faces = m.number_of_faces();
    r->stats.faces_added = q.new_faces;
    r->stats.curve_nodes_out = result.stats.curve_vertices;
  }
}

/// Which features thinner than the vertex separation stages 1-3 close (a vertex of one mesh that
/// close to the other surface: a crossing as thin as that cannot be written in doubles, nor
/// meshed by TetGen): the vertices within the separation of a curve and
///   - crowded: of a curve point with a vertex or another curve point within the separation
///     (internal::crowded_curve_points: embedded, those would be a pair of vertices too close);
///   - none: no vertex (where the crowded way closed some and its outputs failed);
///   - near_close_pairs: of a point of the pairs too close in outputs verified before, or corners
///     of a face that is;
///   - all: every one.
enum class Closing { crowded, none, near_close_pairs, all };

/// Stages 1-3 of seam::pair: the exact intersection curves, embedded into both meshes (at once),
/// and the isolated points of contact made vertices of both. The features thinner than
/// `separation` that `closing` says (with `close_points`, the points of near_close_pairs) are
/// first closed: such vertices move onto the curve there (exactly), and the curves are computed
/// again. A vertex of a flat contact stays, and so does one whose move would take a part of the
/// intersection farther than `tolerance` (see snap_vertices_to_segments).
template <class K>
PairResult<K> embed_into_both(Mesh<K>& a, Mesh<K>& b, const PairOptions& options, Closing closing,
                              double separation, double tolerance,
                              const std::vector<std::array<double, 3>>& close_points,
                              std::vector<std::pair<int, std::size_t>>* closed) {
  PairResult<K> result;
  PairStats& st = result.stats;
  auto t = Clock::now();
  auto found = internal::compute_intersection_curves<K>(a, b);
  std::vector<std::array<double, 3>> crowded;
  if (closing == Closing::crowded && !found.curves.empty())
    crowded = internal::crowded_curve_points<K>(found.curves, a, b, separation);
  const std::vector<std::array<double, 3>>* near = closing == Closing::crowded           ? &crowded
                                                   : closing == Closing::near_close_pairs ? &close_points
                                                                                         : nullptr;
  if (!found.curves.empty() && closing != Closing::none && !(near && near->empty())) {
    const auto& curves = found.curves;
    const auto sa = internal::snap_vertices_to_segments<K>(a, curves, separation, false, true, &b, near, tolerance);
    const auto sb = internal::snap_vertices_to_segments<K>(b, curves, separation, false, true, &a, near, tolerance);
    st.vertices_closed = sa.snapped + sb.snapped;
    if (closed) {  // (mesh, vertex) of each vertex closed, sorted
      for (auto v : sa.moved) closed->emplace_back(0, std::size_t(v));
      for (auto v : sb.moved) closed->emplace_back(1, std::size_t(v));
      std::sort(closed->begin(), closed->end());
    }
    st.max_close_move = std::max(sa.max_move, sb.max_move);
    // Under the exact kernel the vertices moved exactly onto the curves, which lie on both
    // surfaces (under the others, onto the curves rounded).
    if (st.vertices_closed > 0)
      found = internal::compute_intersection_curves<K>(a, b, /*known_degenerate=*/kernel_traits<K>::exact_constructions);
  }
  const std::size_t touching = found.touching_points;
  const auto& curves = found.curves;
  auto& sites_a = found.sites_a;
  auto& sites_b = found.sites_b;
  const auto& contacts = found.contacts;
  st.curve_ends = found.ends;
  st.stage_seconds["intersect"] = seconds_since(t);
  if (curves.empty())
    st.note = touching > 0 ? "the meshes touch without crossing: the points of contact are made vertices of both"
                           : "the meshes do not intersect (disjoint, or one inside the other): nothing to embed";
  st.touching_only = curves.empty() && touching > 0;
  // The two embeddings run concurrently where they share nothing that changes: the curve points
  // (read by both) and every vertex that is not a double (a caller's meshes may share lazy
  // numbers) are made exact first, so that neither embedding refines a shared number in the
  // threads' order (that made the outputs differ from run to run at stop 37: the roundings taken
  // later are the middles of the interval approximations). An error is reported as if they had
  // run one after the other: A's first. Under an area bound they do run one after the other
  // (below: each keeps its Steiner points away from the other's).
  EmbedOptions eo = options.embed;
  eo.snap_tol = 0;
  eo.keep_all_nodes = true;
  eo.curve_tol = 0;
  eo.max_distance = std::numeric_limits<double>::max();  // the points lie on both surfaces
  double seconds_a = 0, seconds_b = 0;
  if (eo.max_area > 0 && !curves.empty()) {
    // An area bound keeps every Steiner point the re-triangulation inserts; where it cascades
    // into a tiny spot (a grazing crossing) points came 2e-7 apart, and near a curve the two
    // surfaces are close too: closer than the vertex separation, a volume mesher takes two
    // points for one. So one mesh after the other, each Steiner point kept that far from every
    // vertex of both meshes, the curve points and the Steiner points before it.
    internal::KeepAway away(min_vertex_separation * internal::bbox_diagonal<K>(a, b));
    away.add_vertices<K>(a);
    away.add_vertices<K>(b);
    away.add_points<K>(curves);
    // ... and from the other surface (see KeepAway::set_surfaces).
    const auto surface_a = internal::input_surface<K>(a), surface_b = internal::input_surface<K>(b);
    auto ta = Clock::now();
    away.set_surfaces({surface_b.get()});
    result.a = internal::embed_with_known_sites<K>(a, curves, eo, &sites_a, &away);
    seconds_a = seconds_since(ta);
    ta = Clock::now();
    away.set_surfaces({surface_a.get()});
    result.b = internal::embed_with_known_sites<K>(b, curves, eo, &sites_b, &away);
    seconds_b = seconds_since(ta);
  } else {
    for (auto& curve : found.curves)
      for (auto& p : curve) fix_rounding(p);
    for (Mesh<K>* m : {&a, &b})
      for (auto v : m->vertices()) fix_rounding(m->point(v));
    std::exception_ptr failed_a, failed_b;
    auto embed_one = [&](Mesh<K>& m, const internal::KnownSites<K>& sites, EmbedResult<K>& out, double& seconds,
                         std::exception_ptr& failed) {
      try {
        const auto t0 = Clock::now();
        out = internal::embed_with_known_sites<K>(m, curves, eo, &sites);
        seconds = seconds_since(t0);
      } catch (...) {
        failed = std::current_exception();
      }
    };
    tbb::parallel_invoke([&] { embed_one(a, sites_a, result.a, seconds_a, failed_a); },
                         [&] { embed_one(b, sites_b, result.b, seconds_b, failed_b); });
    if (failed_a) std::rethrow_exception(failed_a);
    if (failed_b) std::rethrow_exception(failed_b);
  }
  st.stage_seconds["embed_a"] = seconds_a;
  st.stage_seconds["embed_b"] = seconds_b;
  if (result.a.curves != result.b.curves) throw InternalError("pair: the two meshes received different curves");
  result.curves = result.a.curves;
  // Isolated points of contact: a vertex of both, and a curve of one point (see
  // internal/contact_points.h). Under the rounded kernels a point off the faces of either mesh
  // leaves both as they were (the verification then fails and says so).
  if (!contacts.empty()) {
    std::vector<typename Mesh<K>::Vertex_index> va, vb;
    if (internal::insert_points<K>(a, b, contacts, va, vb)) {
      for (std::size_t i = 0; i < contacts.size(); ++i) {
        result.curves.push_back({contacts[i]});
        result.a.curve_vertices.push_back({va[i]});
        result.b.curve_vertices.push_back({vb[i]});
      }
      st.contact_points = contacts.size();
    }
  }
  count_curves(result);
  return result;
}

/// Curve segments and edges next to the curves shorter than `length` collapse in both meshes (see
/// internal/collapse.h): written in doubles, their faces would be flat, and TetGen merges points
/// that close.
template <class K> void collapse_tiny_edges(Mesh<K>& a, Mesh<K>& b, PairResult<K>& result, double length) {
  if (result.curves.empty()) return;
  const auto t = Clock::now();
  const auto cr = internal::collapse_short_curve_segments<K>(a, b, result.curves, result.a.curve_vertices,
                                                             result.b.curve_vertices, 0.0, length, 0, 0, {}, 0, true);
  auto& st = result.stats;
  st.tiny_edges_collapsed += cr.tiny_edges_collapsed;
  st.curve_vertices_collapsed += cr.collapsed;
  if (cr.collapsed + cr.tiny_edges_collapsed > 0) count_curves(result);
  st.stage_seconds["separate"] += seconds_since(t);
}

/// A curve point repeated at two consecutive positions (the same vertex in both meshes: a
/// segment of zero length, which seam check refuses) is kept once: the curve's geometry and its
/// edges are the same. Seen after stage 5's collapses on CT row 10 (docs/real_tows.md), where a
/// curve passes twice through a point.
template <class K> void drop_repeated_curve_points(PairResult<K>& result) {
  bool dropped = false;
  for (std::size_t c = 0; c < result.curves.size(); ++c) {
    auto& curve = result.curves[c];
    auto& va = result.a.curve_vertices[c];
    auto& vb = result.b.curve_vertices[c];
    if (va.size() != curve.size() || vb.size() != curve.size()) continue;
    for (std::size_t i = curve.size(); i-- > 1;)
      if (curve.size() > 2 && curve[i] == curve[i - 1] && va[i] == va[i - 1] && vb[i] == vb[i - 1]) {
        curve.erase(curve.begin() + std::ptrdiff_t(i));
        va.erase(va.begin() + std::ptrdiff_t(i));
        vb.erase(vb.begin() + std::ptrdiff_t(i));
        dropped = true;
      }
  }
  if (dropped) count_curves(result);
}

/// Flat contacts: one common triangulation in both meshes, refined to the angle bound when
/// `min_angle_deg` > 0 (internal/flat_contacts.h); the curves follow.
template <class K>
void unify_contacts(Mesh<K>& a, Mesh<K>& b, PairResult<K>& result, const internal::FlatContactOptions& options) {
  if (result.curves.empty()) return;
  const auto t = Clock::now();
  const auto fc = internal::unify_flat_contacts<K>(
      a, b, {result.curves, result.a.curve_vertices, result.b.curve_vertices}, options);
  result.a.curves = result.b.curves = result.curves;
  if (fc.border_splits > 0) count_curves(result);
  auto& st = result.stats;
  st.contact_patches = fc.patches;
  st.shared_faces = fc.shared_faces;
  st.contact_patches_left = fc.patches_left;
  st.contact_points_inserted = fc.steiner_points;
  st.contact_segments_split = fc.border_splits;
  st.contact_points_dropped = fc.points_dropped;
  st.contact_faces_below_bound = fc.shared_faces_below_bound;
  if (fc.patches_left > 0) internal::append_note(st.note, fc.first_left);
  if (!fc.refinement_failed.empty())
    internal::append_note(st.note, "flat contacts not refined: " + fc.refinement_failed);
  st.stage_seconds["flat_contacts"] = seconds_since(t);
}

}  // namespace

template <class K>
void improve_pair(Mesh<K>& a, Mesh<K>& b, PairResult<K>& result, const PairOptions& options, const Mesh<K>* input_a,
                  const Mesh<K>* input_b) {
  if (result.curves.empty()) return;
  const auto t = Clock::now();
  // The smallest angle of each input face: a face is held to the bound or, where less, to that.
  auto angles_of = [](const Mesh<K>* input) {
    return input ? internal::face_min_angles<K>(*input) : std::vector<double>{};
  };
  const std::vector<double> angles_a = angles_of(input_a), angles_b = angles_of(input_b);
  std::vector<internal::ImproveMesh<K>> meshes{{&a, nullptr, input_a ? &angles_a : nullptr},
                                               {&b, nullptr, input_b ? &angles_b : nullptr}};
  internal::SharedCurves<K> shared{result.curves, {result.a.curve_vertices, result.b.curve_vertices}};
  ImproveOptions io = stage_options(options, result.stats.snap_tol);
  io.min_separation = min_vertex_separation * internal::bbox_diagonal<K>(a, b);
  result.stats.improve = internal::improve<K>(meshes, shared, io);
  result.stats.improved = true;
  result.curves = result.a.curves = result.b.curves = shared.curves;
  result.a.curve_vertices = shared.vertices[0];
  result.b.curve_vertices = shared.vertices[1];
  count_curves(result);
  result.stats.stage_seconds["improve"] = seconds_since(t);
}

namespace {

/// One seam::pair run after its input checks: stages 1-5 on the inputs kept, then stage 6, the
/// verification as written. Outputs that fail it are not given; the run tries the next way (see
/// Closing): the embedded meshes without the quality stage first, then the crowded way's meshes
/// without its closing (if it closed any); then, where the improved outputs failed only on pairs
/// of vertices too close (check 5), the same two with the vertices of those pairs closed, if they
/// lie within the separation of a curve, again while that finds new pairs, at most
/// max_close_pair_rounds times; then with every feature thinner than the separation closed.
/// Each is verified alike.
template <class K> class PairRun {
 public:
  PairRun(Mesh<K>& a, Mesh<K>& b, const PairOptions& options);
  /// The outputs of the first way that passes, in a and b; the inputs back and InternalError when
  /// none does.
  PairResult<K> run();

 private:
  static constexpr int max_close_pair_rounds = 3;
  /// One way: its result when its outputs (improved, or else without the quality stage) pass;
  /// sets next_.
  std::optional<PairResult<K>> attempt(Closing closing);
  /// Stages 1-3 and the flat contacts on the inputs.
  PairResult<K> embedded(Closing closing);
  /// Stage 5 and the figures.
  void finish(PairResult<K>& r);
  /// Stage 6 on a and b; the close pairs of improved outputs are kept (those are the outputs to
  /// mend); the note says which way passed.
  bool passes(PairResult<K>& r, bool improved_outputs, const std::string& way);
  /// Whether the near_close_pairs way has new points to close (and rounds left).
  bool new_close_points();
  void failed(const std::string& what) { problems_ += (problems_.empty() ? "" : "; ") + what + problem_; }

  Mesh<K>& a_;
  Mesh<K>& b_;
  const PairOptions& options_;
  const Mesh<K> a0_, b0_;  // the inputs
  const std::array<std::vector<double>, 2> input_angles_;
  double separation_ = 0, snap_tol_ = 0;
  internal::FlatContactOptions contact_options_;
  std::vector<std::array<double, 3>> close_points_;  // of the pairs every failed way left too close
  std::size_t close_points_used_ = 0;
  int close_pair_rounds_ = 0;
  std::vector<std::pair<int, std::size_t>> closed_vertices_, closed_before_;  // by this way and the last
  Closing next_ = Closing::all;
  std::string problem_, problems_;
};

template <class K>
PairRun<K>::PairRun(Mesh<K>& a, Mesh<K>& b, const PairOptions& options)
    : a_(a), b_(b), options_(options), a0_(a), b0_(b),
      input_angles_{internal::face_min_angles<K>(a0_), internal::face_min_angles<K>(b0_)} {
  separation_ = min_vertex_separation * internal::bbox_diagonal<K>(a, b);
  const double la = mean_edge_length<K>(a), lb = mean_edge_length<K>(b);
  snap_tol_ = options.embed.snap_tol < 0 ? 0.1 * std::min(la, lb) : options.embed.snap_tol;
  // Flat contacts are refined to the quality stage's bound and feature size when that stage runs
  // (it then refines the faces beyond their split borders).
  if (options.improve) {
    contact_options_.min_angle_deg = options.embed.min_angle_deg;
    contact_options_.max_area = options.embed.max_area;
    contact_options_.feature_size =
        internal::feature_size_of(stage_options(options, snap_tol_), snap_tol_, std::min(la, lb));
  }
}

template <class K> PairResult<K> PairRun<K>::embedded(Closing closing) {
  a_ = a0_;
  b_ = b0_;
  closed_before_ = std::move(closed_vertices_);
  closed_vertices_.clear();
  PairResult<K> r =
      embed_into_both<K>(a_, b_, options_, closing, separation_, snap_tol_, close_points_, &closed_vertices_);
  r.stats.snap_tol = snap_tol_;
  unify_contacts<K>(a_, b_, r, contact_options_);
  return r;
}

template <class K> void PairRun<K>::finish(PairResult<K>& r) {
  collapse_tiny_edges<K>(a_, b_, r, separation_);
  drop_repeated_curve_points<K>(r);
  measure_meshes<K>(a_, b_, r, options_.embed.max_area, input_angles_);
}

template <class K> bool PairRun<K>::passes(PairResult<K>& r, bool improved_outputs, const std::string& way) {
  // The verification reads both meshes on two threads, and so does the writer: their points
  // (shared between the meshes and the copies kept for the next way) are made exact first, so
  // that no thread's evaluation changes the roundings another sees (see fix_rounding).
  for (auto v : a_.vertices()) fix_rounding(a_.point(v));
  for (auto v : b_.vertices()) fix_rounding(b_.point(v));
  const bool ok =
      internal::verify_outputs<K>(a0_, b0_, a_, b_, r, problem_, improved_outputs ? &close_points_ : nullptr);
  std::sort(close_points_.begin(), close_points_.end());
  close_points_.erase(std::unique(close_points_.begin(), close_points_.end()), close_points_.end());
  if (!ok) return false;
  if (!problems_.empty())
    internal::append_note(r.stats.note, "seam check failed on (" + problems_ + "): these outputs are " +
                                            (way.empty() ? "" : way + ", ") +
                                            (!improved_outputs ? "the embedded meshes without the quality stage"
                                             : options_.improve ? "improved"
                                                                : "the embedded meshes"));
  return true;
}

template <class K> bool PairRun<K>::new_close_points() {
  if (close_points_.size() == close_points_used_ || close_pair_rounds_ == max_close_pair_rounds) return false;
  close_points_used_ = close_points_.size();
  ++close_pair_rounds_;
  return true;
}

template <class K> std::optional<PairResult<K>> PairRun<K>::attempt(Closing closing) {
  std::string way = closing == Closing::crowded ? ""
                    : closing == Closing::none ? "with no feature closed"
                    : closing == Closing::all  ? "with features thinner than the vertex separation closed"
                                               : internal::say("with the vertices next to ", close_points_.size(),
                                                               " points of too close pairs closed onto the curves");
  auto prefix = [&](const std::string& more) { return way.empty() ? more : way + (more.empty() ? ": " : ", " + more); };
  PairResult<K> result;
  bool embedding_failed = false;
  try {
    result = embedded(closing);
  } catch (const InternalError& e) {  // (a flat contact that does not fit, say): the next way
    problem_ = e.what();
    embedding_failed = true;
  }
  // (after the crowded way: the same without its closing, if it closed any)
  const bool crowded_closed = closing == Closing::crowded && !closed_vertices_.empty();
  next_ = crowded_closed ? Closing::none : Closing::near_close_pairs;
  if (crowded_closed)
    way = internal::say("with ", closed_vertices_.size(),
                        " vertices next to crowded curve points closed onto the curves");
  if (embedding_failed) {
    failed(prefix(""));
    return std::nullopt;
  }
  // The same meshes as a way before (nothing closed, or the same vertices as the way before).
  if ((closing == Closing::near_close_pairs || closing == Closing::all) &&
      (result.stats.vertices_closed == 0 || closed_vertices_ == closed_before_)) {
    next_ = Closing::all;
    return std::nullopt;
  }
  std::optional<std::tuple<Mesh<K>, Mesh<K>, PairResult<K>>> before_improve;
  if (options_.improve && options_.verify_output && !result.curves.empty()) before_improve.emplace(a_, b_, result);
  bool improved = true;  // false: the quality stage stopped (an edit it could not make)
  try {
    if (options_.improve) improve_pair<K>(a_, b_, result, options_, &a0_, &b0_);
  } catch (const InternalError& e) {
    if (!before_improve) throw;
    problem_ = e.what();
    improved = false;
  }
  if (improved) finish(result);
  if (!options_.verify_output) return result;
  if (improved && passes(result, true, way)) return result;
  failed(prefix(""));
  if (before_improve) {
    a_ = std::move(std::get<0>(*before_improve));
    b_ = std::move(std::get<1>(*before_improve));
    result = std::move(std::get<2>(*before_improve));
    finish(result);
    if (passes(result, false, way)) return result;
    failed(prefix("without the quality stage: "));
  }
  return std::nullopt;
}

template <class K> PairResult<K> PairRun<K>::run() {
  for (Closing closing = Closing::crowded;;) {
    if (closing == Closing::near_close_pairs && !new_close_points()) closing = Closing::all;
    if (auto result = attempt(closing)) return std::move(*result);
    if (closing == Closing::all) break;
    closing = next_;
  }
  a_ = a0_;
  b_ = b0_;
  throw InternalError("pair: the outputs fail seam check's tests, so none is given (" + problems_ + ")");
}

}  // namespace

template <class K> PairResult<K> pair(Mesh<K>& a, Mesh<K>& b, const PairOptions& options) {
  check_coordinate_range<K>(a, "A");
  check_coordinate_range<K>(b, "B");
  validate_options(options.embed);
  return PairRun<K>(a, b, options).run();
}

#define SEAM_INSTANTIATE(K)                                                                                   \
  template PairResult<K> pair<K>(Mesh<K>&, Mesh<K>&, const PairOptions&);                                     \
  template void improve_pair<K>(Mesh<K>&, Mesh<K>&, PairResult<K>&, const PairOptions&, const Mesh<K>*,          \
                                const Mesh<K>*);
SEAM_INSTANTIATE(Exact)
SEAM_INSTANTIATE(Filtered)
SEAM_INSTANTIATE(Float)
#undef SEAM_INSTANTIATE

}  // namespace seam
