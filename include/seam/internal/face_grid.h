// seam internal: a dynamic spatial index of face bounding boxes for the quality stage's
// acceptance predicate (which faces lie near a new one).
//
// A hierarchy of grids (an octree kept in hash maps). Level L has cubic cells of width
// base x 2^L, with base a power of two, so that a coordinate's cell index is exact (floor of a
// division by a power of two) and cell i of level L holds cells 2i and 2i + 1 of level L - 1. A box
// is stored at the coarsest-needed level: the smallest L whose cell is at least as wide as the
// box, in every cell it overlaps (at most two per axis). A cell exists when it holds a box or a
// cell below it exists, and links to the cells below it that exist (no hash lookup below the top
// level). A query walks down from the top level through the existing cells that
// overlap its range of cells, and takes a box from one of its cells only (the cell of the lowest
// corner of the box's overlap with the query). So a query costs O(levels + cells met + entries in
// them), and at levels much finer than the query it meets only the cells where faces that small
// are. (A uniform grid at the input's mean edge put every face of a refined spot into one cell,
// and the stage went quadratic: a fuzzer's 11 faces refined to 1,200 took minutes under the
// sanitizers. A grid per level looked at every level's cells in the query's range, or at all of
// a level's cells where they were fewer: on a CT tow pair most of a query's time went to levels
// of a few hundred cells of tiny faces, nowhere near it.)
//
// An entry whose face was removed or remade (another version) is dead: the caller skips it, and
// `insert` drops the dead entries of a cell whenever the cell has grown to twice its size at its
// last purge. So a cell holds at most about twice its live entries however many edits were made at
// one place, at an amortised cost of O(1) liveness tests per insertion.
//
// The boxes must hold their faces (under the exact kernel: from the interval approximations, not
// from the rounded corners): the grid returns only entries whose boxes overlap the query box.
//
// Boxes whose cell index would not fit (hostile coordinates: |x| over 2^62 cells), boxes wider
// than the coarsest level or than the largest double cell width, and inverted boxes go to one
// list that every query tests box by box.
//
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <CGAL/Bbox_3.h>

#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <map>
#include <unordered_map>
#include <vector>

namespace seam::internal {

class FaceGrid {
 public:
  struct Entry {
    std::uint32_t mesh, face, version;
  };
  /// An entry and the box it was inserted with.
  struct Item {
    Entry entry;
    CGAL::Bbox_3 box;
  };
  using Liveness = std::function<bool(const Entry&)>;
  FaceGrid() = default;
  /// `typical_width`: the width of a typical face's box (the mean edge length, say); the base
  /// cell is the power of two at or above it.
  explicit FaceGrid(double typical_width);
  /// `is_live` (optional): whether an entry's face is still the one it was made for.
  void insert(const Entry& entry, const CGAL::Bbox_3& box, const Liveness* is_live = nullptr);
  /// The entries whose boxes overlap `box`, dead ones included. Each entry inserted once is
  /// returned once (taken from one of its cells); the order is the grid's, not a sorted one.
  std::vector<Entry> query(const CGAL::Bbox_3& box) const;
  /// The same, with the boxes: a caller with several boxes queries their union once and tests
  /// each of its boxes against these.
  std::vector<Item> query_items(const CGAL::Bbox_3& box) const;

 private:
  struct Cell {
    std::vector<Item> items;
    std::size_t size_at_purge = 0;
    /// The cells below that exist, by octant (bit 0: odd x index, bit 1: y, bit 2: z); the cells
    /// of a level are nodes of an unordered_map, which keeps them in place when it grows.
    std::array<Cell*, 8> child{};
  };
  using Index = std::array<std::int64_t, 3>;
  struct IndexHash {
    std::size_t operator()(const Index& i) const;
  };
  using Level = std::unordered_map<Index, Cell, IndexHash>;
  static constexpr int min_level = -80, max_level = 80;
  double base_ = 1;
  std::map<int, Level> levels_;
  int top_ = min_level - 1;  ///< the coarsest level (below min_level: none yet)
  Cell unplaced_;            ///< boxes outside the grid's reach
  /// The cell of `level` at `index`, made if missing, with the cells above it up to the top
  /// level (each linked to the one below).
  Cell& cell_at(int level, const Index& index);
  /// Makes `level` the top level: the cells of each level up to it get their parents.
  void raise_top(int level);
};

}  // namespace seam::internal
