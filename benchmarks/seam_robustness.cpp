// seam_robustness: degenerate configurations run through the whole pipeline under each kernel.
//
// Every case is generated deterministically from (--seed, case number): two small meshes (grid
// boxes, octahedra, tetrahedra, tows) in one of the degenerate configurations textile models are
// full of, or one mesh and a curve for seam::embed. Families (case i belongs to family i mod 12):
//   vertices     two grid boxes whose intersection curve runs through vertices of both
//   edges        a bar through a grid box: the curves run along the box's grid lines (edges)
//   endpoints    an octahedron whose edges cross the box surface exactly at box vertices
//   near_tangent a vertex or edge of one mesh a few units in the last place (1e-16..1e-15
//                relative) inside or outside a face of the other
//   coplanar     a box standing on another: overlapping coplanar faces (flat contact)
//   shifted      a copy of a mesh (grid box or tow) translated by fractions of an edge
//   rotated      a copy rotated by a rational rotation (Pythagorean triples), exactly
//   sheared      a copy sheared by a rational matrix, exactly
//   magnitude    one of the above scaled by 10^k (k in -8..8) and translated, exactly
//   resolution   meshes of very different resolutions (1 vs 16-32 squares per side, tows)
//   tows         two tows crossing (the ordinary case), rotated exactly
//   embed        seam::embed of a curve through vertices and along edges of one mesh
// Transformations are done exactly (Epeck, rational matrices); then the case either keeps the
// exact coordinates (the exact kernel gets them, the others the rounded ones: what each can
// represent) or rounds them to double for every kernel.
//
// Every (case, kernel) run is done in a child process (fork) with a time limit (--timeout) and
// a memory limit, so that a crash, an abort or an endless loop is counted, not fatal:
//   valid      pair: seam::check_pair (the code of `seam check`) passes, evaluated with the
//              exact kernel on the kernel's own input and output coordinates, tolerance
//              snap_tol + 1e-9 x the bounding-box diagonal (the default of `seam check`);
//              embed: the output is a valid mesh (exact test), every curve point a vertex and
//              segment an edge, and the output is the input surface (check_same_surface; with
//              snapping, vertices moved at most the snap tolerance)
//   invalid    a check failed (the first problem is reported)
//   exception  the library threw (seam::InternalError, ...)
//   crash      the child died of a signal (segmentation fault, abort, CGAL assertion)
//   timeout    the child was killed after --timeout seconds
//
//   seam_robustness [--seed N] [--cases N] [--timeout S] [--filter SUBSTR] [--kernels LIST]
//                   [--json] [--verbose] [--dump DIR] [--snap case|0|auto] [--contract]
// Exit status 0 when every case is valid under the exact kernel; with --contract, when no case
// under any kernel is invalid, crashed or timed out (a refusal, exit 3 with nothing written, is
// within seam's contract: a success exit means a verified output).
// --filter keeps the cases whose family or description contains SUBSTR (or "case:N": case N);
// --kernels is a comma list of exact, filtered, float; --dump DIR writes each case's meshes (as
// the filtered kernel gets them: rounded) and curves to DIR, for `seam pair` / `seam embed`;
// --snap 0 / auto runs every case without / with the default snapping (default: as the case says,
// one case in three with snapping). Exit status: 1 when the exact kernel has any non-valid run.
//
// SPDX-License-Identifier: GPL-3.0-or-later
#include <seam/check.h>
#include <seam/embed.h>
#include <seam/generate.h>
#include <seam/io.h>
#include <seam/kernels.h>
#include <seam/pair.h>
#include <seam/verify.h>

#include <CGAL/boost/graph/helpers.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <map>
#include <optional>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

namespace {

using seam::Point3d;
using seam::TriangleSoup;
using EK = seam::Exact;
using FT = EK::FT;

// ------------------------------------------------------------------------------ geometry

std::size_t add_point(TriangleSoup& s, std::map<Point3d, std::size_t>& index, const Point3d& p) {
  const auto [it, inserted] = index.try_emplace(p, s.points.size());
  if (inserted) s.points.push_back(p);
  return it->second;
}

/// The closed surface of the box [lo, hi], each side a grid of n[u] x n[v] squares split by a
/// diagonal (alternating when `alternate`), outward orientation. Grid coordinate i on axis d is
/// lo[d] + (hi[d] - lo[d]) * i / n[d], the same double on every side.
TriangleSoup grid_box(const Point3d& lo, const Point3d& hi, const std::array<int, 3>& n, bool alternate = false) {
  TriangleSoup s;
  std::map<Point3d, std::size_t> index;
  auto coord = [&](int d, int i) { return i == n[d] ? hi[d] : lo[d] + (hi[d] - lo[d]) * i / n[d]; };
  for (int axis = 0; axis < 3; ++axis)
    for (int side = 0; side < 2; ++side) {
      const int u = (axis + 1) % 3, v = (axis + 2) % 3;
      auto at = [&](int i, int j) {
        Point3d p;
        p[axis] = side ? hi[axis] : lo[axis];
        p[u] = coord(u, i);
        p[v] = coord(v, j);
        return add_point(s, index, p);
      };
      for (int i = 0; i < n[u]; ++i)
        for (int j = 0; j < n[v]; ++j) {
          const std::size_t p00 = at(i, j), p10 = at(i + 1, j), p11 = at(i + 1, j + 1), p01 = at(i, j + 1);
          const bool other = alternate && (i + j) % 2 == 1;
          std::array<std::size_t, 3> t1, t2;
          if (!other) t1 = {p00, p10, p11}, t2 = {p00, p11, p01};
          else t1 = {p00, p10, p01}, t2 = {p10, p11, p01};
          if (!side) std::swap(t1[1], t1[2]), std::swap(t2[1], t2[2]);
          s.triangles.push_back(t1);
          s.triangles.push_back(t2);
        }
    }
  return s;
}

/// The octahedron with centre c and vertices c +- r along the axes, outward orientation.
TriangleSoup octahedron(const Point3d& c, double r) {
  TriangleSoup s;
  for (int d = 0; d < 3; ++d)
    for (int sign : {1, -1}) {
      Point3d p = c;
      p[d] += sign * r;
      s.points.push_back(p);
    }
  for (int sx = 0; sx < 2; ++sx)
    for (int sy = 0; sy < 2; ++sy)
      for (int sz = 0; sz < 2; ++sz) {
        const std::size_t x = 0 + sx, y = 2 + sy, z = 4 + sz;
        if ((sx + sy + sz) % 2 == 0)
          s.triangles.push_back({x, y, z});
        else
          s.triangles.push_back({x, z, y});
      }
  return s;
}

/// The tetrahedron p0 p1 p2 p3, outward orientation.
TriangleSoup tetrahedron(const Point3d& p0, const Point3d& p1, const Point3d& p2, const Point3d& p3) {
  TriangleSoup s;
  s.points = {p0, p1, p2, p3};
  const EK::Point_3 q0(p0[0], p0[1], p0[2]), q1(p1[0], p1[1], p1[2]), q2(p2[0], p2[1], p2[2]), q3(p3[0], p3[1], p3[2]);
  s.triangles = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
  if (CGAL::orientation(q0, q1, q2, q3) == CGAL::NEGATIVE)
    for (auto& t : s.triangles) std::swap(t[1], t[2]);
  return s;
}

TriangleSoup translated(TriangleSoup s, const Point3d& d) {
  for (auto& p : s.points)
    for (int k = 0; k < 3; ++k) p[k] += d[k];
  return s;
}

/// An exact affine map p -> M p + t (rational entries as Epeck numbers).
struct Affine {
  std::array<std::array<FT, 3>, 3> m{{{FT(1), FT(0), FT(0)}, {FT(0), FT(1), FT(0)}, {FT(0), FT(0), FT(1)}}};
  std::array<FT, 3> t{{FT(0), FT(0), FT(0)}};
  bool identity = true;
  EK::Point_3 operator()(const EK::Point_3& p) const {
    if (identity) return p;
    std::array<FT, 3> r;
    for (int i = 0; i < 3; ++i) r[i] = m[i][0] * p.x() + m[i][1] * p.y() + m[i][2] * p.z() + t[i];
    EK::Point_3 q(r[0], r[1], r[2]);
    CGAL::exact(q);
    return q;
  }
  /// this after `first`
  Affine after(const Affine& first) const {
    if (first.identity) return *this;
    if (identity) return first;
    Affine a;
    a.identity = false;
    for (int i = 0; i < 3; ++i) {
      for (int j = 0; j < 3; ++j) a.m[i][j] = m[i][0] * first.m[0][j] + m[i][1] * first.m[1][j] + m[i][2] * first.m[2][j];
      a.t[i] = m[i][0] * first.t[0] + m[i][1] * first.t[1] + m[i][2] * first.t[2] + t[i];
    }
    return a;
  }
};

FT ratio(long n, long d) { return FT(n) / FT(d); }

/// Rotation by the angle with cos = (a^2 - b^2) / c, sin = 2ab / c, c = a^2 + b^2, about `axis`
/// through `centre`: every entry rational, the images of most double points not doubles.
Affine rotation(int axis, long a, long b, const Point3d& centre) {
  Affine r;
  r.identity = false;
  const long c = a * a + b * b;
  const FT cs = ratio(a * a - b * b, c), sn = ratio(2 * a * b, c);
  const int u = (axis + 1) % 3, v = (axis + 2) % 3;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) r.m[i][j] = FT(i == j ? 1 : 0);
  r.m[u][u] = cs, r.m[u][v] = -sn, r.m[v][u] = sn, r.m[v][v] = cs;
  for (int i = 0; i < 3; ++i) {
    FT mc = 0;
    for (int j = 0; j < 3; ++j) mc = mc + r.m[i][j] * FT(centre[j]);
    r.t[i] = FT(centre[i]) - mc;
  }
  return r;
}

/// x_row += (p / q) x_col, about `centre`.
Affine shear(int row, int col, long p, long q, const Point3d& centre) {
  Affine s;
  s.identity = false;
  s.m[row][col] = ratio(p, q);
  s.t[row] = -ratio(p, q) * FT(centre[col]);
  return s;
}

/// p -> f p + t, f = num / den.
Affine scaling(const FT& f, const std::array<FT, 3>& t) {
  Affine s;
  s.identity = false;
  for (int i = 0; i < 3; ++i) s.m[i][i] = f;
  s.t = t;
  return s;
}

// ------------------------------------------------------------------------------ cases

struct Case {
  int id = 0;
  std::string family, description;
  TriangleSoup a, b;        // double coordinates before the maps
  Affine map_a, map_b;      // exact maps applied to a and b
  bool keep_exact = false;  // the exact kernel gets the exact images, the others rounded ones
  double snap_tol = 0;      // 0 or -1 (automatic)
  bool embed = false;       // seam::embed of `curves` into a (b unused)
  std::vector<std::vector<Point3d>> curves;
};

const std::vector<std::string> families = {"vertices", "edges",  "endpoints", "near_tangent", "coplanar", "shifted",
                                           "rotated",  "sheared", "magnitude", "resolution",  "tows",     "embed"};

struct Rng {
  std::mt19937_64 g;
  explicit Rng(std::uint64_t seed) : g(seed) {}
  int pick(int n) { return int(g() % std::uint64_t(n)); }      // 0 .. n-1
  int range(int lo, int hi) { return lo + pick(hi - lo + 1); }  // lo .. hi
  bool coin() { return pick(2) == 1; }
  template <class T> const T& of(const std::vector<T>& v) { return v[std::size_t(pick(int(v.size())))]; }
};

std::string str(const Point3d& p) {
  std::ostringstream s;
  s.precision(17);
  s << "(" << p[0] << " " << p[1] << " " << p[2] << ")";
  return s.str();
}

const std::vector<std::array<long, 2>> pythagorean = {{2, 1}, {3, 2}, {4, 1}, {4, 3}, {5, 2}, {7, 4}, {10, 3}, {12, 7}};

Affine random_rotation(Rng& r, const Point3d& centre, std::string& what) {
  const int axis = r.pick(3);
  const auto ab = r.of(pythagorean);
  Affine m = rotation(axis, ab[0], ab[1], centre);
  what = "rotated about axis " + std::to_string(axis) + " (" + std::to_string(ab[0]) + "," + std::to_string(ab[1]) + ")";
  if (r.coin()) {  // and about a second axis
    const int axis2 = (axis + 1 + r.pick(2)) % 3;
    const auto cd = r.of(pythagorean);
    m = rotation(axis2, cd[0], cd[1], centre).after(m);
    what += " then axis " + std::to_string(axis2) + " (" + std::to_string(cd[0]) + "," + std::to_string(cd[1]) + ")";
  }
  return m;
}

seam::TowOptions small_tow(Rng& r) {
  seam::TowOptions t;
  t.segments_along = r.range(12, 40);
  t.segments_around = r.range(8, 16);
  t.section = r.coin() ? seam::Section::elliptical : seam::Section::lenticular;
  return t;
}

/// A weft along x and a warp along y crossing it, like one crossing of a plain weave.
/// Returns the warp's height (translate z).
double tow_crossover(Rng& r, Case& c, int along_a, int around_a, int along_b, int around_b) {
  const auto tows = seam::make_crossover(along_a, around_a, along_b, around_b, seam::Section::lenticular,
                                         0.3 + 0.05 * r.range(0, 6));
  c.a = seam::make_tow(tows.weft);
  c.b = seam::make_tow(tows.warp);
  return tows.warp.translate[2];
}

void make_family_case(Case& c, Rng& r) {
  const std::string& f = c.family;
  std::ostringstream d;
  const Point3d zero = {0, 0, 0}, two = {2, 2, 2};
  if (f == "vertices") {
    // A = [0,2]^3 on a grid of spacing 2/n; B = [l, l + s] with l on A's grid lines: the curve
    // (a hexagon, or a rectangle where B's extent reaches past A) runs through A's vertices and,
    // where B's grid matches, through B's.
    std::array<int, 3> na, nb;
    Point3d lo, hi;
    for (int k = 0; k < 3; ++k) {
      na[k] = 1 << r.range(1, 3);
      nb[k] = 1 << r.range(0, 3);
      lo[k] = 2.0 * r.range(1, na[k] - 1) / na[k];
      hi[k] = lo[k] + r.of(std::vector<double>{1.5, 2.0, 3.0});
    }
    c.a = grid_box(zero, two, na, r.coin());
    c.b = grid_box(lo, hi, nb, r.coin());
    d << "box grid " << na[0] << "x" << na[1] << "x" << na[2] << ", box " << str(lo) << "-" << str(hi);
  } else if (f == "edges") {
    // A bar pierces A = [0,2]^3 along axis `ax`; its sides lie in planes of A's grid lines, so
    // the two curves (rectangles in A's sides) run along A's edges.
    const int n = 1 << r.range(1, 3), ax = r.pick(3);
    Point3d lo, hi;
    for (int k = 0; k < 3; ++k) {
      if (k == ax) {
        lo[k] = -0.5 - 0.25 * r.pick(3);
        hi[k] = 2.5 + 0.25 * r.pick(3);
      } else {
        const int i = r.range(0, n - 1), j = r.range(i + 1, n);
        lo[k] = 2.0 * i / n;
        hi[k] = 2.0 * j / n;
        if (i == 0 && j == n) hi[k] = 2.0 * (n - 1) / n;  // keep it inside: no coplanar sides here
      }
    }
    std::array<int, 3> nb;
    for (int k = 0; k < 3; ++k) nb[k] = r.range(1, 6);
    c.a = grid_box(zero, two, {n, n, n}, r.coin());
    c.b = grid_box(lo, hi, nb, r.coin());
    d << "grid " << n << ", bar " << str(lo) << "-" << str(hi);
  } else if (f == "endpoints") {
    // An octahedron with centre (cx, cy, 2 + dz) and radius rad = m h, dz = k h: its four lower
    // edges cross A's top face (z = 2) at (cx +- (rad - dz), cy) and (cx, cy +- (rad - dz)), at
    // vertices of A when cx, cy are on A's grid (else on edges of A).
    const int n = 1 << r.range(2, 3);
    const double h = 2.0 / n;
    const int m = r.range(1, 3), k = r.range(0, m - 1);
    const double off = r.coin() ? 0.0 : h / 2;
    const int lo_i = m - k, hi_i = n - (m - k);
    const double cx = h * r.range(lo_i, std::max(lo_i, hi_i)) + (r.coin() ? off : 0), cy = h * r.range(lo_i, std::max(lo_i, hi_i));
    c.a = grid_box(zero, two, {n, n, n}, r.coin());
    c.b = octahedron({cx, cy, 2 + k * h}, m * h);
    if (r.coin()) std::swap(c.a, c.b);
    d << "grid " << n << ", octahedron centre " << str({cx, cy, 2 + k * h}) << " radius " << m * h;
  } else if (f == "near_tangent") {
    // A vertex (octahedron) or an edge (tetrahedron) a few ulps below (inside) or above A's top.
    const int n = 1 << r.range(1, 3);
    const double h = 2.0 / n;
    const int ulps = r.of(std::vector<int>{-3, -1, 1, 2, 4, 8});
    double z = 2.0;
    for (int i = 0; i < std::abs(ulps); ++i) z = std::nextafter(z, ulps > 0 ? 0.0 : 4.0);
    const int where = r.pick(3);  // at a vertex, inside an edge, inside a face of A
    const double x = h * r.range(1, n - 1) + (where >= 1 ? h / 4 : 0), y = h * r.range(1, n - 1) + (where == 2 ? h / 8 : 0);
    const double rad = 0.25 * r.range(1, 3) * std::min(1.0, h);
    c.a = grid_box(zero, two, {n, n, n}, r.coin());
    const bool edge = r.coin();
    if (!edge) {
      c.b = octahedron({x, y, 2 + rad}, rad);
      c.b.points[5][2] = z;  // the lowest vertex, exactly (2 + rad - rad would round to 2)
    } else {
      const double ex = rad * (r.coin() ? 1 : 0.5), ey = rad * (r.coin() ? 0.5 : 0);
      c.b = tetrahedron({x - ex, y - ey, z}, {x + ex, y + ey, z}, {x + ey, y - ex, z + rad}, {x - ey, y + ex, z + rad});
    }
    d << "grid " << n << ", " << (edge ? "edge" : "vertex") << " at " << ulps << " ulp below the top face, "
      << (where == 0 ? "at a vertex" : where == 1 ? "inside an edge" : "inside a face");
    if (r.pick(3) == 0) {  // the whole configuration rotated (exactly)
      std::string what;
      c.map_a = c.map_b = random_rotation(r, {1, 1, 1}, what);
      c.keep_exact = true;
      d << ", both " << what << ", kept exact";
    }
  } else if (f == "coplanar") {
    // B stands on A's top face: their faces overlap in the plane z = 1.
    c.a = grid_box(zero, {2, 2, 1}, {4, 4, 2}, r.coin());
    Point3d lo, hi;
    const double unit = r.coin() ? 0.125 : 1.0 / 3;
    for (int k = 0; k < 2; ++k) {
      const int i = r.range(-4, 12);
      lo[k] = i * 0.125 * (unit == 0.125 ? 1 : 1);
      hi[k] = lo[k] + unit * r.range(2, 8);
      if (r.pick(4) == 0) lo[k] = 0.0, hi[k] = r.coin() ? 2.0 : 2.5;  // sides flush with A's
    }
    lo[2] = 1.0;
    hi[2] = 1.5 + 0.5 * r.pick(2);
    if (hi[0] <= 0 || lo[0] >= 2 || hi[1] <= 0 || lo[1] >= 2) lo[0] = 0.5, hi[0] = 1.5;
    if (hi[1] <= 0 || lo[1] >= 2) lo[1] = 0.5, hi[1] = 1.5;
    const std::array<int, 3> nb = {r.range(1, 5), r.range(1, 5), r.range(1, 2)};
    c.b = grid_box(lo, hi, nb, r.coin());
    d << "box " << str(lo) << "-" << str(hi) << " on top, grid " << nb[0] << "x" << nb[1];
    if (r.pick(3) == 0) {
      std::string what;
      c.map_a = c.map_b = random_rotation(r, {1, 1, 0.5}, what);
      c.keep_exact = r.pick(3) != 0;
      d << ", both " << what << (c.keep_exact ? ", kept exact" : ", rounded");
    }
  } else if (f == "shifted") {
    // B = A translated by fractions of an edge (0 along some axes: coplanar sides overlap).
    Point3d s;
    if (r.pick(3) != 0) {
      const int n = 1 << r.range(1, 3);
      const double h = 2.0 / n;
      for (int k = 0; k < 3; ++k) s[k] = h * r.of(std::vector<double>{0.0, 0.25, 0.5, 1.0, 1.0 / 3, 0.125, 1.5});
      if (s == Point3d{0, 0, 0}) s[0] = h / 2;
      c.a = grid_box(zero, two, {n, n, n}, r.coin());
      d << "grid box " << n << " shifted by " << str(s);
    } else {
      seam::TowOptions t = small_tow(r);
      const double h = t.length / t.segments_along;
      s = {h * r.of(std::vector<double>{0.25, 0.5, 1.0 / 3, 1.0, 3.5}), 0.05 * r.pick(4), 0.0625 * r.pick(3)};
      if (r.coin()) t.crimp_amplitude = 0;  // a straight tow: its sides slide along themselves
      c.a = seam::make_tow(t);
      d << "tow " << t.segments_along << "x" << t.segments_around << (t.crimp_amplitude == 0 ? " straight" : "")
        << " shifted by " << str(s);
    }
    c.b = translated(c.a, s);
  } else if (f == "rotated") {
    // B = a copy of A (or of a smaller box) rotated exactly about a point.
    std::string what;
    if (r.pick(3) != 0) {
      const int n = 1 << r.range(0, 3);
      c.a = grid_box(zero, two, {n, n, n}, r.coin());
      c.b = r.coin() ? c.a : grid_box({0.5, 0.5, 0.5}, {1.5, 1.5, 2.5}, {2, 2, 4});
      const Point3d centre = r.coin() ? Point3d{1, 1, 1} : Point3d{1.5, 0.5, 1};
      c.map_b = random_rotation(r, centre, what);
      d << "grid box " << n << ", copy " << what << " about " << str(centre);
    } else {
      const seam::TowOptions t = small_tow(r);
      c.a = seam::make_tow(t);
      c.b = c.a;
      c.map_b = random_rotation(r, {5, 0, 0}, what);
      d << "tow " << t.segments_along << "x" << t.segments_around << ", copy " << what;
    }
    c.keep_exact = r.coin();
    d << (c.keep_exact ? ", kept exact" : ", rounded");
  } else if (f == "sheared") {
    const int n = 1 << r.range(0, 3);
    c.a = grid_box(zero, two, {n, n, n}, r.coin());
    c.b = r.coin() ? c.a : grid_box({0.25, 0.5, 0.75}, {2.25, 2.5, 2.75}, {n, n, n});
    const int row = r.pick(3), col = (row + 1 + r.pick(2)) % 3;
    const long q = r.of(std::vector<long>{3, 5, 7, 10}), p = r.range(1, int(q) - 1);
    c.map_b = shear(row, col, p, q, {1, 1, 1});
    c.keep_exact = r.coin();
    d << "grid box " << n << ", sheared x" << row << " += " << p << "/" << q << " x" << col
      << (c.keep_exact ? ", kept exact" : ", rounded");
  } else if (f == "magnitude") {
    // One of the axis-aligned configurations, scaled by 10^k and translated by 10^k (3/7, ...).
    Case base;
    base.family = r.of(std::vector<std::string>{"vertices", "edges", "endpoints", "coplanar", "shifted"});
    make_family_case(base, r);
    c.a = base.a;
    c.b = base.b;
    const int k = r.of(std::vector<int>{-8, -6, -4, -3, 3, 4, 6, 8});
    FT f10 = 1;
    for (int i = 0; i < std::abs(k); ++i) f10 = k > 0 ? f10 * 10 : f10 / 10;
    const std::array<FT, 3> t = {f10 * ratio(3, 7), f10 * ratio(-5, 11), f10 * ratio(1, 3)};
    const bool translate = r.coin();
    c.map_a = c.map_b = scaling(f10, translate ? t : std::array<FT, 3>{0, 0, 0});
    c.keep_exact = r.pick(3) == 0;
    d << base.family << " [" << base.description << "] scaled by 1e" << k << (translate ? " and translated" : "")
      << (c.keep_exact ? ", kept exact" : ", rounded");
  } else if (f == "resolution") {
    if (r.coin()) {
      const int nb = r.range(16, 32);
      c.a = grid_box(zero, two, {1, 1, 1});
      const double s = 0.5 + 0.25 * r.pick(4);
      c.b = grid_box({s, s / 2, s / 4}, {s + 2, s / 2 + 2, s / 4 + 2}, {nb, nb, nb}, r.coin());
      d << "box of 12 faces and a box of " << c.b.triangles.size() << " faces";
    } else {
      const bool coarse_a = r.coin();
      const int fine_along = r.range(150, 300), fine_around = r.range(24, 40);
      const int coarse_along = r.range(4, 10), coarse_around = r.range(4, 8);
      if (coarse_a)
        tow_crossover(r, c, coarse_along, coarse_around, fine_along, fine_around);
      else
        tow_crossover(r, c, fine_along, fine_around, coarse_along, coarse_around);
      d << "tows of " << c.a.triangles.size() << " and " << c.b.triangles.size() << " faces";
    }
    if (r.coin()) std::swap(c.a, c.b);
  } else if (f == "tows") {
    const int around_b = r.range(8, 32), along_b = r.range(20, 120), around_a = r.range(8, 32), along_a = r.range(20, 120);
    const double dz = tow_crossover(r, c, along_a, around_a, along_b, around_b);
    d << "tows of " << c.a.triangles.size() << " and " << c.b.triangles.size() << " faces (" << along_a << "x"
      << around_a << ", " << along_b << "x" << around_b << ", warp at z " << dz << ")";
    if (r.coin()) {
      std::string what;
      c.map_a = c.map_b = random_rotation(r, {0, 0, 0}, what);
      c.keep_exact = r.coin();
      d << ", both " << what << (c.keep_exact ? ", kept exact" : ", rounded");
    }
  } else if (f == "embed") {
    // One mesh and a curve through its vertices and along its edges.
    c.embed = true;
    if (r.pick(3) != 0) {
      // A polyline on the top face of a grid box: steps between grid points (along edges, along
      // or across the split diagonals, through vertices) and half steps (to edge midpoints), and
      // maybe down the side x = 2.
      const int n = 1 << r.range(1, 3);
      const double h = 2.0 / n;
      c.a = grid_box(zero, two, {n, n, n}, r.coin());
      std::vector<Point3d> curve;
      // Monotone in x (no self-crossing), from the border x = 0 or from inside.
      int i = r.coin() ? 0 : r.range(0, n), j = r.range(0, 2 * n);  // in half steps
      curve.push_back({i * h / 2, j * h / 2, 2.0});
      while (i < 2 * n && curve.size() < 12) {
        const int di = std::min(r.range(1, 2), 2 * n - i);
        int dj = r.range(-2, 2);
        if (j + dj < 0 || j + dj > 2 * n) dj = -dj;
        i += di, j += dj;
        curve.push_back({i * h / 2, j * h / 2, 2.0});
      }
      if (i == 2 * n && r.coin()) curve.push_back({2.0, j * h / 2, 2.0 - h * r.range(1, 2 * n) / 2});  // down the side
      c.curves.push_back(curve);
      d << "grid box " << n << ", curve of " << curve.size() << " points on the top face";
    } else {
      // A tow and a closed curve through the vertices of one ring (along its edges) or zigzagging
      // between two rings (along or across the quads' diagonals).
      seam::TowOptions t = small_tow(r);
      c.a = seam::make_tow(t);
      const int ring = r.range(1, t.segments_along - 2), m = t.segments_around;
      const bool zig = r.coin();
      std::vector<Point3d> curve;
      for (int j = 0; j < m; ++j) {
        const int ri = zig && j % 2 ? ring + 1 : ring;
        curve.push_back(c.a.points[std::size_t(ri * m + j)]);
      }
      if (zig && m % 2) curve.pop_back();
      curve.push_back(curve.front());
      c.curves.push_back(curve);
      d << "tow " << t.segments_along << "x" << m << ", closed curve " << (zig ? "zigzag between rings " : "along ring ")
        << ring;
    }
    if (r.pick(4) == 0) {  // scaled by a power of 2 (exact) or 10^-4 (rounded)
      const double f = r.coin() ? 1024.0 * 1024.0 : 1e-4;
      for (auto& p : c.a.points)
        for (auto& x : p) x *= f;
      for (auto& cv : c.curves)
        for (auto& p : cv)
          for (auto& x : p) x *= f;
      d << ", scaled by " << f;
    }
  }
  c.description = d.str();
}

Case make_case(int id, std::uint64_t seed) {
  Case c;
  c.id = id;
  c.family = families[std::size_t(id) % families.size()];
  Rng r(seed * 0x9E3779B97F4A7C15ull + std::uint64_t(id) * 1000003ull + 17);
  make_family_case(c, r);
  c.snap_tol = r.pick(3) == 0 ? -1.0 : 0.0;
  if (c.snap_tol < 0) c.description += ", default snapping";
  return c;
}

// ------------------------------------------------------------------------------ running one case

/// A mesh with the same connectivity and each point mapped by `pt` (vertex and face indices kept).
template <class KOut, class KIn, class F> seam::Mesh<KOut> convert(const seam::Mesh<KIn>& m, F pt) {
  seam::Mesh<KOut> out;
  using VO = typename seam::Mesh<KOut>::Vertex_index;
  std::vector<VO> map(m.number_of_vertices() + m.number_of_removed_vertices());
  for (auto v : m.vertices()) map[std::size_t(v)] = out.add_vertex(pt(m.point(v)));
  for (auto f : m.faces()) {
    std::vector<VO> vs;
    for (auto v : CGAL::vertices_around_face(m.halfedge(f), m)) vs.push_back(map[std::size_t(v)]);
    if (out.add_face(vs) == seam::Mesh<KOut>::null_face()) throw std::runtime_error("convert: add_face failed");
  }
  return out;
}

template <class K> typename K::Point_3 round_point(const EK::Point_3& p) {
  const auto& e = CGAL::exact(p);
  return typename K::Point_3(CGAL::to_double(e.x()), CGAL::to_double(e.y()), CGAL::to_double(e.z()));
}

template <class K> EK::Point_3 to_exact(const typename K::Point_3& p) {
  if constexpr (std::is_same_v<K, EK>) {
    return p;
  } else {
    return EK::Point_3(CGAL::to_double(p.x()), CGAL::to_double(p.y()), CGAL::to_double(p.z()));
  }
}

/// The input of kernel K for a mesh of the case: the exact images under `map`; for K = Exact
/// kept exact when the case says so, else rounded to double.
template <class K> seam::Mesh<K> input_mesh(const TriangleSoup& soup, const Affine& map, bool keep_exact) {
  seam::validate_triangle_mesh(soup, "generated mesh");
  const seam::Mesh<EK> m = seam::mesh_from_soup<EK>(soup, "generated mesh");
  if (map.identity) {
    if constexpr (std::is_same_v<K, EK>) return m;
    else return seam::mesh_from_soup<K>(soup, "generated mesh");
  }
  if constexpr (std::is_same_v<K, EK>)
    if (keep_exact) return convert<EK, EK>(m, [&](const EK::Point_3& p) { return map(p); });
  return convert<K, EK>(m, [&](const EK::Point_3& p) { return round_point<K>(map(p)); });
}

double bbox_diagonal(const seam::Mesh<EK>& a, const seam::Mesh<EK>& b) {
  CGAL::Bbox_3 box;
  for (auto v : a.vertices()) box += a.point(v).bbox();
  for (auto v : b.vertices()) box += b.point(v).bbox();
  return std::sqrt(std::pow(box.xmax() - box.xmin(), 2) + std::pow(box.ymax() - box.ymin(), 2) +
                   std::pow(box.zmax() - box.zmin(), 2));
}

enum class Outcome { valid, invalid, exception, crash, timeout };
const char* outcome_name(Outcome o) {
  switch (o) {
    case Outcome::valid: return "valid";
    case Outcome::invalid: return "invalid";
    case Outcome::exception: return "exception";
    case Outcome::crash: return "crash";
    case Outcome::timeout: return "timeout";
  }
  return "?";
}

struct RunResult {
  Outcome outcome = Outcome::crash;
  std::string detail;
  double seconds = 0;
};

template <class K> RunResult run_pair(const Case& c) {
  const auto to_ek = [](const typename K::Point_3& p) { return to_exact<K>(p); };
  seam::Mesh<K> a = input_mesh<K>(c.a, c.map_a, c.keep_exact), b = input_mesh<K>(c.b, c.map_b, c.keep_exact);
  // The reference input of the check: what this kernel was given, exactly.
  const seam::Mesh<EK> ea = convert<EK, K>(a, to_ek), eb = convert<EK, K>(b, to_ek);
  seam::PairOptions o;
  o.embed.snap_tol = c.snap_tol;
  const seam::PairResult<K> res = seam::pair<K>(a, b, o);
  std::vector<seam::Polyline<EK>> curves;
  for (const auto& cv : res.curves) {
    curves.emplace_back();
    for (const auto& p : cv) curves.back().push_back(to_ek(p));
  }
  const seam::Mesh<EK> ea2 = convert<EK, K>(a, to_ek), eb2 = convert<EK, K>(b, to_ek);
  const double tol = res.stats.snap_tol + 1e-9 * bbox_diagonal(ea, eb);
  // (check 5, vertices apart as written, only where the inputs are doubles: a file can hold them)
  const seam::PairCheckReport report = seam::check_pair<EK>(ea, eb, ea2, eb2, curves, tol, nullptr, !c.keep_exact);
  RunResult rr;
  std::ostringstream d;
  d << res.curves.size() << " curve(s), " << res.stats.curve_vertices << " points";
  if (report.ok()) {
    rr.outcome = Outcome::valid;
  } else {
    rr.outcome = Outcome::invalid;
    d << "; check_pair: " << report.problems.front();
    if (report.problems.size() > 1) d << " (+" << report.problems.size() - 1 << " more)";
  }
  rr.detail = d.str();
  return rr;
}

template <class K> RunResult run_embed(const Case& c) {
  seam::Mesh<K> mesh = input_mesh<K>(c.a, c.map_a, c.keep_exact);
  const seam::Mesh<K> input = mesh;
  const auto curves = seam::to_kernel<K>(c.curves);
  seam::EmbedOptions o;
  o.snap_tol = c.snap_tol;
  const seam::EmbedResult<K> res = seam::embed<K>(mesh, curves, o);
  std::vector<std::string> problems = seam::check_valid_mesh<EK>(
      convert<EK, K>(mesh, [](const typename K::Point_3& p) { return to_exact<K>(p); }), CGAL::is_closed(input));
  for (const auto& p : seam::check_curves_embedded<K>(mesh, res)) problems.push_back(p);
  if (c.snap_tol == 0) {
    for (const auto& p : seam::check_same_surface<K>(input, mesh)) problems.push_back(p);
  } else {
    for (const auto& p : seam::check_vertex_moves<K>(input, mesh, res.stats.snap_tol)) problems.push_back(p);
  }
  RunResult rr;
  std::ostringstream d;
  d << res.stats.curve_nodes_out << " curve vertices, " << res.stats.faces_crossed << " faces crossed";
  if (problems.empty()) {
    rr.outcome = Outcome::valid;
  } else {
    rr.outcome = Outcome::invalid;
    d << "; " << problems.front();
    if (problems.size() > 1) d << " (+" << problems.size() - 1 << " more)";
  }
  rr.detail = d.str();
  return rr;
}

RunResult run_in_process(const Case& c, seam::KernelKind kind) {
  try {
    return seam::with_kernel(kind, [&](auto k) {
      using K = decltype(k);
      return c.embed ? run_embed<K>(c) : run_pair<K>(c);
    });
  } catch (const seam::InternalError& e) {
    return {Outcome::exception, std::string("InternalError: ") + e.what()};
  } catch (const seam::InvalidInput& e) {
    return {Outcome::exception, std::string("InvalidInput: ") + e.what()};
  } catch (const std::bad_alloc&) {
    return {Outcome::exception, "std::bad_alloc (memory limit)"};
  } catch (const std::exception& e) {
    return {Outcome::exception, std::string("exception: ") + e.what()};
  }
}

/// Runs the case in a child process; kills it after `timeout` seconds.
RunResult run_in_child(const Case& c, seam::KernelKind kind, double timeout) {
  int fds[2];
  if (::pipe(fds) != 0) return {Outcome::crash, "pipe failed"};
  std::fflush(nullptr);
  const auto start = std::chrono::steady_clock::now();
  const pid_t pid = ::fork();
  if (pid < 0) return {Outcome::crash, "fork failed"};
  if (pid == 0) {
    ::close(fds[0]);
    rlimit lim{};
    lim.rlim_cur = lim.rlim_max = rlim_t(6) << 30;  // 6 GiB: a runaway allocation is an exception
    ::setrlimit(RLIMIT_AS, &lim);
    const RunResult r = run_in_process(c, kind);
    std::string msg = std::string(1, char('0' + int(r.outcome))) + r.detail.substr(0, 2000);
    std::size_t done = 0;
    while (done < msg.size()) {
      const ssize_t w = ::write(fds[1], msg.data() + done, msg.size() - done);
      if (w <= 0) break;
      done += std::size_t(w);
    }
    ::close(fds[1]);
    ::_exit(0);
  }
  ::close(fds[1]);
  std::string msg;
  int status = 0;
  bool exited = false, killed = false;
  for (;;) {
    const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (elapsed > timeout) {
      ::kill(pid, SIGKILL);
      ::waitpid(pid, &status, 0);
      killed = true;
      break;
    }
    pollfd p{fds[0], POLLIN, 0};
    if (::poll(&p, 1, 20) > 0) {
      char buf[4096];
      const ssize_t n = ::read(fds[0], buf, sizeof buf);
      if (n > 0) msg.append(buf, std::size_t(n));
    }
    const pid_t w = ::waitpid(pid, &status, WNOHANG);
    if (w == pid) {
      exited = true;
      break;
    }
  }
  if (exited) {  // what the child wrote and is still in the pipe
    char buf[4096];
    ssize_t n;
    ::fcntl(fds[0], F_SETFL, O_NONBLOCK);
    while ((n = ::read(fds[0], buf, sizeof buf)) > 0) msg.append(buf, std::size_t(n));
  }
  ::close(fds[0]);
  RunResult r;
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (killed) {
    r.outcome = Outcome::timeout;
    r.detail = "killed after " + std::to_string(timeout) + " s";
  } else if (WIFSIGNALED(status)) {
    r.outcome = Outcome::crash;
    r.detail = std::string("signal ") + std::to_string(WTERMSIG(status)) + " (" + ::strsignal(WTERMSIG(status)) + ")";
  } else if (msg.empty() || msg[0] < '0' || msg[0] > '4') {
    r.outcome = Outcome::crash;
    r.detail = "exited with status " + std::to_string(WEXITSTATUS(status)) + " without a result";
  } else {
    r.outcome = Outcome(msg[0] - '0');
    r.detail = msg.substr(1);
  }
  return r;
}

std::string json_escape(const std::string& s) {
  std::string o;
  for (char ch : s) {
    if (ch == '"' || ch == '\\') o += '\\', o += ch;
    else if (static_cast<unsigned char>(ch) < 0x20) o += ' ';
    else o += ch;
  }
  return o;
}

struct Counts {
  std::size_t cases = 0, by[5] = {0, 0, 0, 0, 0};
};

}  // namespace

int main(int argc, char** argv) {
  std::uint64_t seed = 1;
  int cases = 252;
  double timeout = 60;
  std::string filter, dump, snap = "case";
  std::vector<seam::KernelKind> kernels = {seam::KernelKind::exact, seam::KernelKind::filtered, seam::KernelKind::float_};
  bool json = false, verbose = false, contract = false;
  auto usage = [] {
    std::cerr << "usage: seam_robustness [--seed N] [--cases N] [--timeout S] [--filter SUBSTR] "
                 "[--kernels exact,filtered,float] [--json] [--verbose] [--dump DIR] [--snap case|0|auto] "
                 "[--contract]\n";
    return 2;
  };
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) throw std::invalid_argument(a + " needs a value");
      return argv[++i];
    };
    try {
      if (a == "--seed") seed = std::stoull(value());
      else if (a == "--cases") cases = std::stoi(value());
      else if (a == "--timeout") timeout = std::stod(value());
      else if (a == "--filter") filter = value();
      else if (a == "--dump") dump = value();
      else if (a == "--snap") snap = value();
      else if (a == "--json") json = true;
      else if (a == "--verbose") verbose = true;
      else if (a == "--contract") contract = true;
      else if (a == "--kernels") {
        kernels.clear();
        std::stringstream s(value());
        std::string k;
        while (std::getline(s, k, ',')) {
          if (k == "exact") kernels.push_back(seam::KernelKind::exact);
          else if (k == "filtered") kernels.push_back(seam::KernelKind::filtered);
          else if (k == "float") kernels.push_back(seam::KernelKind::float_);
          else throw std::invalid_argument("unknown kernel " + k);
        }
      } else if (a == "-h" || a == "--help") {
        usage();
        return 0;
      } else {
        throw std::invalid_argument("unknown argument " + a);
      }
    } catch (const std::exception& e) {
      std::cerr << "seam_robustness: " << e.what() << "\n";
      return usage();
    }
  }
  if (cases < 0 || !(timeout > 0)) return usage();

  std::map<std::string, Counts> totals;                                // kernel -> counts
  std::map<std::string, std::map<std::string, Counts>> by_family;      // family -> kernel -> counts
  std::ostringstream failures;                                         // JSON objects
  std::size_t failure_count = 0;
  bool exact_all_valid = true, contract_kept = true;
  std::map<std::string, double> seconds;
  for (int id = 0; id < cases; ++id) {
    Case c;
    try {
      c = make_case(id, seed);
    } catch (const std::exception& e) {
      std::cerr << "seam_robustness: case " << id << " could not be generated: " << e.what() << "\n";
      return 3;
    }
    if (snap == "0") c.snap_tol = 0;
    if (snap == "auto") c.snap_tol = -1;
    if (!filter.empty() && c.family.find(filter) == std::string::npos &&
        c.description.find(filter) == std::string::npos && filter != "case:" + std::to_string(id))
      continue;
    if (!dump.empty()) {  // the inputs as the filtered kernel gets them (rounded), for `seam pair`
      for (int m = 0; m < (c.embed ? 1 : 2); ++m) {
        const auto mesh = input_mesh<seam::Filtered>(m ? c.b : c.a, m ? c.map_b : c.map_a, c.keep_exact);
        seam::write_triangle_mesh(seam::soup_from_mesh<seam::Filtered>(mesh),
                                  dump + "/case" + std::to_string(id) + (m ? "_b.off" : "_a.off"));
      }
      if (c.embed) seam::write_polylines(c.curves, dump + "/case" + std::to_string(id) + "_curves.txt");
    }
    for (auto kind : kernels) {
      const std::string kn = seam::kernel_name(kind);
      const RunResult r = run_in_child(c, kind, timeout);
      ++totals[kn].cases;
      ++totals[kn].by[int(r.outcome)];
      ++by_family[c.family][kn].cases;
      ++by_family[c.family][kn].by[int(r.outcome)];
      seconds[kn] += r.seconds;
      if (kind == seam::KernelKind::exact && r.outcome != Outcome::valid) exact_all_valid = false;
      if (r.outcome != Outcome::valid && r.outcome != Outcome::exception) contract_kept = false;
      if (r.outcome != Outcome::valid) {
        failures << (failure_count++ ? ",\n    " : "\n    ") << "{\"case\": " << c.id << ", \"family\": \"" << c.family
                 << "\", \"kernel\": \"" << kn << "\", \"outcome\": \"" << outcome_name(r.outcome)
                 << "\", \"description\": \"" << json_escape(c.description) << "\", \"detail\": \""
                 << json_escape(r.detail) << "\"}";
      }
      if (!json && (verbose || (r.outcome != Outcome::valid && kind == seam::KernelKind::exact)))
        std::cout << "case " << c.id << " [" << c.family << "] " << kn << ": " << outcome_name(r.outcome) << " ("
                  << r.seconds << " s) " << c.description << " -- " << r.detail << std::endl;
    }
  }

  auto counts_json = [](const Counts& k) {
    std::ostringstream s;
    s << "{\"cases\": " << k.cases;
    for (int o = 0; o < 5; ++o) s << ", \"" << outcome_name(Outcome(o)) << "\": " << k.by[o];
    s << "}";
    return s.str();
  };
  if (json) {
    std::cout << "{\"seed\": " << seed << ", \"timeout\": " << timeout << ",\n \"kernels\": {";
    bool first = true;
    for (auto kind : kernels) {
      const std::string kn = seam::kernel_name(kind);
      std::cout << (first ? "" : ",") << "\n  \"" << kn << "\": " << counts_json(totals[kn]);
      first = false;
    }
    std::cout << "},\n \"seconds\": {";
    first = true;
    for (const auto& [kn, s] : seconds) std::cout << (first ? "" : ", ") << "\"" << kn << "\": " << s, first = false;
    std::cout << "},\n \"families\": {";
    first = true;
    for (const auto& [fam, ks] : by_family) {
      std::cout << (first ? "" : ",") << "\n  \"" << fam << "\": {";
      bool f2 = true;
      for (const auto& [kn, k] : ks) std::cout << (f2 ? "" : ", ") << "\"" << kn << "\": " << counts_json(k), f2 = false;
      std::cout << "}";
      first = false;
    }
    std::cout << "},\n \"failures\": [" << failures.str() << "]}\n";
  } else {
    std::printf("%-10s %6s %6s %8s %10s %6s %8s %9s\n", "kernel", "cases", "valid", "invalid", "exception", "crash",
                "timeout", "seconds");
    for (auto kind : kernels) {
      const std::string kn = seam::kernel_name(kind);
      const Counts& k = totals[kn];
      std::printf("%-10s %6zu %6zu %8zu %10zu %6zu %8zu %9.1f\n", kn.c_str(), k.cases, k.by[0], k.by[1], k.by[2], k.by[3],
                  k.by[4], seconds[kn]);
    }
    std::printf("\nvalid / cases per family\n%-13s", "family");
    for (auto kind : kernels) std::printf(" %9s", seam::kernel_name(kind));
    std::printf("\n");
    for (const auto& [fam, ks] : by_family) {
      std::printf("%-13s", fam.c_str());
      for (auto kind : kernels) {
        auto it = ks.find(seam::kernel_name(kind));
        if (it == ks.end()) std::printf(" %9s", "-");
        else std::printf(" %5zu/%-3zu", it->second.by[0], it->second.cases);
      }
      std::printf("\n");
    }
  }
  return (contract ? contract_kept : exact_all_valid) ? 0 : 1;
}
