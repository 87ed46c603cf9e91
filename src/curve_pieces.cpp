// The curves of several pairs cut into pieces that share no segment. See seam/internal/curve_pieces.h.
// SPDX-License-Identifier: GPL-3.0-or-later
#include <seam/internal/curve_pieces.h>

#include <algorithm>
#include <map>
#include <utility>

namespace seam::internal {

namespace {

using SegmentKey = std::pair<int, int>;  // point ids, smaller first
SegmentKey key_of(int x, int y) { return {std::min(x, y), std::max(x, y)}; }
using Covering = std::map<SegmentKey, std::vector<std::pair<std::size_t, std::size_t>>>;  // (pair, curve)s

/// Where a curve that shares segments with others is cut into pieces (the indices of the pieces'
/// first segments, ascending): where the curves running along its segments change (so where the
/// tows holding them may change, and where another curve joins, leaves or ends), so that every
/// curve along a stretch is cut at the same points. A closed curve with no such place is cut at
/// its smallest point, the same in every curve that runs along it. `ids`: the curve's point ids.
template <class K, class Less>
std::vector<std::size_t> piece_starts(const Polyline<K>& curve, const std::vector<int>& ids, const Covering& covering,
                                      const Less& less) {
  const bool closed = is_closed(curve);
  const std::size_t n = closed ? curve.size() - 1 : curve.size();  // distinct points
  const std::size_t segments = closed ? n : n - 1;
  auto curves_along = [&](std::size_t s) -> const std::vector<std::pair<std::size_t, std::size_t>>& {
    const auto it = covering.find(key_of(ids[s % n], ids[(s + 1) % n]));
    if (it == covering.end()) throw InternalError("textile: a curve segment is missing from the curves along it");
    return it->second;
  };
  std::vector<std::size_t> starts;
  for (std::size_t s = 0; s < segments; ++s)
    if ((s == 0 && !closed) || curves_along(s) != curves_along((s + segments - 1) % segments)) starts.push_back(s);
  if (starts.empty()) {
    std::size_t smallest = 0;
    for (std::size_t i = 1; i < n; ++i)
      if (less(curve[i], curve[smallest])) smallest = i;
    starts.push_back(smallest);
  }
  return starts;
}

}  // namespace

template <class K> CurvePieces<K> cut_into_pieces(const std::vector<PairCurveRefs<K>>& pairs, std::size_t tows) {
  using Point = typename K::Point_3;
  using V = typename Mesh<K>::Vertex_index;
  auto less = [](const Point& x, const Point& y) { return CGAL::compare_xyz(x, y) == CGAL::SMALLER; };
  std::map<Point, int, decltype(less)> ids(less);
  // Every curve's point ids, and every segment's tows (sorted) and number of curves.
  std::vector<std::vector<std::vector<int>>> id(pairs.size());
  std::map<SegmentKey, std::vector<std::size_t>> holders;
  Covering covering;
  std::map<SegmentKey, int> curves_of;
  for (std::size_t p = 0; p < pairs.size(); ++p)
    for (std::size_t c = 0; c < pairs[p].curves->size(); ++c) {
      const auto& curve = (*pairs[p].curves)[c];
      auto& ci = id[p].emplace_back();
      for (const Point& x : curve) ci.push_back(ids.emplace(x, int(ids.size())).first->second);
      for (std::size_t i = 0; i + 1 < ci.size(); ++i) {
        const SegmentKey k = key_of(ci[i], ci[i + 1]);
        ++curves_of[k];
        covering[k].emplace_back(p, c);
        auto& h = holders[k];
        for (const std::size_t tow : {pairs[p].a, pairs[p].b})
          if (!std::binary_search(h.begin(), h.end(), tow)) h.insert(std::upper_bound(h.begin(), h.end(), tow), tow);
      }
    }
  CurvePieces<K> out;
  for (const auto& [k, n] : curves_of) out.shared_segments += n > 1 ? 1 : 0;
  out.shared.vertices.resize(tows);
  out.uses.resize(pairs.size());
  out.whole.resize(pairs.size());
  std::vector<std::vector<int>> piece_ids;  // per piece, its point ids
  std::map<SegmentKey, std::size_t> piece_of;  // every segment of a cut curve -> its piece

  auto new_piece = [&](Polyline<K> points, std::vector<int> pids) {
    const std::size_t piece = out.shared.curves.size();
    out.shared.curves.push_back(std::move(points));
    for (std::size_t t = 0; t < tows; ++t) out.shared.vertices[t].emplace_back();
    for (std::size_t i = 0; i + 1 < pids.size(); ++i) piece_of[key_of(pids[i], pids[i + 1])] = piece;
    piece_ids.push_back(std::move(pids));
    return piece;
  };

  for (std::size_t p = 0; p < pairs.size(); ++p) {
    const auto& refs = pairs[p];
    for (std::size_t c = 0; c < refs.curves->size(); ++c) {
      const Polyline<K>& curve = (*refs.curves)[c];
      const std::vector<int>& ci = id[p][c];
      const auto& va = (*refs.vertices_a)[c];
      const auto& vb = (*refs.vertices_b)[c];
      bool shares = false;
      for (std::size_t i = 0; i + 1 < ci.size() && !shares; ++i) shares = curves_of[key_of(ci[i], ci[i + 1])] > 1;
      if (!shares) {  // one piece: the curve as it is
        const std::size_t piece = out.shared.curves.size();
        out.shared.curves.push_back(curve);
        for (std::size_t t = 0; t < tows; ++t)
          out.shared.vertices[t].push_back(t == refs.a ? va : t == refs.b ? vb : std::vector<V>{});
        piece_ids.push_back(ci);
        out.uses[p].push_back({{piece, false}});
        out.whole[p].push_back(1);
        continue;
      }
      const bool closed = is_closed(curve);
      const std::size_t n = closed ? curve.size() - 1 : curve.size();  // distinct points
      const std::size_t segments = closed ? n : n - 1;
      const std::vector<std::size_t> starts = piece_starts<K>(curve, ci, covering, less);
      out.whole[p].push_back(0);
      auto& uses = out.uses[p].emplace_back();
      for (std::size_t k = 0; k < starts.size(); ++k) {
        const std::size_t from = starts[k];
        std::size_t to = k + 1 < starts.size() ? starts[k + 1] : (closed ? starts[0] + n : segments);
        if (to <= from) to += n;
        // Points from..to (indices mod n), and their vertices in this pair's tows.
        Polyline<K> points;
        std::vector<int> pids;
        std::vector<V> in_a, in_b;
        for (std::size_t i = from; i <= to; ++i) {
          points.push_back(curve[i % n]);
          pids.push_back(ci[i % n]);
          in_a.push_back(va[i % n]);
          in_b.push_back(vb[i % n]);
        }
        const auto found = piece_of.find(key_of(pids[0], pids[1]));
        std::size_t piece;
        bool reversed = false;
        if (found == piece_of.end()) {
          piece = new_piece(std::move(points), pids);
        } else {
          piece = found->second;
          const auto& known = piece_ids[piece];
          reversed = !(known == pids);
          if (reversed && !std::equal(known.begin(), known.end(), pids.rbegin(), pids.rend()))
            throw InternalError("textile: two curves share segments but not as one stretch");
        }
        if (reversed) {
          std::reverse(in_a.begin(), in_a.end());
          std::reverse(in_b.begin(), in_b.end());
        }
        for (const std::size_t tow : {refs.a, refs.b}) {
          auto& vs = out.shared.vertices[tow][piece];
          const auto& mine = tow == refs.a ? in_a : in_b;
          if (vs.empty()) vs = mine;
          else if (vs != mine) throw InternalError("textile: a curve stretch has two vertex lists in one tow");
        }
        uses.push_back({piece, reversed});
      }
    }
  }
  // Every tow holding a segment of a piece holds the piece.
  for (std::size_t piece = 0; piece < piece_ids.size(); ++piece) {
    const auto& pids = piece_ids[piece];
    if (pids.size() < 2) continue;
    for (const std::size_t tow : holders[key_of(pids[0], pids[1])])
      if (out.shared.vertices[tow][piece].size() != pids.size())
        throw InternalError("textile: a curve stretch lacks its vertices in a tow holding it");
  }
  return out;
}

template <class K> void join_pieces(const CurvePieces<K>& pieces, const std::vector<PairCurveRefs<K>>& pairs) {
  using V = typename Mesh<K>::Vertex_index;
  for (std::size_t p = 0; p < pairs.size(); ++p) {
    const auto& refs = pairs[p];
    for (std::size_t c = 0; c < refs.curves->size(); ++c) {
      const bool closed = is_closed((*refs.curves)[c]);
      Polyline<K> points;
      std::vector<V> in_a, in_b;
      for (const auto& use : pieces.uses[p][c]) {
        Polyline<K> piece = pieces.shared.curves[use.piece];
        std::vector<V> pa = pieces.shared.vertices[refs.a][use.piece], pb = pieces.shared.vertices[refs.b][use.piece];
        if (use.reversed) {
          std::reverse(piece.begin(), piece.end());
          std::reverse(pa.begin(), pa.end());
          std::reverse(pb.begin(), pb.end());
        }
        const std::size_t skip = points.empty() ? 0 : 1;
        if (skip && (piece.empty() || !(points.back() == piece.front())))
          throw InternalError("textile: the quality stage moved a place where two curves part");
        points.insert(points.end(), piece.begin() + std::ptrdiff_t(skip), piece.end());
        in_a.insert(in_a.end(), pa.begin() + std::ptrdiff_t(skip), pa.end());
        in_b.insert(in_b.end(), pb.begin() + std::ptrdiff_t(skip), pb.end());
      }
      if (closed && (points.size() < 2 || !(points.front() == points.back())))
        throw InternalError("textile: a closed curve did not close again from its pieces");
      // A closed curve cut into pieces starts where it did, if that point is still on it.
      if (closed && !pieces.whole[p][c]) {
        const auto& first = (*refs.curves)[c].front();
        const auto at = std::find(points.begin(), points.end() - 1, first);
        if (at != points.end() - 1 && at != points.begin()) {
          const auto k = at - points.begin();
          auto rotate = [k](auto& list) {
            list.pop_back();  // the repeated first point
            std::rotate(list.begin(), list.begin() + k, list.end());
            list.push_back(list.front());
          };
          rotate(points);
          rotate(in_a);
          rotate(in_b);
        }
      }
      (*refs.curves)[c] = std::move(points);
      (*refs.vertices_a)[c] = std::move(in_a);
      (*refs.vertices_b)[c] = std::move(in_b);
    }
  }
}

#define SEAM_INSTANTIATE(K)                                                                                 \
  template CurvePieces<K> cut_into_pieces<K>(const std::vector<PairCurveRefs<K>>&, std::size_t);           \
  template void join_pieces<K>(const CurvePieces<K>&, const std::vector<PairCurveRefs<K>>&);
SEAM_INSTANTIATE(Exact)
SEAM_INSTANTIATE(Filtered)
SEAM_INSTANTIATE(Float)
#undef SEAM_INSTANTIATE

}  // namespace seam::internal
