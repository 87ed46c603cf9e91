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
// Deferred entries (`defer`): for an index of many faces of which a few regions are asked about
// (the quality stage indexes every face of both meshes, and asks about the band's
// neighbourhood: at 1M faces per tow, filling the grid took most of the stage's time and about a
// quarter of the run's memory). A deferred entry is kept in a bucket, a cube `bucket_cells` base
// cells wide, by its box's lowest corner (boxes wider than half a bucket, or out of the indices'
// reach, are inserted at once); a query first inserts the entries of the buckets it could need
// that are still live (`Deferred::is_live`), each with its box as `Deferred::box_of` gives it
// then. A box no wider than a bucket that overlaps the query has its lowest corner in a bucket
// from one below the query's lowest corner's to the query's highest corner's (exact: the bucket
// width is a power of two), so a query finds what it would have found had every entry been
// inserted at once, but for entries dead by then, which callers skip anyway. The caller must
// keep the boxes of live deferred entries as they were when deferred.
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
  using BoxOf = std::function<CGAL::Bbox_3(const Entry&)>;
  /// How deferred entries are inserted (see the top of this file).
  struct Deferred {
    BoxOf box_of;
    Liveness is_live;
  };
  static constexpr int bucket_cells = 4;  ///< a power of two (the bucket width is then exact)
  FaceGrid() = default;
  /// `typical_width`: the width of a typical face's box (the mean edge length, say); the base
  /// cell is the power of two at or above it.
  explicit FaceGrid(double typical_width);
  /// `is_live` (optional): whether an entry's face is still the one it was made for.
  void insert(const Entry& entry, const CGAL::Bbox_3& box, const Liveness* is_live = nullptr);
  /// Sets how deferred entries are inserted; before the first `defer`.
  void set_deferred(Deferred how) { deferred_how_ = std::move(how); }
  /// Holds the entry (with this box) to be inserted when a query first needs it.
  void defer(const Entry& entry, const CGAL::Bbox_3& box);
  /// The entries whose boxes overlap `box`. Each entry inserted once is returned once (taken from
  /// one of its cells); the order is the grid's, not a sorted one. Dead entries may be among
  /// them; where the grid has a liveness test (set_deferred), those the query meets are dropped
  /// from their cells instead (the live ones keep their order). (Not const: it also inserts the
  /// deferred entries it needs.)
  std::vector<Entry> query(const CGAL::Bbox_3& box);
  /// The same, with the boxes: a caller with several boxes queries their union once and tests
  /// each of its boxes against these.
  std::vector<Item> query_items(const CGAL::Bbox_3& box);

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
  /// Deferred entries by bucket (see the top of this file); a bucket goes once inserted.
  std::unordered_map<Index, std::vector<Entry>, IndexHash> buckets_;
  Deferred deferred_how_;
  /// Inserts the deferred entries a query of `box` may find.
  void insert_deferred_near(const CGAL::Bbox_3& box);
  void insert_bucket(std::vector<Entry>& entries);
};

}  // namespace seam::internal
