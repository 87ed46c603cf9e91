// seam internal: the piecewise-linear complex of a volume mesh. See include/seam/internal/volume_plc.h.
// SPDX-License-Identifier: GPL-3.0-or-later
#include <seam/internal/volume_plc.h>

#include <seam/internal/message.h>
#include <seam/io.h>

#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Side_of_triangle_mesh.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>
#include <CGAL/box_intersection_d.h>
#include <CGAL/intersections.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <numeric>
#include <optional>
#include <set>
#include <unordered_map>

namespace seam::internal {

namespace {

using K = Filtered;

/// Union-find over the faces of one tow.
struct Components {
  std::vector<std::size_t> parent;
  explicit Components(std::size_t n) : parent(n) { std::iota(parent.begin(), parent.end(), std::size_t(0)); }
  std::size_t find(std::size_t i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  }
  void join(std::size_t a, std::size_t b) { parent[find(a)] = find(b); }
};

/// The components of tow `tow` (faces joined across their edges).
void add_components(Plc& plc, int tow, const std::vector<std::array<std::size_t, 3>>& triangles) {
  Components uf(triangles.size());
  std::map<std::pair<std::size_t, std::size_t>, std::size_t> first_face;
  for (std::size_t f = 0; f < triangles.size(); ++f)
    for (int k = 0; k < 3; ++k) {
      const std::size_t a = triangles[f][k], b = triangles[f][(k + 1) % 3];
      const auto [it, added] = first_face.emplace(std::make_pair(std::min(a, b), std::max(a, b)), f);
      if (!added) uf.join(f, it->second);
    }
  std::map<std::size_t, std::size_t> component_of_root;
  for (std::size_t f = 0; f < triangles.size(); ++f) {
    const auto [it, added] = component_of_root.emplace(uf.find(f), plc.components.size());
    if (added) plc.components.push_back({tow, {}});
    plc.components[it->second].triangles.push_back(triangles[f]);
  }
}

}  // namespace

long double signed_volume(const TriangleSoup& s) {
  long double sum = 0;
  const Point3d& o = s.points.front();
  for (const auto& t : s.triangles) {
    long double u[3], v[3], w[3];
    for (int k = 0; k < 3; ++k) {
      u[k] = (long double)s.points[t[0]][k] - o[k];
      v[k] = (long double)s.points[t[1]][k] - o[k];
      w[k] = (long double)s.points[t[2]][k] - o[k];
    }
    sum += u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) + u[2] * (v[0] * w[1] - v[1] * w[0]);
  }
  return sum;
}

namespace {

/// A tow's two faces at an edge, as oriented in the tow, with the tow's orientation sign.
struct EdgeWedge {
  int tow = 0;
  std::array<std::size_t, 3> face[2];
  int faces = 0;
};

/// Whether the half-plane of the edge through point r lies strictly inside the tow's wedge.
bool inside_wedge(const Plc& plc, const EdgeWedge& w, int sign, std::size_t r) {
  const auto side = [&](const std::array<std::size_t, 3>& f, std::size_t x) {
    return static_cast<int>(CGAL::orientation(plc.point(f[0]), plc.point(f[1]), plc.point(f[2]), plc.point(x))) * sign;
  };
  const auto third = [](const std::array<std::size_t, 3>& f, const std::array<std::size_t, 3>& g) {
    for (const std::size_t v : f)
      if (std::find(g.begin(), g.end(), v) == g.end()) return v;
    return f[0];
  };
  const bool convex = side(w.face[0], third(w.face[1], w.face[0])) <= 0;
  const int s0 = side(w.face[0], r), s1 = side(w.face[1], r);
  return convex ? (s0 < 0 && s1 < 0) : (s0 < 0 || s1 < 0);
}

std::string face_name(const TriangleOwner& o, bool second, const std::vector<std::string>& names) {
  return say(names[second ? o.tow_b : o.tow_a], " face ", second ? o.face_b : o.face_a);
}

/// Whether two triangles of the complex that share `shared` corners meet anywhere else.
bool meet_elsewhere(const Plc& plc, const std::array<std::size_t, 3>& s, const std::array<std::size_t, 3>& t) {
  int shared = 0;
  int si = -1, ti = -1;  // the shared corner when there is one
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      if (s[i] == t[j]) {
        ++shared;
        si = i;
        ti = j;
      }
  const auto P = [&](std::size_t i) { return plc.point(i); };
  const K::Triangle_3 S(P(s[0]), P(s[1]), P(s[2])), T(P(t[0]), P(t[1]), P(t[2]));
  if (shared == 0) return CGAL::do_intersect(S, T);
  if (shared == 1) {  // the intersection must be that corner: no opposite edge meets the other face
    const K::Segment_3 s_opposite(P(s[(si + 1) % 3]), P(s[(si + 2) % 3]));
    const K::Segment_3 t_opposite(P(t[(ti + 1) % 3]), P(t[(ti + 2) % 3]));
    return CGAL::do_intersect(s_opposite, T) || CGAL::do_intersect(t_opposite, S);
  }
  if (shared == 2) {  // the intersection is the common edge unless they overlap in one plane
    std::size_t s_other = 0, t_other = 0;
    std::vector<std::size_t> common;
    for (int i = 0; i < 3; ++i) {
      if (std::find(t.begin(), t.end(), s[i]) == t.end()) s_other = s[i];
      else common.push_back(s[i]);
      if (std::find(s.begin(), s.end(), t[i]) == s.end()) t_other = t[i];
    }
    const std::size_t p = common[0], q = common[1];
    if (CGAL::orientation(P(p), P(q), P(s_other), P(t_other)) != CGAL::COPLANAR) return false;
    return CGAL::coplanar_orientation(P(p), P(q), P(s_other), P(t_other)) == CGAL::POSITIVE;
  }
  return false;  // the same triangle (not two triangles of the complex)
}


using Vb = CGAL::Triangulation_vertex_base_with_info_2<std::size_t, K>;
using Fb = CGAL::Constrained_triangulation_face_base_2<K>;
using Tds = CGAL::Triangulation_data_structure_2<Vb, Fb>;
using Cdt = CGAL::Constrained_Delaunay_triangulation_2<K, Tds, CGAL::No_constraint_intersection_requiring_constructions_tag>;
using PointBox = CGAL::Box_intersection_d::Box_with_info_d<double, 3, std::size_t>;

/// The coordinates of a grid of `n` steps from lo to hi along one axis (the ends exact), the
/// same for every face that contains that axis: the points on a box edge are shared.
std::vector<double> grid_coordinates(double lo, double hi, double spacing) {
  const double steps = spacing > 0 ? std::ceil((hi - lo) / spacing) : 1.0;
  const int n = static_cast<int>(std::clamp(steps, 1.0, 200.0));
  std::vector<double> x(static_cast<std::size_t>(n) + 1);
  for (int i = 0; i <= n; ++i) x[static_cast<std::size_t>(i)] = i == n ? hi : lo + (hi - lo) * i / n;
  return x;
}

/// Tow vertices and edges on the box's boundary, as 3D boxes grown by `grow` on every side: grid
/// points inside one are left out (the decision depends on the point only, so a grid point on a
/// box edge is kept or left out in both faces that contain it).
std::vector<PointBox> boundary_feature_boxes(const Plc& plc, const AxisBox& box, double grow) {
  const auto on_boundary = [&](const Point3d& p) {
    for (int a = 0; a < 3; ++a)
      if (p[a] == box.min[a] || p[a] == box.max[a]) return true;
    return false;
  };
  std::vector<PointBox> boxes;
  const auto add = [&](const Point3d& p, const Point3d& q) {
    double lo[3], hi[3];
    for (int a = 0; a < 3; ++a) {
      lo[a] = std::min(p[a], q[a]) - grow;
      hi[a] = std::max(p[a], q[a]) + grow;
    }
    boxes.emplace_back(PointBox(lo, hi, boxes.size()));
  };
  for (const auto& t : plc.triangles)
    for (int k = 0; k < 3; ++k) {
      const auto &p = plc.points[t[k]], &q = plc.points[t[(k + 1) % 3]];
      if (on_boundary(p)) add(p, on_boundary(q) ? q : p);
    }
  return boxes;
}

/// The grid points of face (axis a, coordinate c) away from the boundary features.
std::vector<Point3d> face_grid(const AxisBox& box, int a, double c, double spacing, const std::vector<PointBox>& features) {
  const int u = (a + 1) % 3, v = (a + 2) % 3;
  std::vector<PointBox> grid;
  std::vector<Point3d> points;
  for (const double x : grid_coordinates(box.min[u], box.max[u], spacing))
    for (const double y : grid_coordinates(box.min[v], box.max[v], spacing)) {
      Point3d p;
      p[a] = c;
      p[u] = x;
      p[v] = y;
      double lo[3] = {p[0], p[1], p[2]};
      grid.emplace_back(PointBox(lo, lo, points.size()));
      points.push_back(p);
    }
  std::vector<char> skip(points.size(), 0);
  auto features_copy = features;
  CGAL::box_intersection_d(grid.begin(), grid.end(), features_copy.begin(), features_copy.end(),
                           [&](const PointBox& g, const PointBox&) { skip[g.info()] = 1; },
                           std::ptrdiff_t(10), CGAL::Box_intersection_d::CLOSED);
  std::vector<Point3d> kept;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const bool corner = (points[i][u] == box.min[u] || points[i][u] == box.max[u]) &&
                        (points[i][v] == box.min[v] || points[i][v] == box.max[v]);
    if (corner || !skip[i]) kept.push_back(points[i]);
  }
  return kept;
}

/// One face of the box: its CDT through the grid, the tow vertices and edges in it.
void add_box_face(Plc& plc, const AxisBox& box, int a, double c, const std::vector<Point3d>& grid) {
  const int u = (a + 1) % 3, v = (a + 2) % 3;
  Cdt cdt;
  const auto insert = [&](const Point3d& p) {
    const auto vh = cdt.insert(K::Point_2(p[u], p[v]));
    vh->info() = plc.add_point(p);
    return vh;
  };
  for (const auto& p : grid) insert(p);
  std::vector<std::pair<std::size_t, std::size_t>> edges;
  for (std::size_t f = 0; f < plc.tow_triangle_count; ++f)
    for (int k = 0; k < 3; ++k) {
      const std::size_t i = plc.triangles[f][k], j = plc.triangles[f][(k + 1) % 3];
      if (plc.points[i][a] == c && plc.points[j][a] == c) edges.emplace_back(std::min(i, j), std::max(i, j));
      else if (plc.points[i][a] == c) insert(plc.points[i]);
    }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  try {
    for (const auto& [i, j] : edges) cdt.insert_constraint(insert(plc.points[i]), insert(plc.points[j]));
    Point3d corner[4];
    for (int k = 0; k < 4; ++k) {
      corner[k][a] = c;
      corner[k][u] = (k == 1 || k == 2) ? box.max[u] : box.min[u];
      corner[k][v] = k >= 2 ? box.max[v] : box.min[v];
    }
    for (int k = 0; k < 4; ++k) cdt.insert_constraint(insert(corner[k]), insert(corner[(k + 1) % 4]));
  } catch (const Cdt::Intersection_of_constraints_exception&) {
    throw InternalError("tow edges in a face of the box cross each other (the overlap check should have found it)");
  }
  for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f) {
    const std::array<std::size_t, 3> t{f->vertex(0)->info(), f->vertex(1)->info(), f->vertex(2)->info()};
    const auto [it, added] = plc.triangle_of.emplace(face_key(t[0], t[1], t[2]), plc.triangles.size());
    if (added) {
      plc.triangles.push_back(t);
      plc.owner.push_back({-1, 0, -1, 0, true});
    } else {
      plc.owner[it->second].on_box = true;
    }
  }
}

}  // namespace

std::size_t Plc::add_point(const Point3d& p) {
  const auto [it, added] = index.emplace(p, points.size());
  if (added) points.push_back(p);
  return it->second;
}

Plc merge_tows(const std::vector<TriangleSoup>& tows, const std::vector<std::string>& names,
               const std::vector<TriangleSoup>* closed) {
  Plc plc;
  std::vector<int> orientation;  // +1: outward normals (positive enclosed volume), -1: inward
  for (std::size_t i = 0; i < tows.size(); ++i) {
    orientation.push_back(signed_volume(closed ? (*closed)[i] : tows[i]) >= 0 ? 1 : -1);
    plc.orientation.push_back(orientation.back());
    const int tow = static_cast<int>(i);
    std::vector<std::size_t> id(tows[i].points.size());
    for (std::size_t v = 0; v < id.size(); ++v) id[v] = plc.add_point(tows[i].points[v]);
    std::vector<std::array<std::size_t, 3>> triangles;
    for (std::size_t f = 0; f < tows[i].triangles.size(); ++f) {
      const auto& t = tows[i].triangles[f];
      const std::array<std::size_t, 3> m{id[t[0]], id[t[1]], id[t[2]]};
      triangles.push_back(m);
      const auto [it, added] = plc.triangle_of.emplace(face_key(m[0], m[1], m[2]), plc.triangles.size());
      if (added) {
        plc.triangles.push_back(m);
        plc.owner.push_back({tow, f, -1, 0, false});
        continue;
      }
      TriangleOwner& o = plc.owner[it->second];
      if (o.tow_a == tow)
        throw InvalidInput(say(names[i], ": faces ", o.face_a, " and ", f, " have the same three corners"));
      if (o.tow_b >= 0)
        throw InvalidInput(say(names[i], ": face ", f, " is also a face of ", names[o.tow_a], " and of ", names[o.tow_b],
                               " (a face may be shared by two tows, not three)"));
      // Two tows that touch along a face see it from opposite sides (their outward normals are
      // opposite); the same side means that they overlap there (the same tow twice, say).
      const auto& first = plc.triangles[it->second];
      const bool same_order = (m[0] == first[0] && m[1] == first[1]) || (m[0] == first[1] && m[1] == first[2]) ||
                              (m[0] == first[2] && m[1] == first[0]);
      if (same_order == (orientation[static_cast<std::size_t>(o.tow_a)] == orientation[i]))
        throw InvalidInput(say(names[i], " face ", f, " and ", names[o.tow_a], " face ", o.face_a,
                               " are the same triangle with the same outside: the tows overlap (run seam resolve first)"));
      o.tow_b = tow;
      o.face_b = f;
    }
    add_components(plc, tow, triangles);
  }
  plc.tow_triangle_count = plc.triangles.size();
  return plc;
}

void check_no_overlap(const Plc& plc, const std::vector<std::string>& names) {
  using Box = CGAL::Box_intersection_d::Box_with_info_d<double, 3, std::size_t>;
  std::vector<Box> boxes;
  boxes.reserve(plc.triangles.size());
  for (std::size_t f = 0; f < plc.triangles.size(); ++f) {
    const auto& t = plc.triangles[f];
    const auto b = plc.point(t[0]).bbox() + plc.point(t[1]).bbox() + plc.point(t[2]).bbox();
    boxes.emplace_back(b, f);
  }
  std::vector<std::pair<std::size_t, std::size_t>> candidates;
  CGAL::box_self_intersection_d(boxes.begin(), boxes.end(), [&](const Box& a, const Box& b) {
    candidates.emplace_back(a.info(), b.info());
  });
  std::sort(candidates.begin(), candidates.end());  // the same first report for any box order
  for (const auto& [f, g] : candidates) {
    if (!meet_elsewhere(plc, plc.triangles[f], plc.triangles[g])) continue;
    const TriangleOwner &a = plc.owner[f], &b = plc.owner[g];
    const bool same_tow = a.tow_a == b.tow_a;
    throw InvalidInput(say(face_name(a, false, names), " and ", face_name(b, false, names),
                           same_tow ? " intersect (the surface intersects itself)"
                                    : " intersect: the tows overlap or touch off their common vertices, edges and faces "
                                      "(run seam resolve first)"));
  }
}

double mean_edge_length(const std::vector<TriangleSoup>& tows) {
  double sum = 0;
  std::size_t n = 0;
  for (const auto& tow : tows)
    for (const auto& t : tow.triangles)
      for (int k = 0; k < 3; ++k) {
        const auto &p = tow.points[t[k]], &q = tow.points[t[(k + 1) % 3]];
        sum += std::sqrt((p[0] - q[0]) * (p[0] - q[0]) + (p[1] - q[1]) * (p[1] - q[1]) + (p[2] - q[2]) * (p[2] - q[2]));
        ++n;
      }
  return n == 0 ? 0.0 : sum / n;
}

void add_box_faces(Plc& plc, const AxisBox& box, double spacing) {
  const auto features = boundary_feature_boxes(plc, box, std::max(0.0, spacing / 2));
  for (int a = 0; a < 3; ++a)
    for (const double c : {box.min[a], box.max[a]}) {
      const int u = (a + 1) % 3, v = (a + 2) % 3;
      const double grid_spacing = spacing > 0 ? spacing : 2 * std::max(box.max[u] - box.min[u], box.max[v] - box.min[v]);
      add_box_face(plc, box, a, c, face_grid(box, a, c, grid_spacing, features));
    }
}

void check_no_crossing_at_edges(const Plc& plc, const std::vector<std::string>& names) {
  std::unordered_map<std::uint64_t, std::vector<EdgeWedge>> wedges;
  for (const auto& component : plc.components)
    for (const auto& f : component.triangles)
      for (int k = 0; k < 3; ++k) {
        const std::uint64_t a = f[k], b = f[(k + 1) % 3];
        auto& list = wedges[std::min(a, b) << 32 | std::max(a, b)];
        if (list.empty() || list.back().tow != component.tow) list.push_back({component.tow, {}, 0});
        if (list.back().faces < 2) list.back().face[list.back().faces++] = f;
      }
  for (const auto& [key, list] : wedges) {
    if (list.size() < 2) continue;
    for (std::size_t i = 0; i < list.size(); ++i)
      for (std::size_t j = 0; j < list.size(); ++j) {
        if (i == j || list[i].faces != 2 || list[j].faces != 2) continue;
        const EdgeWedge &a = list[i], &b = list[j];
        for (const auto& f : b.face)
          for (const std::size_t r : f)
            if (r != (key >> 32) && r != (key & 0xffffffffu) &&
                inside_wedge(plc, a, plc.orientation[static_cast<std::size_t>(a.tow)], r))
              throw InvalidInput(say(names[static_cast<std::size_t>(b.tow)], " and ", names[static_cast<std::size_t>(a.tow)],
                                     ": the tows overlap (their surfaces cross along a common edge, as after seam pair: "
                                     "run seam resolve first)"));
      }
  }
}

namespace {

/// The box face of each box triangle of the PLC (axis * 2 + 1 for the upper face), -1 for tow
/// triangles (exact: the corners' coordinates equal the face's).
std::vector<int> box_faces_of(const Plc& plc, const AxisBox& box) {
  const std::size_t n = plc.triangles.size(), first = plc.tow_triangle_count;
  std::vector<int> face_of(n, -1);
  for (std::size_t f = first; f < n; ++f) {
    if (plc.owner[f].tow_a >= 0) continue;  // a tow face lying in the box face
    const auto& t = plc.triangles[f];
    for (int a = 0; a < 3 && face_of[f] < 0; ++a)
      for (int upper = 0; upper < 2; ++upper) {
        const double c = upper ? box.max[a] : box.min[a];
        if (plc.points[t[0]][a] == c && plc.points[t[1]][a] == c && plc.points[t[2]][a] == c) face_of[f] = 2 * a + upper;
      }
    if (face_of[f] < 0) throw InternalError("a box triangle lies in no face of the box");
  }
  return face_of;
}

/// Closes clipped tow `tow` (its surface `closed`) with its caps (PLC triangles, oriented), and
/// finds its components again.
void add_caps(Plc& plc, int tow, const std::vector<std::array<std::size_t, 3>>& caps, TriangleSoup& closed) {
  std::map<Point3d, std::size_t> local;
  for (std::size_t v = 0; v < closed.points.size(); ++v) local.emplace(closed.points[v], v);
  std::vector<std::array<std::size_t, 3>> in_plc;
  for (const auto& t : closed.triangles)
    in_plc.push_back({plc.index.at(closed.points[t[0]]), plc.index.at(closed.points[t[1]]), plc.index.at(closed.points[t[2]])});
  for (const auto& t : caps) {
    std::array<std::size_t, 3> m;
    for (int k = 0; k < 3; ++k) {
      const auto [it, added] = local.emplace(plc.points[t[k]], closed.points.size());
      if (added) closed.points.push_back(plc.points[t[k]]);
      m[k] = it->second;
    }
    closed.triangles.push_back(m);
    in_plc.push_back(t);
  }
  plc.components.erase(std::remove_if(plc.components.begin(), plc.components.end(),
                                      [&](const TowComponent& c) { return c.tow == tow; }),
                       plc.components.end());
  add_components(plc, tow, in_plc);
}

}  // namespace

std::vector<TriangleSoup> close_clipped_tows(Plc& plc, const ClippedTows& clipped, const AxisBox& box,
                                             const std::vector<std::string>& names) {
  const std::vector<TriangleSoup>& uncut = clipped.uncut;
  std::vector<TriangleSoup> closed = clipped.surfaces;
  if (std::none_of(clipped.clipped.begin(), clipped.clipped.end(), [](char c) { return c != 0; })) return closed;
  const std::size_t n = plc.triangles.size(), first = plc.tow_triangle_count;
  auto edge_key = [](std::size_t a, std::size_t b) { return std::make_pair(std::min(a, b), std::max(a, b)); };
  std::set<std::pair<std::size_t, std::size_t>> tow_edges;
  for (std::size_t f = 0; f < first; ++f)
    for (int k = 0; k < 3; ++k) tow_edges.insert(edge_key(plc.triangles[f][k], plc.triangles[f][(k + 1) % 3]));
  const std::vector<int> face_of = box_faces_of(plc, box);
  // Regions: box triangles of one face joined across edges that are no tow edge.
  Components regions(n);
  std::map<std::pair<std::size_t, std::size_t>, std::size_t> first_face;
  for (std::size_t f = first; f < n; ++f) {
    if (face_of[f] < 0) continue;
    for (int k = 0; k < 3; ++k) {
      const auto e = edge_key(plc.triangles[f][k], plc.triangles[f][(k + 1) % 3]);
      if (tow_edges.count(e)) continue;
      const auto [it, added] = first_face.emplace(e, f);
      if (!added && face_of[it->second] == face_of[f]) regions.join(f, it->second);
    }
  }
  std::map<std::size_t, std::vector<std::size_t>> members;
  for (std::size_t f = first; f < n; ++f)
    if (face_of[f] >= 0) members[regions.find(f)].push_back(f);
  // The exact side test of each clipped tow's uncut surface.
  struct Side {
    Mesh<K> mesh;
    std::unique_ptr<CGAL::Side_of_triangle_mesh<Mesh<K>, K>> test;
    CGAL::Bbox_3 bbox;
  };
  std::vector<std::unique_ptr<Side>> sides(uncut.size());
  for (std::size_t i = 0; i < uncut.size(); ++i) {
    if (!clipped.clipped[i]) continue;
    auto s = std::make_unique<Side>();
    s->mesh = mesh_from_soup<K>(uncut[i], names[i]);
    for (auto v : s->mesh.vertices()) s->bbox += s->mesh.point(v).bbox();
    s->test = std::make_unique<CGAL::Side_of_triangle_mesh<Mesh<K>, K>>(s->mesh);
    sides[i] = std::move(s);
  }
  auto area = [&](std::size_t f) {
    const auto& t = plc.triangles[f];
    return CGAL::cross_product(plc.point(t[1]) - plc.point(t[0]), plc.point(t[2]) - plc.point(t[0])).squared_length();
  };
  // A point of box triangle f's face, in the face's plane coordinates (exact: a projection).
  auto in_plane = [&](std::size_t f, const Point3d& x) {
    const int a = face_of[f] / 2;
    return K::Point_2(x[(a + 1) % 3], x[(a + 2) % 3]);
  };
  auto turn_of = [&](std::size_t f, const std::array<std::size_t, 3>& t) {
    return CGAL::orientation(in_plane(f, plc.points[t[0]]), in_plane(f, plc.points[t[1]]), in_plane(f, plc.points[t[2]]));
  };
  // A point strictly inside box triangle f (its centroid in doubles, checked exactly), if any.
  auto inner_point = [&](std::size_t f) -> std::optional<K::Point_3> {
    const auto& t = plc.triangles[f];
    Point3d c;
    for (int k = 0; k < 3; ++k) c[k] = (plc.points[t[0]][k] + plc.points[t[1]][k] + plc.points[t[2]][k]) / 3;
    c[face_of[f] / 2] = plc.points[t[0]][face_of[f] / 2];
    const auto turn = turn_of(f, t);
    const K::Point_2 x = in_plane(f, c);
    for (int k = 0; k < 3; ++k)
      if (turn == CGAL::COLLINEAR ||
          CGAL::orientation(in_plane(f, plc.points[t[k]]), in_plane(f, plc.points[t[(k + 1) % 3]]), x) != turn)
        return std::nullopt;
    return K::Point_3(c[0], c[1], c[2]);
  };
  std::vector<std::vector<std::array<std::size_t, 3>>> caps(uncut.size());
  for (auto& [root, faces] : members) {
    std::sort(faces.begin(), faces.end(), [&](std::size_t x, std::size_t y) { return area(x) > area(y); });
    int inside = -2;  // -2: not decided yet, -1: in no tow
    std::size_t tested = 0;
    for (const std::size_t f : faces) {
      if (tested == 3) break;
      const auto point = inner_point(f);
      if (!point) continue;
      ++tested;
      int in = -1;
      for (std::size_t i = 0; i < sides.size(); ++i) {
        if (!sides[i] || !CGAL::do_overlap(point->bbox(), sides[i]->bbox)) continue;
        // On the boundary: the point lies on a face of the tow in the box plane that the cut
        // dropped (the tow lies outside the box there): not a cap.
        if ((*sides[i]->test)(*point) != CGAL::ON_BOUNDED_SIDE) continue;
        if (in >= 0)
          throw InvalidInput(say(names[std::size_t(in)], " and ", names[i],
                                 ": the tows overlap in a face of the box (run seam resolve first)"));
        in = int(i);
      }
      if (inside != -2 && inside != in) throw InternalError("the caps of a clipped tow: the side tests of one region disagree");
      inside = in;
    }
    if (inside == -2) throw InternalError("the caps of a clipped tow: a region of a box face has no triangle with an inner point");
    if (inside < 0) continue;
    const std::size_t i = std::size_t(inside);
    for (const std::size_t f : faces) {
      auto t = plc.triangles[f];
      // Outward from the tow is outward from the box, for a tow oriented outwards.
      const int outward = (face_of[f] % 2 ? 1 : -1) * plc.orientation[i];
      if ((turn_of(f, t) == CGAL::LEFT_TURN ? 1 : -1) != outward) std::swap(t[1], t[2]);
      plc.owner[f].tow_a = int(i);
      plc.owner[f].face_a = closed[i].triangles.size() + caps[i].size();
      caps[i].push_back(t);
    }
  }
  for (std::size_t i = 0; i < uncut.size(); ++i)
    if (clipped.clipped[i]) add_caps(plc, int(i), caps[i], closed[i]);
  return closed;
}

}  // namespace seam::internal
