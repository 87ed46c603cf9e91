// seam: generated tow geometry (see generate.h).
//
// The smooth surface is P(s, phi) = X(c(s) + u(phi) B + v(phi) N(s)) where
//   c(s) = (s, 0, A sin(2 pi s / lambda))   the crimped path (in the xz plane),
//   T(s) = c'(s) / |c'(s)|,  B = (0, 1, 0),  N(s) = T(s) x B   (so N = +z for a straight path),
//   (u, v) the section point at angle phi, X the rigid transform (rotate_z, rotate_x, translate).
// Since the path is planar, (T, B, N) is a rotation-minimising frame: the sections do not twist.
//
// The mesh has segments_along + 1 rings of segments_around vertices (ring i at s_i = i * length /
// segments_along, vertex j at phi_j = 2 pi j / segments_around), every vertex exactly on the
// smooth surface. Quads are split along alternating diagonals (checkerboard). With caps, one
// centre vertex per end (on the path) and a fan of triangles close the tube.
//
// Orientation: dP/dphi x dP/ds points outwards (B x N = T, the section runs counter-clockwise
// about T), so the quad (i,j) (i,j+1) (i+1,j+1) (i+1,j) is counter-clockwise seen from outside.
//
// SPDX-License-Identifier: GPL-3.0-or-later

#include <seam/generate.h>

#include <cmath>
#include <cstddef>
#include <string>

namespace seam {
namespace {

constexpr double two_pi = 6.283185307179586476925286766559;

Point3d add(const Point3d& p, const Point3d& q) { return {p[0] + q[0], p[1] + q[1], p[2] + q[2]}; }
Point3d scale(double t, const Point3d& p) { return {t * p[0], t * p[1], t * p[2]}; }
Point3d cross(const Point3d& p, const Point3d& q) {
  return {p[1] * q[2] - p[2] * q[1], p[2] * q[0] - p[0] * q[2], p[0] * q[1] - p[1] * q[0]};
}

void require(bool ok, const std::string& what) {
  if (!ok) throw InvalidInput("tow options: " + what);
}

void validate(const TowOptions& o) {
  require(std::isfinite(o.length) && o.length > 0, "length must be positive and finite");
  require(std::isfinite(o.half_width) && o.half_width > 0, "half_width must be positive and finite");
  require(std::isfinite(o.half_height) && o.half_height > 0,
          "half_height must be positive and finite");
  require(o.section != Section::lenticular || o.half_height <= o.half_width,
          "a lenticular section needs half_height <= half_width");
  require(std::isfinite(o.crimp_amplitude), "crimp_amplitude must be finite");
  require(std::isfinite(o.crimp_wavelength) && o.crimp_wavelength > 0,
          "crimp_wavelength must be positive and finite");
  require(o.heights.empty() || (std::isfinite(o.heights_spacing) && o.heights_spacing > 0),
          "heights_spacing must be positive and finite");
  for (double h : o.heights) require(std::isfinite(h), "heights must be finite");
  require(o.segments_along >= 1, "segments_along must be at least 1");
  require(o.segments_around >= 3, "segments_around must be at least 3");
  require(std::isfinite(o.rotate_z) && std::isfinite(o.rotate_x), "rotations must be finite");
  require(std::isfinite(o.translate[0]) && std::isfinite(o.translate[1]) &&
              std::isfinite(o.translate[2]),
          "translate must be finite");
}

/// Section point (u along B, v along N) at angle phi.
std::array<double, 2> section_point(const TowOptions& o, double phi) {
  const double a = o.half_width, b = o.half_height;
  const double c = std::cos(phi), s = std::sin(phi);
  if (o.section == Section::elliptical) return {a * c, b * s};
  // Lens: two circular arcs of radius R through (+-a, 0) and (0, +-b).
  const double x = a * c;
  const double R = (a * a + b * b) / (2.0 * b);
  double h = std::sqrt(std::fmax(0.0, R * R - x * x)) - (R - b);
  h = std::fmax(0.0, h);  // rounding near the tips
  return {x, s < 0 ? -h : h};
}

/// The untransformed point of the tube at path parameter s with section coordinates (u, v).
/// Height and slope of the path at s.
std::array<double, 2> path_height(const TowOptions& o, double s) {
  if (o.heights.empty()) {
    const double k = two_pi / o.crimp_wavelength;
    const double A = o.crimp_amplitude;
    return {A * std::sin(k * s), A * k * std::cos(k * s)};
  }
  // Between the crossings k and k + 1 (at (k + 0.5) * spacing and (k + 1.5) * spacing).
  const double d = o.heights_spacing;
  const double x = s / d - 0.5;
  const double k = std::floor(x), t = x - k;
  const long n = static_cast<long>(o.heights.size());
  const auto at = [&](double index) {
    const long i = ((static_cast<long>(index) % n) + n) % n;
    return o.heights[static_cast<std::size_t>(i)];
  };
  const double z0 = at(k), z1 = at(k + 1);
  constexpr double pi = two_pi / 2;
  return {z0 + (z1 - z0) * 0.5 * (1 - std::cos(pi * t)), (z1 - z0) * 0.5 * pi * std::sin(pi * t) / d};
}

Point3d tube_point(const TowOptions& o, double s, double u, double v) {
  const auto [z, dz] = path_height(o, s);
  const Point3d c = {s, 0.0, z};
  const double len = std::sqrt(1.0 + dz * dz);
  const Point3d T = {1.0 / len, 0.0, dz / len};
  const Point3d B = {0.0, 1.0, 0.0};
  const Point3d N = cross(T, B);  // (-dz, 0, 1) / len
  return add(c, add(scale(u, B), scale(v, N)));
}

/// Rotation about z by rotate_z, then about x by rotate_x, then translation.
Point3d transform(const TowOptions& o, const Point3d& p) {
  const double cz = std::cos(o.rotate_z), sz = std::sin(o.rotate_z);
  const double cx = std::cos(o.rotate_x), sx = std::sin(o.rotate_x);
  const Point3d q = {cz * p[0] - sz * p[1], sz * p[0] + cz * p[1], p[2]};
  const Point3d r = {q[0], cx * q[1] - sx * q[2], sx * q[1] + cx * q[2]};
  return add(r, o.translate);
}

}  // namespace

Point3d tow_surface_point(const TowOptions& options, double s, double phi) {
  validate(options);
  const auto uv = section_point(options, phi);
  return transform(options, tube_point(options, s, uv[0], uv[1]));
}

TriangleSoup make_tow(const TowOptions& options) {
  validate(options);
  const std::size_t along = static_cast<std::size_t>(options.segments_along);
  const std::size_t around = static_cast<std::size_t>(options.segments_around);

  TriangleSoup soup;
  soup.points.reserve((along + 1) * around + 2);
  soup.triangles.reserve(2 * along * around + (options.capped ? 2 * around : 0));

  std::vector<std::array<double, 2>> section(around);
  for (std::size_t j = 0; j < around; ++j)
    section[j] = section_point(options, two_pi * static_cast<double>(j) / static_cast<double>(around));

  for (std::size_t i = 0; i <= along; ++i) {
    // The last ring sits exactly at s = length.
    const double s = i == along ? options.length
                                : options.length * static_cast<double>(i) / static_cast<double>(along);
    for (std::size_t j = 0; j < around; ++j)
      soup.points.push_back(transform(options, tube_point(options, s, section[j][0], section[j][1])));
  }
  auto vid = [around](std::size_t i, std::size_t j) { return i * around + j % around; };

  for (std::size_t i = 0; i < along; ++i) {
    for (std::size_t j = 0; j < around; ++j) {
      const std::size_t q0 = vid(i, j), q1 = vid(i, j + 1), q2 = vid(i + 1, j + 1), q3 = vid(i + 1, j);
      if ((i + j) % 2 == 0) {
        soup.triangles.push_back({q0, q1, q2});
        soup.triangles.push_back({q0, q2, q3});
      } else {
        soup.triangles.push_back({q0, q1, q3});
        soup.triangles.push_back({q1, q2, q3});
      }
    }
  }

  if (options.capped) {
    const std::size_t c0 = soup.points.size();
    soup.points.push_back(transform(options, tube_point(options, 0.0, 0.0, 0.0)));
    const std::size_t c1 = soup.points.size();
    soup.points.push_back(transform(options, tube_point(options, options.length, 0.0, 0.0)));
    for (std::size_t j = 0; j < around; ++j) {
      soup.triangles.push_back({c0, vid(0, j + 1), vid(0, j)});            // outward normal -T
      soup.triangles.push_back({c1, vid(along, j), vid(along, j + 1)});    // outward normal +T
    }
  }
  return soup;
}

std::vector<Point3d> make_ring_curve(const TowOptions& options, double s_center, double tilt,
                                     int samples) {
  validate(options);
  require(samples >= 3, "a ring curve needs at least 3 samples");
  require(std::isfinite(s_center) && std::isfinite(tilt), "ring centre and tilt must be finite");
  require(s_center - std::fabs(tilt) >= 0.0 && s_center + std::fabs(tilt) <= options.length,
          "the ring curve (s_center +- |tilt|) must stay within [0, length]");
  std::vector<Point3d> curve;
  curve.reserve(static_cast<std::size_t>(samples) + 1);
  for (int k = 0; k < samples; ++k) {
    const double phi = two_pi * static_cast<double>(k) / static_cast<double>(samples);
    curve.push_back(tow_surface_point(options, s_center + tilt * std::cos(phi), phi));
  }
  curve.push_back(curve.front());
  return curve;
}

namespace {

/// The inverse of the rigid transform.
Point3d untransform(const TowOptions& o, const Point3d& p) {
  const Point3d r = {p[0] - o.translate[0], p[1] - o.translate[1], p[2] - o.translate[2]};
  const double cz = std::cos(o.rotate_z), sz = std::sin(o.rotate_z);
  const double cx = std::cos(o.rotate_x), sx = std::sin(o.rotate_x);
  const Point3d q = {r[0], cx * r[1] + sx * r[2], -sx * r[1] + cx * r[2]};
  return {cz * q[0] + sz * q[1], -sz * q[0] + cz * q[1], q[2]};
}

/// Surface parameters (s, phi) of a point near the tow's surface: s from the path's direction,
/// phi from the section coordinates (a first guess for Gauss-Newton).
std::array<double, 2> surface_parameters(const TowOptions& o, const Point3d& p) {
  const Point3d q = untransform(o, p);
  const double s = std::fmin(std::fmax(q[0], 0.0), o.length);
  const double u = q[1], v = q[2] - path_height(o, s)[0];
  return {s, std::atan2(v / o.half_height, u / o.half_width)};
}

}  // namespace

std::vector<Point3d> smooth_intersection_points(const TowOptions& a, const TowOptions& b,
                                                const std::vector<Point3d>& near) {
  validate(a);
  validate(b);
  std::vector<Point3d> result;
  result.reserve(near.size());
  for (const Point3d& seed : near) {
    const auto pa = surface_parameters(a, seed), pb = surface_parameters(b, seed);
    std::array<double, 4> x = {pa[0], pa[1], pb[0], pb[1]};  // (s_a, phi_a, s_b, phi_b)
    auto residual = [&](const std::array<double, 4>& y) {
      const Point3d p = tow_surface_point(a, y[0], y[1]), q = tow_surface_point(b, y[2], y[3]);
      return Point3d{p[0] - q[0], p[1] - q[1], p[2] - q[2]};
    };
    Point3d f = residual(x);
    const double scale = std::fmax(a.half_width, b.half_width);
    bool converged = false;
    for (int iteration = 0; iteration < 50 && !converged; ++iteration) {
      // Jacobian by central differences; the minimal-norm step -J^T (J J^T)^-1 f.
      double J[3][4];
      for (int k = 0; k < 4; ++k) {
        const double h = 1e-7;
        auto plus = x, minus = x;
        plus[std::size_t(k)] += h;
        minus[std::size_t(k)] -= h;
        const Point3d fp = residual(plus), fm = residual(minus);
        for (int r = 0; r < 3; ++r) J[r][k] = (fp[std::size_t(r)] - fm[std::size_t(r)]) / (2 * h);
      }
      double M[3][3];
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) {
          M[r][c] = 0;
          for (int k = 0; k < 4; ++k) M[r][c] += J[r][k] * J[c][k];
        }
      const double det = M[0][0] * (M[1][1] * M[2][2] - M[1][2] * M[2][1]) -
                         M[0][1] * (M[1][0] * M[2][2] - M[1][2] * M[2][0]) +
                         M[0][2] * (M[1][0] * M[2][1] - M[1][1] * M[2][0]);
      if (!(std::fabs(det) > 0)) break;
      // w = M^-1 f (Cramer), step = -J^T w
      double w[3];
      for (int c = 0; c < 3; ++c) {
        double N[3][3];
        for (int r = 0; r < 3; ++r)
          for (int k = 0; k < 3; ++k) N[r][k] = k == c ? f[std::size_t(r)] : M[r][k];
        w[c] = (N[0][0] * (N[1][1] * N[2][2] - N[1][2] * N[2][1]) - N[0][1] * (N[1][0] * N[2][2] - N[1][2] * N[2][0]) +
                N[0][2] * (N[1][0] * N[2][1] - N[1][1] * N[2][0])) /
               det;
      }
      for (int k = 0; k < 4; ++k) x[std::size_t(k)] -= J[0][k] * w[0] + J[1][k] * w[1] + J[2][k] * w[2];
      x[0] = std::fmin(std::fmax(x[0], 0.0), a.length);
      x[2] = std::fmin(std::fmax(x[2], 0.0), b.length);
      f = residual(x);
      converged = std::sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]) < 1e-13 * scale;
    }
    require(converged, "smooth_intersection_points: a point did not converge onto both surfaces");
    result.push_back(tow_surface_point(a, x[0], x[1]));
  }
  return result;
}

CrossoverTows make_crossover(int weft_along, int weft_around, int warp_along, int warp_around,
                             Section warp_section, double warp_height) {
  CrossoverTows c;
  c.weft.segments_along = weft_along;
  c.weft.segments_around = weft_around;
  c.weft.translate = {-5.0, 0.0, 0.0};
  c.warp.section = warp_section;
  c.warp.crimp_amplitude = -0.3;
  c.warp.rotate_z = M_PI / 2;
  c.warp.translate = {0.0, -5.0, warp_height};
  c.warp.segments_along = warp_along;
  c.warp.segments_around = warp_around;
  return c;
}

std::vector<NamedTow> make_weave(const WeaveOptions& o) {
  const auto need = [](bool ok, const std::string& what) {
    if (!ok) throw InvalidInput("weave options: " + what);
  };
  need(o.warps >= 1 && o.wefts >= 1, "warps and wefts must be at least 1");
  need(o.over >= 1 && o.under >= 1, "over and under must be at least 1");
  need(std::isfinite(o.spacing) && o.spacing > 0, "spacing must be positive and finite");
  need(std::isfinite(o.overlap), "overlap must be finite");
  need(std::isfinite(o.half_height) && o.half_height > 0 && std::fabs(o.overlap) < 2 * o.half_height,
       "half_height must be positive and |overlap| < 2 half_height");
  need(o.segments_per_crossing >= 1 && o.segments_around >= 3,
       "segments_per_crossing must be at least 1 and segments_around at least 3");
  const double a = o.half_height - o.overlap / 2;  // |height| of a tow's path at its crossings
  const auto weft_over = [&](int i, int j) { return (i + j) % (o.over + o.under) < o.over; };
  std::vector<NamedTow> tows;
  // Vertices per ring: 2 mod 4, so that no vertex line runs along the top or bottom of a tow
  // (phi = pi/2, 3 pi/2), where the crossing tow's rings would meet it edge on edge within
  // rounding (the rotation by pi/2 is not exact): curve points 1e-16 apart.
  const auto two_mod_four = [](int n) { return n + ((6 - n % 4) % 4); };
  auto base = [&](int crossings) {
    TowOptions t;
    t.length = crossings * o.spacing;
    t.half_width = o.half_width;
    t.half_height = o.half_height;
    t.section = o.section;
    t.heights_spacing = o.spacing;
    t.segments_along = crossings * o.segments_per_crossing;
    t.segments_around = two_mod_four(o.segments_around);
    return t;
  };
  for (int j = 0; j < o.wefts; ++j) {
    TowOptions t = base(o.warps);
    for (int i = 0; i < o.warps; ++i) t.heights.push_back(weft_over(i, j) ? a : -a);
    t.translate = {0.0, (j + 0.5) * o.spacing, 0.0};
    tows.push_back({"weft" + std::to_string(j), t});
  }
  for (int i = 0; i < o.warps; ++i) {
    TowOptions t = base(o.wefts);
    t.segments_along += 1;  // a different resolution: the two meshes' vertices do not line up
    t.segments_around = two_mod_four(o.segments_around) + 4;
    for (int j = 0; j < o.wefts; ++j) t.heights.push_back(weft_over(i, j) ? -a : a);
    t.rotate_z = two_pi / 4;  // along +y
    t.translate = {(i + 0.5) * o.spacing, 0.0, 0.0};
    tows.push_back({"warp" + std::to_string(i), t});
  }
  for (const auto& t : tows) validate(t.options);
  return tows;
}

}  // namespace seam
