// Test fixtures shared by the test files: a small generated tow, a box and a tetrahedron, and
// `tetgen -d` on two meshes merged as a volume mesher gets them.
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <seam/generate.h>
#include <seam/io.h>

#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cstdlib>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "test_support.h"

namespace seam_test {

/// A short crimped tow, 20 x 18 segments, centred on the origin along x.
inline seam::TowOptions small_tow() {
  seam::TowOptions t;
  t.length = 4;
  t.half_width = 0.8;
  t.half_height = 0.3;
  t.crimp_amplitude = 0.15;
  t.crimp_wavelength = 4;
  t.segments_along = 20;
  t.segments_around = 18;
  t.translate = {-2, 0, 0};
  return t;
}

/// The axis-aligned box [lo, hi] as a closed, outward-oriented triangle soup (corner i = x + 2y + 4z).
inline seam::TriangleSoup box_soup(const seam::Point3d& lo, const seam::Point3d& hi) {
  seam::TriangleSoup soup;
  for (int i = 0; i < 8; ++i)
    soup.points.push_back({(i & 1) ? hi[0] : lo[0], ((i >> 1) & 1) ? hi[1] : lo[1], ((i >> 2) & 1) ? hi[2] : lo[2]});
  soup.triangles = {{0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}, {0, 1, 5}, {0, 5, 4},
                    {2, 6, 7}, {2, 7, 3}, {0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}};
  return soup;
}

/// A tetrahedron on the triangle (a, b, c), counter-clockwise seen from the apex's side, with its
/// apex at `apex` (outward-oriented).
inline seam::TriangleSoup tetrahedron(const seam::Point3d& a, const seam::Point3d& b, const seam::Point3d& c,
                                      const seam::Point3d& apex) {
  seam::TriangleSoup tet;
  tet.points = {a, b, c, apex};
  tet.triangles = {{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {2, 0, 3}};
  return tet;
}

/// Surfaces as one OFF file as a volume mesher gets them: vertices with the same coordinates
/// merged, a face of both (a shared face of a flat contact) written once.
inline void write_merged(const std::vector<seam::TriangleSoup>& soups, const std::string& path) {
  seam::TriangleSoup merged;
  std::map<seam::Point3d, std::size_t> index;
  std::set<std::array<std::size_t, 3>> seen;
  for (const auto& s : soups) {
    std::vector<std::size_t> map(s.points.size());
    for (std::size_t i = 0; i < s.points.size(); ++i) {
      auto [it, inserted] = index.try_emplace(s.points[i], merged.points.size());
      if (inserted) merged.points.push_back(s.points[i]);
      map[i] = it->second;
    }
    for (const auto& t : s.triangles) {
      std::array<std::size_t, 3> tri = {map[t[0]], map[t[1]], map[t[2]]}, key = tri;
      std::sort(key.begin(), key.end());
      if (seen.insert(key).second) merged.triangles.push_back(tri);
    }
  }
  seam::write_triangle_mesh(merged, path);
}

/// `tetgen -d` on the surfaces merged (write_merged): the number of intersecting face pairs it
/// reports.
inline long tetgen_intersecting_pairs(const std::vector<seam::TriangleSoup>& soups, const TempDir& dir) {
  write_merged(soups, dir.file("merged.off"));
  const std::string log = dir.file("tetgen.log");
  const std::string cmd = "cd '" + dir.path.string() + "' && tetgen -d merged.off > '" + log + "' 2>&1";
  REQUIRE(std::system(cmd.c_str()) == 0);
  const std::string text = read_bytes(log);
  if (text.find("No faces are intersecting.") != std::string::npos) return 0;
  const auto at = text.find("!! Found ");
  REQUIRE(at != std::string::npos);
  return std::strtol(text.c_str() + at + 9, nullptr, 10);
}

}  // namespace seam_test
