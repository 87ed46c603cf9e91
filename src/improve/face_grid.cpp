// seam: the quality stage's index of face boxes (see seam/internal/face_grid.h).
// SPDX-License-Identifier: GPL-3.0-or-later

#include <seam/internal/face_grid.h>

#include <algorithm>
#include <cmath>

namespace seam::internal {

namespace {

constexpr double index_limit = 4611686018427387904.0;  // 2^62: cell indices stay well inside int64

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

void FaceGrid::insert(const Entry& entry, const CGAL::Bbox_3& box, const Liveness* is_live) {
  double width = 0;
  for (int d = 0; d < 3; ++d) width = std::max(width, box.max(d) - box.min(d));
  int level = min_level;
  if (width > 0) {
    int e = 0;
    const double m = std::frexp(width / base_, &e);  // width / base_ = m 2^e, m in [0.5, 1)
    level = std::max(min_level, m == 0.5 ? e - 1 : e);
  }
  Index index{};
  bool placed = level <= max_level && std::isfinite(width);
  const double cell = std::ldexp(base_, level);
  for (int d = 0; d < 3 && placed; ++d) placed = cell_index(box.min(d), cell, index[std::size_t(d)]);
  Cell& target = placed ? levels_[level][index] : unplaced_;
  purge_when_grown(target, is_live);
  target.items.push_back({entry, box});
}

void FaceGrid::collect(int level, const Level& cells, const CGAL::Bbox_3& box, std::vector<Entry>& found) const {
  const auto take = [&](const Cell& c) {
    for (const Item& item : c.items)
      if (CGAL::do_overlap(item.box, box)) found.push_back(item.entry);
  };
  const double cell = std::ldexp(base_, level);
  Index lo{}, hi{};
  bool indexed = true;
  double count = 1;
  for (std::size_t d = 0; d < 3 && indexed; ++d) {
    indexed = cell_index(box.min(int(d)), cell, lo[d]) && cell_index(box.max(int(d)), cell, hi[d]);
    lo[d] -= 1;  // a box stored one cell lower can reach into the query
    count *= double(hi[d] - lo[d] + 1);
  }
  if (!indexed || count > double(cells.size())) {  // fewer occupied cells than cells in range
    for (const auto& [index, c] : cells) take(c);
    return;
  }
  for (std::int64_t i = lo[0]; i <= hi[0]; ++i)
    for (std::int64_t j = lo[1]; j <= hi[1]; ++j)
      for (std::int64_t k = lo[2]; k <= hi[2]; ++k)
        if (const auto it = cells.find({i, j, k}); it != cells.end()) take(it->second);
}

std::vector<FaceGrid::Entry> FaceGrid::query(const CGAL::Bbox_3& box) const {
  std::vector<Entry> found;
  for (const auto& [level, cells] : levels_) collect(level, cells, box, found);
  for (const Item& item : unplaced_.items)
    if (CGAL::do_overlap(item.box, box)) found.push_back(item.entry);
  return found;
}

}  // namespace seam::internal
