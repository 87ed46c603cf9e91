// seam::verify_volume_mesh and the tet quality figures. Independent of how the mesh was built:
// it uses only the tet mesh, the input tows and the box. Exact: orientations with Epick's exact
// predicates on the doubles, volumes as exact sums of exact determinants (CGAL::Mpzf: dyadic
// numbers, + - * without rounding).
// SPDX-License-Identifier: GPL-3.0-or-later
#include <seam/volume_mesh.h>

#include <seam/internal/message.h>
#include <seam/internal/volume_plc.h>
#include <seam/kernels.h>

#include <CGAL/Mpzf.h>

#include <algorithm>
#include <cmath>
#include <map>
#include <unordered_map>

namespace seam {

namespace {

using internal::say;
using Exact6 = CGAL::Mpzf;  // six times a volume, exactly

Exact6 det3(const Point3d& p, const Point3d& q, const Point3d& r, const Point3d& s) {
  Exact6 u[3], v[3], w[3];
  for (int k = 0; k < 3; ++k) {
    u[k] = Exact6(q[k]) - Exact6(p[k]);
    v[k] = Exact6(r[k]) - Exact6(p[k]);
    w[k] = Exact6(s[k]) - Exact6(p[k]);
  }
  return u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) + u[2] * (v[0] * w[1] - v[1] * w[0]);
}

/// Six times the volume enclosed by a closed surface (its sign by the orientation), exactly.
Exact6 enclosed_volume6(const TriangleSoup& tow) {
  const Point3d o = tow.points.front();  // any reference point: the sum does not depend on it
  Exact6 sum(0.0);
  for (const auto& t : tow.triangles) sum = sum + det3(o, tow.points[t[0]], tow.points[t[1]], tow.points[t[2]]);
  return sum;
}

Exact6 abs6(const Exact6& x) { return CGAL::sign(x) == CGAL::NEGATIVE ? -x : x; }

bool check_indices(const TetMesh& mesh, std::size_t tows, std::vector<std::string>& problems) {
  if (mesh.region.size() != mesh.tets.size()) problems.push_back("one region per tet is needed");
  for (std::size_t t = 0; t < mesh.tets.size() && problems.empty(); ++t) {
    for (const std::size_t v : mesh.tets[t])
      if (v >= mesh.points.size()) problems.push_back(say("tet ", t, " has a corner out of range"));
    if (mesh.region[t] < 0 || static_cast<std::size_t>(mesh.region[t]) > tows)
      problems.push_back(say("tet ", t, " has region ", mesh.region[t], " (", tows, " tows)"));
  }
  return problems.empty();
}

/// Volumes per region against the enclosed volumes.
void check_volumes(const TetMesh& mesh, const std::vector<TriangleSoup>& tows, const AxisBox& box,
                   std::vector<std::string>& problems, VolumeMeshStats& stats) {
  const std::size_t n = tows.size() + 1;
  std::vector<Exact6> tet_sum(n, Exact6(0.0)), enclosed(n, Exact6(0.0));
  std::vector<std::size_t> count(n, 0);
  std::size_t bad = 0;
  for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
    const auto& c = mesh.tets[t];
    const auto& P = mesh.points;
    const Filtered::Point_3 a(P[c[0]][0], P[c[0]][1], P[c[0]][2]), b(P[c[1]][0], P[c[1]][1], P[c[1]][2]),
        d(P[c[2]][0], P[c[2]][1], P[c[2]][2]), e(P[c[3]][0], P[c[3]][1], P[c[3]][2]);
    if (CGAL::orientation(a, b, d, e) != CGAL::POSITIVE) ++bad;
    const auto r = static_cast<std::size_t>(mesh.region[t]);
    tet_sum[r] = tet_sum[r] + det3(P[c[0]], P[c[1]], P[c[2]], P[c[3]]);
    ++count[r];
  }
  if (bad > 0) problems.push_back(say(bad, " tets are inverted or flat"));
  Exact6 box6(6.0);
  for (int k = 0; k < 3; ++k) box6 = box6 * (Exact6(box.max[k]) - Exact6(box.min[k]));
  enclosed[0] = box6;
  for (std::size_t i = 0; i < tows.size(); ++i) {
    enclosed[i + 1] = abs6(enclosed_volume6(tows[i]));
    enclosed[0] = enclosed[0] - enclosed[i + 1];
  }
  stats.regions.clear();
  for (std::size_t r = 0; r < n; ++r) {
    RegionStats rs;
    rs.name = r < mesh.region_names.size() ? mesh.region_names[r] : say("region ", r);
    rs.tets = count[r];
    rs.volume = CGAL::to_double(tet_sum[r]) / 6;
    rs.surface_volume = CGAL::to_double(enclosed[r]) / 6;
    const double difference = std::abs(CGAL::to_double(tet_sum[r] - enclosed[r]));
    const double reference = std::abs(CGAL::to_double(enclosed[r]));
    rs.relative_error = difference == 0 ? 0.0 : (reference > 0 ? difference / reference : HUGE_VAL);
    if (!(rs.relative_error <= 1e-9))
      problems.push_back(say(rs.name, ": its tets fill ", rs.volume, ", its surfaces enclose ", rs.surface_volume,
                             " (relative difference ", rs.relative_error, ")"));
    if (rs.tets == 0 && CGAL::sign(enclosed[r]) != CGAL::ZERO) problems.push_back(rs.name + ": no tet");
    stats.regions.push_back(rs);
  }
}

/// Every tow triangle is a mesh face with one tet of its tow behind it; a face of two tows has
/// exactly a tet of each; a face with one tet only lies in a face of the box.
void check_surfaces(const TetMesh& mesh, const std::vector<TriangleSoup>& tows, const AxisBox& box,
                    std::vector<std::string>& problems) {
  std::map<Point3d, std::size_t> index;
  for (std::size_t i = 0; i < mesh.points.size(); ++i) index.emplace(mesh.points[i], i);
  struct Face {
    std::vector<int> owners;   // tow regions whose triangle it is
    std::vector<int> regions;  // regions of the tets that have it
    Point3d corner[3];
  };
  std::unordered_map<internal::FaceKey, Face, internal::FaceKeyHash> faces;
  for (std::size_t i = 0; i < tows.size(); ++i)
    for (std::size_t f = 0; f < tows[i].triangles.size(); ++f) {
      std::size_t v[3];
      for (int k = 0; k < 3; ++k) {
        const auto it = index.find(tows[i].points[tows[i].triangles[f][k]]);
        if (it == index.end()) {
          problems.push_back(say(mesh.region_names.at(i + 1), ": a corner of face ", f, " is not a mesh point"));
          return;
        }
        v[k] = it->second;
      }
      Face& face = faces[internal::face_key(v[0], v[1], v[2])];
      face.owners.push_back(static_cast<int>(i + 1));
      for (int k = 0; k < 3; ++k) face.corner[k] = mesh.points[v[k]];
    }
  for (std::size_t t = 0; t < mesh.tets.size(); ++t)
    for (int k = 0; k < 4; ++k) {
      const auto& c = mesh.tets[t];
      const auto it = faces.find(internal::face_key(c[(k + 1) % 4], c[(k + 2) % 4], c[(k + 3) % 4]));
      if (it != faces.end()) it->second.regions.push_back(mesh.region[t]);
    }
  std::size_t missing = 0, wrong_sides = 0;
  for (const auto& [key, face] : faces) {
    if (face.regions.empty()) {
      ++missing;
      continue;
    }
    bool ok = face.regions.size() <= 2 && face.owners.size() <= 2;
    for (const int owner : face.owners) ok = ok && std::count(face.regions.begin(), face.regions.end(), owner) == 1;
    if (face.owners.size() == 2) ok = ok && face.regions.size() == 2;
    if (face.regions.size() == 1) {  // on the box's boundary: all three corners in one face of the box
      bool on_box = false;
      for (int a = 0; a < 3; ++a)
        for (const double c : {box.min[a], box.max[a]})
          on_box = on_box || (face.corner[0][a] == c && face.corner[1][a] == c && face.corner[2][a] == c);
      ok = ok && on_box;
    }
    if (!ok) ++wrong_sides;
  }
  if (missing > 0) problems.push_back(say(missing, " tow faces are not faces of the mesh (split or lost)"));
  if (wrong_sides > 0)
    problems.push_back(say(wrong_sides, " tow faces do not separate their tow's tets from the other regions"));
}

}  // namespace

std::vector<std::string> verify_volume_mesh(const TetMesh& mesh, const std::vector<TriangleSoup>& tows, const AxisBox& box,
                                            bool steiner_on_surfaces, VolumeMeshStats& stats) {
  std::vector<std::string> problems;
  if (!check_indices(mesh, tows.size(), problems)) return problems;
  check_volumes(mesh, tows, box, problems, stats);
  if (!steiner_on_surfaces) check_surfaces(mesh, tows, box, problems);
  return problems;
}

namespace internal {

void tet_quality(const TetMesh& mesh, double bound, VolumeMeshStats& stats) {
  constexpr double pi = 3.14159265358979323846;
  double min_dihedral = 180, max_dihedral = 0, max_ratio = 0;
  std::size_t above = 0;
  using V = Filtered::Vector_3;
  for (const auto& c : mesh.tets) {
    Filtered::Point_3 p[4];
    for (int k = 0; k < 4; ++k) p[k] = {mesh.points[c[k]][0], mesh.points[c[k]][1], mesh.points[c[k]][2]};
    double shortest = HUGE_VAL;
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j) {
        shortest = std::min(shortest, (p[j] - p[i]).squared_length());
        int k = 0;
        while (k == i || k == j) ++k;
        int l = 6 - i - j - k;
        const V e = p[j] - p[i];
        const V n1 = CGAL::cross_product(e, p[k] - p[i]), n2 = CGAL::cross_product(e, p[l] - p[i]);
        const double cosine = n1 * n2 / std::sqrt(n1.squared_length() * n2.squared_length());
        const double angle = std::acos(std::clamp(cosine, -1.0, 1.0)) * 180 / pi;
        min_dihedral = std::min(min_dihedral, angle);
        max_dihedral = std::max(max_dihedral, angle);
      }
    const V u = p[1] - p[0], v = p[2] - p[0], w = p[3] - p[0];
    const V centre = (u.squared_length() * CGAL::cross_product(v, w) + v.squared_length() * CGAL::cross_product(w, u) +
                      w.squared_length() * CGAL::cross_product(u, v)) /
                     (2 * (u * CGAL::cross_product(v, w)));
    const double ratio = std::sqrt(centre.squared_length() / shortest);
    max_ratio = std::max(max_ratio, ratio);
    if (bound > 0 && ratio > bound) ++above;
  }
  stats.min_dihedral_deg = mesh.tets.empty() ? 0 : min_dihedral;
  stats.max_dihedral_deg = max_dihedral;
  stats.max_radius_edge = max_ratio;
  stats.tets_above_radius_edge = above;
}

}  // namespace internal

}  // namespace seam
