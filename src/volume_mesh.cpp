// seam::volume_mesh: checks, the piecewise-linear complex, region seeds, TetGen, verification.
// See include/seam/volume_mesh.h.
// SPDX-License-Identifier: GPL-3.0-or-later
#include <seam/volume_mesh.h>

#include <seam/internal/message.h>
#include <seam/internal/tetgen_call.h>
#include <seam/internal/volume_plc.h>
#include <seam/kernels.h>

#include <CGAL/Side_of_triangle_mesh.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <numeric>
#include <unordered_map>

namespace seam {

namespace {

using internal::say;
using K = Filtered;
using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

void check_options(const VolumeMeshOptions& o, std::size_t tows, std::size_t names) {
  if (tows == 0) throw InvalidInput("volume mesh: no tow given");
  if (names != tows) throw InvalidInput("volume mesh: one name per tow is needed");
  if (!(std::isfinite(o.margin) && o.margin >= 0)) throw InvalidInput(say("margin ", o.margin, ": must be a finite number >= 0"));
  if (!(std::isfinite(o.radius_edge) && (o.radius_edge == 0 || o.radius_edge >= 1.2)))
    throw InvalidInput(say("radius-edge ", o.radius_edge, ": must be 0 (no quality refinement) or a finite number >= 1.2"));
  if (!(std::isfinite(o.max_volume) && o.max_volume >= 0))
    throw InvalidInput(say("max-volume ", o.max_volume, ": must be a finite number >= 0"));
  if (!std::isfinite(o.box_face_spacing)) throw InvalidInput("box face spacing: must be finite");
  if (!(std::isfinite(o.cut_snap) && o.cut_snap >= 0 && o.cut_snap <= 0.5))
    throw InvalidInput(say("cut snap ", o.cut_snap, ": must be from 0 to 0.5 (a fraction of the mean edge length)"));
  if (o.box) {
    for (int k = 0; k < 3; ++k)
      if (!(std::isfinite(o.box->min[k]) && std::isfinite(o.box->max[k]) && o.box->min[k] < o.box->max[k]))
        throw InvalidInput(say("box: min ", o.box->min[k], " must be below max ", o.box->max[k], " (axis ", k, ")"));
    check_coordinate_range({o.box->min, o.box->max}, "box");
  }
}

/// Every edge of a (validated, so manifold and consistently oriented) tow used by two triangles.
void check_closed(const TriangleSoup& tow, const std::string& name) {
  std::unordered_map<std::uint64_t, int> uses;
  uses.reserve(tow.triangles.size() * 3);
  for (const auto& t : tow.triangles)
    for (int k = 0; k < 3; ++k) {
      const std::uint64_t a = t[k], b = t[(k + 1) % 3];
      ++uses[std::min(a, b) << 32 | std::max(a, b)];
    }
  for (const auto& [key, n] : uses)
    if (n != 2)
      throw InvalidInput(say(name, ": not closed (the edge between vertices ", key >> 32, " and ", key & 0xffffffffu,
                             " has one face): a tow must be a closed surface"));
}

AxisBox matrix_box(const std::vector<TriangleSoup>& tows, const std::vector<std::string>& names, const VolumeMeshOptions& o) {
  AxisBox box;
  if (o.box) {
    box = *o.box;
  } else {
    box.min = {HUGE_VAL, HUGE_VAL, HUGE_VAL};
    box.max = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
    for (const auto& tow : tows)
      for (const auto& p : tow.points)
        for (int k = 0; k < 3; ++k) {
          box.min[k] = std::min(box.min[k], p[k]);
          box.max[k] = std::max(box.max[k], p[k]);
        }
    for (int k = 0; k < 3; ++k) {
      box.min[k] -= o.margin;
      box.max[k] += o.margin;
    }
  }
  if (o.box) return box;  // a tow crossing the box is cut by it (clip_tows_to_box)
  static const char* axis = "xyz";
  for (std::size_t i = 0; i < tows.size(); ++i)
    for (const auto& p : tows[i].points)
      for (int k = 0; k < 3; ++k)
        if (p[k] < box.min[k] || p[k] > box.max[k])
          throw InvalidInput(say(names[i], ": the vertex (", p[0], ", ", p[1], ", ", p[2], ") lies outside the matrix box (",
                                 axis[k], " from ", box.min[k], " to ", box.max[k],
                                 "): tows must lie in the box; tows crossing it are not supported yet"));
  return box;
}

/// One connected component of a tow as a mesh, with its exact inside test.
struct ComponentSide {
  Mesh<K> mesh;
  std::unique_ptr<CGAL::Side_of_triangle_mesh<Mesh<K>, K>> side;
  CGAL::Bbox_3 bbox;
};

std::unique_ptr<ComponentSide> component_side(const internal::Plc& plc, const std::vector<std::array<std::size_t, 3>>& faces,
                                              const std::string& name) {
  auto c = std::make_unique<ComponentSide>();
  std::unordered_map<std::size_t, Mesh<K>::Vertex_index> vertex;
  for (const auto& f : faces) {
    std::array<Mesh<K>::Vertex_index, 3> v;
    for (int k = 0; k < 3; ++k) {
      auto it = vertex.find(f[k]);
      if (it == vertex.end()) {
        it = vertex.emplace(f[k], c->mesh.add_vertex(plc.point(f[k]))).first;
        c->bbox += plc.point(f[k]).bbox();
      }
      v[k] = it->second;
    }
    if (c->mesh.add_face(v[0], v[1], v[2]) == Mesh<K>::null_face()) throw InternalError(name + ": a component could not be built");
  }
  c->side = std::make_unique<CGAL::Side_of_triangle_mesh<Mesh<K>, K>>(c->mesh);
  return c;
}

/// A point strictly inside a component of a tow: a face centroid moved inwards, tried on the
/// largest faces at decreasing distances, checked exactly.
Point3d seed_point(const internal::Plc& plc, const std::vector<std::array<std::size_t, 3>>& faces,
                   const ComponentSide& component, const std::string& name) {
  std::vector<std::size_t> order(faces.size());
  std::iota(order.begin(), order.end(), std::size_t(0));
  const auto area2 = [&](std::size_t f) {
    const auto& t = faces[f];
    return CGAL::cross_product(plc.point(t[1]) - plc.point(t[0]), plc.point(t[2]) - plc.point(t[0])).squared_length();
  };
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return area2(a) > area2(b); });
  if (order.size() > 32) order.resize(32);
  for (const double fraction : {0.1, 0.01, 0.001, 1e-4})
    for (const std::size_t f : order) {
      const auto& t = faces[f];
      const K::Point_3 c = CGAL::centroid(plc.point(t[0]), plc.point(t[1]), plc.point(t[2]));
      K::Vector_3 n = CGAL::cross_product(plc.point(t[1]) - plc.point(t[0]), plc.point(t[2]) - plc.point(t[0]));
      const double len = std::sqrt(n.squared_length());
      if (!(len > 0)) continue;
      n = n * (fraction * std::sqrt(len / 2) / len);  // a fraction of the face's size
      for (const double sign : {-1.0, 1.0}) {
        const K::Point_3 p = c + sign * n;
        if ((*component.side)(p) == CGAL::ON_BOUNDED_SIDE) return {p.x(), p.y(), p.z()};
      }
    }
  throw InternalError(name + ": no point strictly inside the tow was found (region seed for TetGen)");
}

/// A seed point per component; a seed inside (or on) another tow's component means that the
/// two tows overlap (nested, or crossing): InvalidInput.
void add_seeds(const internal::Plc& plc, const std::vector<std::string>& names, internal::TetgenInput& input) {
  std::vector<std::unique_ptr<ComponentSide>> sides;
  for (const auto& component : plc.components) {
    const std::string& name = names[static_cast<std::size_t>(component.tow)];
    sides.push_back(component_side(plc, component.triangles, name));
    input.seeds.push_back(seed_point(plc, component.triangles, *sides.back(), name));
    input.seed_attributes.push_back(component.tow + 1);
  }
  for (std::size_t c = 0; c < sides.size(); ++c)
    for (std::size_t d = 0; d < sides.size(); ++d) {
      const auto& s = input.seeds[c];
      const K::Point_3 p(s[0], s[1], s[2]);
      if (plc.components[c].tow == plc.components[d].tow || !CGAL::do_overlap(p.bbox(), sides[d]->bbox)) continue;
      if ((*sides[d]->side)(p) != CGAL::ON_UNBOUNDED_SIDE)
        throw InvalidInput(say(names[static_cast<std::size_t>(plc.components[c].tow)], " and ",
                               names[static_cast<std::size_t>(plc.components[d].tow)],
                               ": the tows overlap (a point inside one is inside the other): run seam resolve first"));
    }
}

std::string tetgen_switches(const VolumeMeshOptions& o) {
  std::string s = "pAMQ";
  if (!o.steiner_on_surfaces) s += "Y";
  char number[64];
  if (o.radius_edge > 0) {
    std::snprintf(number, sizeof number, "q%.6f", o.radius_edge);
    s += number;
  }
  if (o.max_volume > 0) {
    // TetGen reads digits and '.' only (no exponent).
    const int decimals = std::max(6, 6 - static_cast<int>(std::floor(std::log10(o.max_volume))));
    std::snprintf(number, sizeof number, "a%.*f", std::min(decimals, 40), o.max_volume);
    s += number;
  }
  return s;
}

/// TetGen's output as a TetMesh: the input points must come back unchanged, first; tets of a
/// tow's seed attribute (tow i + 1) are that tow's, the others (unseeded regions) the matrix.
TetMesh to_tet_mesh(internal::TetgenOutput&& out, const internal::Plc& plc, const std::vector<std::string>& names) {
  if (out.points.size() < plc.points.size()) throw InternalError("TetGen dropped input points (merged as duplicates?)");
  for (std::size_t i = 0; i < plc.points.size(); ++i)
    if (out.points[i] != plc.points[i]) throw InternalError("TetGen moved or reordered an input point");
  TetMesh mesh;
  mesh.points = std::move(out.points);
  mesh.tets = std::move(out.tets);
  mesh.region.resize(mesh.tets.size());
  const int n = static_cast<int>(names.size());
  for (std::size_t t = 0; t < mesh.tets.size(); ++t)
    mesh.region[t] = (out.attribute[t] >= 1 && out.attribute[t] <= n) ? out.attribute[t] : 0;
  mesh.region_names.push_back("matrix");
  for (const auto& name : names) mesh.region_names.push_back(name);
  return mesh;
}

/// The contact patches: faces of the complex shared by two tows, with the tet of the first tow.
std::vector<ContactPatch> contact_patches(const TetMesh& mesh, const internal::Plc& plc) {
  // The tet of each region on each face of a shared triangle.
  std::unordered_map<internal::FaceKey, std::map<int, std::size_t>, internal::FaceKeyHash> tet_of;
  for (std::size_t f = 0; f < plc.triangles.size(); ++f)
    if (plc.owner[f].tow_b >= 0) {
      const auto& tri = plc.triangles[f];
      tet_of[internal::face_key(tri[0], tri[1], tri[2])];
    }
  for (std::size_t t = 0; t < mesh.tets.size(); ++t)
    for (int k = 0; k < 4; ++k) {
      const auto& c = mesh.tets[t];
      const auto it = tet_of.find(internal::face_key(c[(k + 1) % 4], c[(k + 2) % 4], c[(k + 3) % 4]));
      if (it != tet_of.end()) it->second[mesh.region[t]] = t;
    }
  std::map<std::pair<int, int>, ContactPatch> patches;
  for (std::size_t f = 0; f < plc.triangles.size(); ++f) {
    const auto& owner = plc.owner[f];
    if (owner.tow_b < 0) continue;
    const int a = std::min(owner.tow_a, owner.tow_b) + 1, b = std::max(owner.tow_a, owner.tow_b) + 1;
    auto& patch = patches[{a, b}];
    patch.a = a;
    patch.b = b;
    const auto& tri = plc.triangles[f];
    const auto& tets = tet_of.at(internal::face_key(tri[0], tri[1], tri[2]));
    const auto it = tets.find(a);
    if (it == tets.end()) throw InternalError("a shared face has no tet of its tow (verification missed it)");
    patch.faces.push_back(tri);
    patch.tet_a.push_back(it->second);
  }
  std::vector<ContactPatch> result;
  for (auto& [key, patch] : patches) result.push_back(std::move(patch));
  return result;
}

}  // namespace

VolumeMeshResult volume_mesh(const std::vector<TriangleSoup>& tows, const std::vector<std::string>& names,
                             const VolumeMeshOptions& options) {
  check_options(options, tows.size(), names.size());
  VolumeMeshResult result;
  VolumeMeshStats& st = result.stats;
  auto t0 = Clock::now();
  for (std::size_t i = 0; i < tows.size(); ++i) {
    validate_triangle_mesh(tows[i], names[i]);
    check_closed(tows[i], names[i]);
  }
  st.box = matrix_box(tows, names, options);
  // Tows crossing the box (a periodic unit cell) are cut by it; the box faces then close them.
  // Vertices near a box plane move onto it first; if the tows moved so fail the checks (or one
  // keeps nothing in the box), they are cut as they are (the checks then speak about the input).
  const double snap = options.cut_snap > 0 ? options.cut_snap * internal::mean_edge_length(tows) : 0.0;
  internal::ClippedTows cut;
  internal::Plc plc;
  for (const double s : {snap, 0.0}) {
    try {
      cut = internal::clip_tows_to_box(tows, names, st.box, s);
      plc = internal::merge_tows(cut.surfaces, names, &cut.uncut);
      internal::check_no_overlap(plc, names);
      internal::check_no_crossing_at_edges(plc, names);
      break;
    } catch (const InvalidInput& e) {
      if (s == 0) throw;  // moved, the tows failed (or lost their part in the box): as they are
      st.cut_snap_undone = e.what();
    }
  }
  for (const char c : cut.clipped) st.clipped_tows += c ? 1 : 0;
  st.cut_snapped_vertices = cut.snapped;
  st.cut_snap_max_move = cut.max_move;
  st.stage_seconds["check"] = seconds_since(t0);

  t0 = Clock::now();
  double spacing = options.box_face_spacing;
  if (spacing == 0) {  // auto: the tows' mean edge length, but at most 20 steps along the box's longest side
    double longest = 0;
    for (int k = 0; k < 3; ++k) longest = std::max(longest, st.box.max[k] - st.box.min[k]);
    spacing = std::max(internal::mean_edge_length(cut.surfaces), longest / 20);
  }
  // TetGen 1.5.0 stops on one of its own assertions on some valid inputs (internal/tetgen_call.h),
  // and whether it does changes with the box faces' grid points, chaotically (the 4 x 4 weave of
  // the tests: spacing 0.1 stops it, 0.097 does not). So where it stops, the grid is made again
  // a little finer, at most five more times; the spacing used is reported. With no grid there is
  // nothing to move: the first stop is final.
  const internal::Plc tows_only = plc;
  std::vector<TriangleSoup> closed;
  const std::array<double, 6> finer = {1.0, 0.97, 0.94, 0.91, 0.88, 0.85};
  for (std::size_t attempt = 0;; ++attempt) {
    plc = tows_only;
    st.box_face_spacing = spacing > 0 ? spacing * finer[attempt] : 0.0;
    internal::add_box_faces(plc, st.box, spacing > 0 ? st.box_face_spacing : spacing);
    closed = internal::close_clipped_tows(plc, cut, st.box, names);
    for (std::size_t i = 0; i < closed.size(); ++i)
      if (cut.clipped[i]) {
        try {
          check_closed(closed[i], names[i]);
        } catch (const InvalidInput& e) {
          throw InternalError(std::string("the tow cut by the box is not closed by its caps: ") + e.what());
        }
      }
    internal::TetgenInput input;
    add_seeds(plc, names, input);
    input.points = plc.points;
    input.triangles = plc.triangles;
    input.switches = tetgen_switches(options);
    st.tetgen_switches = input.switches;
    st.input_points = plc.points.size();
    st.input_triangles = plc.triangles.size();
    st.tow_triangles = st.shared_triangles = st.box_triangles = 0;
    for (const auto& owner : plc.owner) {
      if (owner.tow_a >= 0) ++st.tow_triangles;
      if (owner.tow_b >= 0) ++st.shared_triangles;
      if (owner.on_box) ++st.box_triangles;
    }
    st.stage_seconds["plc"] += seconds_since(t0);
    t0 = Clock::now();
    try {
      result.mesh = to_tet_mesh(internal::run_tetgen(input), plc, names);
      st.stage_seconds["tetgen"] += seconds_since(t0);
      break;
    } catch (const internal::TetgenAborted& e) {
      st.stage_seconds["tetgen"] += seconds_since(t0);
      st.tetgen_aborts.push_back(e.what());
      if (!(spacing > 0) || attempt + 1 == finer.size())
        throw InternalError(std::string(e.what()) + (spacing > 0 ? say(" with ", finer.size(), " box grids down to spacing ",
                                                                       st.box_face_spacing, "; try another --box-spacing or --radius-edge")
                                                                 : std::string("; try a box grid (--box-spacing) or another --radius-edge")));
    }
    t0 = Clock::now();
  }
  st.points = result.mesh.points.size();
  st.tets = result.mesh.tets.size();
  st.steiner_points = st.points - plc.points.size();

  t0 = Clock::now();
  const auto problems = verify_volume_mesh(result.mesh, closed, st.box, options.steiner_on_surfaces, st);
  if (!problems.empty())
    throw InternalError("the volume mesh failed its verification: " + problems.front() +
                        (problems.size() > 1 ? say(" (and ", problems.size() - 1, " more problems)") : std::string()));
  if (!options.steiner_on_surfaces) result.contacts = contact_patches(result.mesh, plc);
  internal::tet_quality(result.mesh, options.radius_edge, st);
  st.stage_seconds["verify"] = seconds_since(t0);
  return result;
}

}  // namespace seam
