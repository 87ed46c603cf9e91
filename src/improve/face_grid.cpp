// seam: the quality stage's index of face boxes (see seam/internal/face_grid.h).
// SPDX-License-Identifier: GPL-3.0-or-later

#include <seam/internal/face_grid.h>

#include <algorithm>
#include <cmath>

namespace seam::internal {

namespace {

constexpr double index_limit = 4611686018427387904.0;  // 2^62: cell indices stay well inside int64
constexpr std::int64_t parent_limit = std::int64_t(1) << 61;  // a cell whose children could exist

/// Drops the dead entries of a cell once it has grown to twice its size at its last purge
/// (amortised O(1) liveness tests per insertion).
template <class Cell, class Liveness> void purge_when_grown(Cell& cell, const Liveness* is_live) {
  if (!is_live || cell.items.size() < 2 * cell.size_at_purge + 8) return;
  auto& items = cell.items;
  items.erase(std::remove_if(items.begin(), items.end(), [&](const auto& x) { return !(*is_live)(x.entry); }),
              items.end());
  cell.size_at_purge = items.size();
}

/// floor(x / width) for a power-of-two width (exact), or false where it is not a finite index.
bool cell_index(double x, double width, std::int64_t& index) {
  const double q = std::floor(x / width);
  if (!(std::abs(q) < index_limit)) return false;  // NaN and infinities fail too
  index = std::int64_t(q);
  return true;
}

/// The octant of cell index i within its parent's (see FaceGrid::Cell::child).
template <class Index> std::size_t octant(const Index& i) {
  return std::size_t(i[0] & 1) | std::size_t(i[1] & 1) << 1 | std::size_t(i[2] & 1) << 2;
}

/// floor(i / 2): the index of the cell one level up holding cell i.
std::int64_t parent_index(std::int64_t i) { return i >= 0 ? i / 2 : -((1 - i) / 2); }

}  // namespace

std::size_t FaceGrid::IndexHash::operator()(const Index& i) const {
  std::uint64_t h = 1469598103934665603ULL;
  for (std::int64_t x : i) h = (h ^ std::uint64_t(x)) * 1099511628211ULL;
  return std::size_t(h ^ (h >> 29));
}

FaceGrid::FaceGrid(double typical_width) {
  if (std::isfinite(typical_width) && typical_width > 0) {
    int e = 0;
    std::frexp(typical_width, &e);  // typical_width <= 2^e
    base_ = std::ldexp(1.0, std::clamp(e, -1000, 1000));
  }
}

FaceGrid::Cell& FaceGrid::cell_at(int level, const Index& index) {
  const auto [it, made] = levels_[level].try_emplace(index);
  if (made && level < top_) {
    Index up = index;
    for (auto& x : up) x = parent_index(x);
    cell_at(level + 1, up).child[octant(index)] = &it->second;
  }
  return it->second;
}

void FaceGrid::raise_top(int level) {
  if (top_ < min_level) {
    top_ = level;
    return;
  }
  for (; top_ < level; ++top_) {  // every cell of the top level gets its parent
    Level& up = levels_[top_ + 1];
    for (auto& [index, cell] : levels_[top_]) {
      Index p = index;
      for (auto& x : p) x = parent_index(x);
      up.try_emplace(p).first->second.child[octant(index)] = &cell;
    }
  }
}

void FaceGrid::insert(const Entry& entry, const CGAL::Bbox_3& box, const Liveness* is_live) {
  double width = 0;
  for (int d = 0; d < 3; ++d) width = std::max(width, box.max(d) - box.min(d));
  int level = min_level;
  if (width > 0) {
    int e = 0;
    const double m = std::frexp(width / base_, &e);  // width / base_ = m 2^e, m in [0.5, 1)
    level = std::max(min_level, m == 0.5 ? e - 1 : e);
  }
  Index lo{}, hi{};
  const double cell = std::ldexp(base_, level);
  bool placed = level <= max_level && std::isfinite(width) && std::isfinite(cell);
  for (std::size_t d = 0; d < 3 && placed; ++d)
    placed = cell_index(box.min(int(d)), cell, lo[d]) && cell_index(box.max(int(d)), cell, hi[d]) && lo[d] <= hi[d];
  if (!placed) {
    purge_when_grown(unplaced_, is_live);
    unplaced_.items.push_back({entry, box});
    return;
  }
  if (level > top_) raise_top(level);
  // In every cell it overlaps: at most two per axis, as the box is no wider than a cell.
  for (std::int64_t i = lo[0]; i <= hi[0]; ++i)
    for (std::int64_t j = lo[1]; j <= hi[1]; ++j)
      for (std::int64_t k = lo[2]; k <= hi[2]; ++k) {
        Cell& cell = cell_at(level, Index{i, j, k});
        purge_when_grown(cell, is_live);
        cell.items.push_back({entry, box});
      }
}

void FaceGrid::defer(const Entry& entry, const CGAL::Bbox_3& box) {
  const double bucket = base_ * bucket_cells;
  Index index{};
  bool held = std::isfinite(bucket) && deferred_how_.box_of && deferred_how_.is_live;
  for (std::size_t d = 0; d < 3 && held; ++d)  // (no wider than half a bucket, as computed: than a bucket, exactly)
    held = box.max(int(d)) - box.min(int(d)) <= 0.5 * bucket && cell_index(box.min(int(d)), bucket, index[d]) &&
           std::abs(index[d]) < parent_limit;
  if (!held) return insert(entry, box);
  buckets_[index].push_back(entry);
}

void FaceGrid::insert_bucket(std::vector<Entry>& entries) {
  for (const Entry& e : entries)
    if (deferred_how_.is_live(e)) insert(e, deferred_how_.box_of(e));
  entries.clear();
}

void FaceGrid::insert_deferred_near(const CGAL::Bbox_3& box) {
  if (buckets_.empty()) return;
  const double bucket = base_ * bucket_cells;
  Index lo{}, hi{};
  bool indexed = true;
  for (std::size_t d = 0; d < 3 && indexed; ++d) {
    indexed = cell_index(box.min(int(d)), bucket, lo[d]) && cell_index(box.max(int(d)), bucket, hi[d]);
    lo[d] -= 1;  // a box starting up to a bucket below the query's lowest corner
  }
  double count = 1;
  for (std::size_t d = 0; d < 3 && indexed; ++d) count *= double(hi[d] - lo[d] + 1);
  if (!indexed || count > double(buckets_.size())) {  // by the buckets, where they are fewer
    for (auto it = buckets_.begin(); it != buckets_.end();) {
      bool in_range = true;
      for (std::size_t d = 0; d < 3 && indexed && in_range; ++d)
        in_range = it->first[d] >= lo[d] && it->first[d] <= hi[d];
      if (!in_range) {
        ++it;
        continue;
      }
      insert_bucket(it->second);
      it = buckets_.erase(it);
    }
    return;
  }
  for (std::int64_t i = lo[0]; i <= hi[0]; ++i)
    for (std::int64_t j = lo[1]; j <= hi[1]; ++j)
      for (std::int64_t k = lo[2]; k <= hi[2]; ++k)
        if (const auto it = buckets_.find({i, j, k}); it != buckets_.end()) {
          insert_bucket(it->second);
          buckets_.erase(it);
        }
}

std::vector<FaceGrid::Entry> FaceGrid::query(const CGAL::Bbox_3& box) {
  const std::vector<Item> items = query_items(box);
  std::vector<Entry> found;
  found.reserve(items.size());
  for (const Item& item : items) found.push_back(item.entry);
  return found;
}

std::vector<FaceGrid::Item> FaceGrid::query_items(const CGAL::Bbox_3& box) {
  insert_deferred_near(box);
  std::vector<Item> found;
  for (const Item& item : unplaced_.items)
    if (CGAL::do_overlap(item.box, box)) found.push_back(item);
  if (top_ < min_level) return found;
  // Down from the top level, through the cells that overlap the query's range of cells and
  // exist (hold boxes, or cells below that do).
  std::vector<std::pair<Index, Cell*>> cells, below;
  for (int level = top_; level >= min_level; --level) {
    const auto at = levels_.find(level);
    if (at == levels_.end()) break;
    Level& here = at->second;
    const double width = std::ldexp(base_, level);
    Index lo{}, hi{};
    bool indexed = true;  // false: the query reaches beyond the indices (all cells are in range)
    for (std::size_t d = 0; d < 3 && indexed; ++d)
      indexed = cell_index(box.min(int(d)), width, lo[d]) && cell_index(box.max(int(d)), width, hi[d]);
    const auto in_range = [&](const Index& c) {
      for (std::size_t d = 0; d < 3 && indexed; ++d)
        if (c[d] < lo[d] || c[d] > hi[d]) return false;
      return true;
    };
    if (level == top_) {  // by the cells in range, or by the level's cells where they are fewer
      double count = 1;
      for (std::size_t d = 0; d < 3; ++d) count *= double(hi[d] - lo[d] + 1);
      if (!indexed || count > double(here.size())) {
        for (auto& [index, cell] : here)
          if (in_range(index)) cells.emplace_back(index, &cell);
      } else {
        for (std::int64_t i = lo[0]; i <= hi[0]; ++i)
          for (std::int64_t j = lo[1]; j <= hi[1]; ++j)
            for (std::int64_t k = lo[2]; k <= hi[2]; ++k)
              if (const auto it = here.find({i, j, k}); it != here.end()) cells.emplace_back(it->first, &it->second);
      }
    } else {
      below.clear();
      for (const auto& [parent, parent_cell] : cells) {
        if (std::abs(parent[0]) >= parent_limit || std::abs(parent[1]) >= parent_limit ||
            std::abs(parent[2]) >= parent_limit)
          continue;  // no cell below it can be indexed
        for (int child = 0; child < 8; ++child) {
          Cell* const there = parent_cell->child[std::size_t(child)];
          if (!there) continue;
          const Index c{2 * parent[0] + (child & 1), 2 * parent[1] + ((child >> 1) & 1), 2 * parent[2] + (child >> 2)};
          if (in_range(c)) below.emplace_back(c, there);
        }
      }
      std::swap(cells, below);
    }
    // A box is in every cell it overlaps; it is taken from one only: the cell holding the corner
    // of the overlap of its box and the query that is lowest along each axis (exact: the cell
    // width is a power of two).
    // A dead entry met on the way is dropped from its cell (the live ones keep their order).
    const Liveness& is_live = deferred_how_.is_live;
    for (const auto& [index, cell] : cells) {
      auto& items = cell->items;
      std::size_t kept = 0;
      for (std::size_t i = 0; i < items.size(); ++i) {
        const Item& item = items[i];
        const bool overlaps = CGAL::do_overlap(item.box, box);
        if (overlaps && is_live && !is_live(item.entry)) continue;
        if (kept != i) items[kept] = item;
        ++kept;
        if (!overlaps) continue;
        bool here_once = true;
        for (std::size_t d = 0; d < 3 && here_once; ++d)
          here_once = std::floor(std::max(item.box.min(int(d)), box.min(int(d))) / width) == double(index[d]);
        if (here_once) found.push_back(item);
      }
      items.resize(kept);
      cell->size_at_purge = std::min(cell->size_at_purge, kept);
    }
    if (cells.empty()) break;
  }
  return found;
}

}  // namespace seam::internal
