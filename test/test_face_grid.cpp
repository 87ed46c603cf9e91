// Tests of the quality stage's index of face boxes: a query returns exactly the stored boxes that
// overlap it, each once, whatever the spread of sizes and positions.
#include <catch2/catch.hpp>

#include <seam/internal/face_grid.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <tuple>
#include <vector>

namespace {

using seam::internal::FaceGrid;

auto key(const FaceGrid::Entry& e) { return std::make_tuple(e.mesh, e.face, e.version); }

std::vector<std::tuple<std::uint32_t, std::uint32_t, std::uint32_t>> keys(std::vector<FaceGrid::Entry> entries) {
  std::vector<std::tuple<std::uint32_t, std::uint32_t, std::uint32_t>> k;
  for (const auto& e : entries) k.push_back(key(e));
  std::sort(k.begin(), k.end());
  return k;
}

/// A box of width 10^[-6, 3] at a place within 10^[-3, 6] of the origin, or, one time in 50, at a
/// hostile place (1e300) or of a hostile width (1e290).
CGAL::Bbox_3 random_box(std::mt19937& rng) {
  std::uniform_real_distribution<double> unit(-1, 1), exponent(-6, 3), place(-3, 6);
  std::uniform_int_distribution<int> rare(0, 49);
  const int kind = rare(rng);
  const double width = kind == 0 ? 1e290 : std::pow(10.0, exponent(rng));
  const double reach = kind == 1 ? 1e300 : std::pow(10.0, place(rng));
  double lo[3], hi[3];
  for (int d = 0; d < 3; ++d) {
    lo[d] = unit(rng) * reach;
    hi[d] = lo[d] + width * std::abs(unit(rng));
  }
  return {lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]};
}

}  // namespace

TEST_CASE("face grid: a query finds exactly the boxes that overlap it, each once", "[improve]") {
  std::mt19937 rng(5);
  for (double typical : {1e-3, 0.7, 1.0, 300.0}) {
    FaceGrid grid(typical);
    std::vector<std::pair<FaceGrid::Entry, CGAL::Bbox_3>> stored;
    for (std::uint32_t i = 0; i < 3000; ++i) {
      // Clusters: every tenth box near the last one, a hundred times smaller (a refined spot).
      CGAL::Bbox_3 box = random_box(rng);
      if (i % 10 != 0 && !stored.empty()) {
        const CGAL::Bbox_3& last = stored.back().second;
        const double w = std::max(1e-9, (last.xmax() - last.xmin()) / 100);
        box = CGAL::Bbox_3(last.xmin() + w, last.ymin() + w, last.zmin() + w, last.xmin() + 2 * w, last.ymin() + 3 * w,
                           last.zmin() + 2 * w);
      }
      const FaceGrid::Entry e{i % 2, i, i * 7};
      grid.insert(e, box);
      stored.emplace_back(e, box);
    }
    for (int q = 0; q < 400; ++q) {
      const CGAL::Bbox_3 box = q % 2 ? random_box(rng) : stored[std::size_t(q) * 7].second;
      std::vector<FaceGrid::Entry> expected;
      for (const auto& [e, b] : stored)
        if (CGAL::do_overlap(b, box)) expected.push_back(e);
      const auto found = grid.query(box);
      CHECK(found.size() == expected.size());  // each once
      CHECK(keys(found) == keys(expected));
    }
  }
}

TEST_CASE("face grid: dead entries are dropped as a cell grows, live ones never", "[improve]") {
  FaceGrid grid(1.0);
  std::vector<bool> live;
  const FaceGrid::Liveness is_live = [&](const FaceGrid::Entry& e) { return bool(live[e.face]); };
  const CGAL::Bbox_3 spot(0.1, 0.1, 0.1, 0.2, 0.2, 0.2);
  for (std::uint32_t i = 0; i < 10000; ++i) {  // repeated edits at one spot: all but every 100th die
    live.push_back(true);
    if (i > 0 && (i - 1) % 100 != 0) live[i - 1] = false;
    grid.insert({0, i, 0}, spot, &is_live);
  }
  const auto found = grid.query(spot);
  std::size_t live_found = 0;
  for (const auto& e : found) live_found += live[e.face];
  CHECK(live_found == std::size_t(std::count(live.begin(), live.end(), true)));
  CHECK(found.size() <= 2 * live_found + 16);  // the dead ones do not pile up
}

TEST_CASE("face grid: deferred entries are found as if inserted at once, dead ones not", "[improve]") {
  std::mt19937 rng(11);
  for (double typical : {1e-3, 0.7, 300.0}) {
    FaceGrid grid(typical);
    std::vector<std::pair<FaceGrid::Entry, CGAL::Bbox_3>> stored;
    std::vector<bool> live, deferred;
    grid.set_deferred({[&](const FaceGrid::Entry& e) { return stored[e.face].second; },
                       [&](const FaceGrid::Entry& e) { return bool(live[e.face]); }});
    std::uniform_int_distribution<int> coin(0, 3);
    for (std::uint32_t i = 0; i < 3000; ++i) {
      CGAL::Bbox_3 box = random_box(rng);
      if (i % 3 != 0 && !stored.empty()) {  // most near the last one, of a typical size
        const CGAL::Bbox_3& last = stored.back().second;
        const double w = typical * (0.2 + 0.5 * std::abs(std::sin(double(i))));
        box = CGAL::Bbox_3(last.xmin() + w, last.ymin() - w, last.zmin(), last.xmin() + 2 * w, last.ymin(), last.zmin() + w);
      }
      const FaceGrid::Entry e{i % 2, i, 0};
      stored.emplace_back(e, box);
      live.push_back(true);
      deferred.push_back(coin(rng) != 0);
      if (deferred.back())
        grid.defer(e, box);
      else
        grid.insert(e, box);
    }
    // Some deferred entries die before any query: those the grid holds (boxes no wider than the
    // typical width, near the origin) are never inserted, so never found. (A box too wide for a
    // bucket, or out of the indices' reach, is inserted at once: found while dead, as inserted
    // entries are.)
    std::vector<bool> dead_before_any;
    for (std::size_t i = 0; i < live.size(); ++i) {
      const CGAL::Bbox_3& b = stored[i].second;
      const bool held = b.xmax() - b.xmin() <= typical && b.ymax() - b.ymin() <= typical &&
                        b.zmax() - b.zmin() <= typical && std::abs(b.xmin()) < 1e9 && std::abs(b.ymin()) < 1e9 &&
                        std::abs(b.zmin()) < 1e9;
      dead_before_any.push_back(deferred[i] && held && i % 11 == 5);
      if (dead_before_any.back()) live[i] = false;
    }
    CHECK(std::count(dead_before_any.begin(), dead_before_any.end(), true) > 20);
    for (int q = 0; q < 400; ++q) {
      if (q % 50 == 0)  // some deferred entries die between queries (a face an edit removed)
        for (std::size_t i = 0; i < live.size(); i += 7)
          if (deferred[i] && coin(rng) == 0) live[i] = false;
      const CGAL::Bbox_3 box = q % 2 ? random_box(rng) : stored[std::size_t(q) * 7].second;
      std::vector<FaceGrid::Entry> expected;
      for (const auto& [e, b] : stored)
        if (CGAL::do_overlap(b, box) && live[e.face]) expected.push_back(e);
      std::vector<FaceGrid::Entry> found;
      for (const auto& e : grid.query(box)) {  // dead ones a caller skips (those inserted before they died)
        CHECK_FALSE(dead_before_any[e.face]);
        if (live[e.face]) found.push_back(e);
      }
      CHECK(found.size() == expected.size());  // each once
      CHECK(keys(found) == keys(expected));
    }
  }
}
