// seam fuzzing: the entry functions of the libFuzzer targets (fuzz/fuzz_*.cpp), shared with the
// regression test (test/test_fuzz_regressions.cpp), which feeds every committed corpus and crash
// file to the same function through the normal build.
//
// The contract checked: whatever the bytes, the library either succeeds or throws one of its
// typed exceptions (seam::Error: InvalidInput, IOError, InternalError). Anything else (another
// exception, a CGAL assertion, a crash, a sanitizer finding, a hang) is a bug.
//
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <seam/check.h>
#include <seam/io.h>
#include <seam/pair.h>

#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

namespace seam_fuzz {

/// A broken promise of the library found by a fuzz entry (not a seam::Error: escapes to the
/// fuzzer, which reports it as a crash, and fails the regression test).
struct ContractViolation : std::logic_error {
  using std::logic_error::logic_error;
};

/// Mesh readers: `data` is a whole file in `format` ("off", "obj", "ply", "stl"). A file that
/// passes parsing and validation must convert to a Surface_mesh without error.
inline void mesh_reader(const std::uint8_t* data, std::size_t size, const char* format) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  seam::TriangleSoup soup;
  try {
    soup = seam::parse_triangle_mesh(text, format, "fuzz");
  } catch (const seam::Error&) {
    return;
  }
  // Issue 22, class 5 (silent misreads): a UTF-8 byte-order mark changes nothing, and data
  // after what an OFF or PLY header declares is refused (it was read as the declared count).
  const std::string fmt = format;
  const bool has_bom = text.substr(0, 3) == "\xEF\xBB\xBF";
  if (fmt != "stl" && !has_bom) {
    seam::TriangleSoup with_bom;
    try {
      with_bom = seam::parse_triangle_mesh("\xEF\xBB\xBF" + std::string(text), format, "fuzz");
    } catch (const seam::Error& e) {
      throw ContractViolation(std::string("a byte-order mark made a valid file invalid: ") + e.what());
    }
    if (with_bom.triangles != soup.triangles || with_bom.points.size() != soup.points.size())
      throw ContractViolation("a byte-order mark changed the mesh");
  }
  if (fmt == "off" || fmt == "ply") {
    bool refused = false;
    try {
      seam::parse_triangle_mesh(std::string(text) + "\n3 0 1 2\n", format, "fuzz");
    } catch (const seam::InvalidInput&) {
      refused = true;
    }
    if (!refused) throw ContractViolation("data after the declared faces was accepted");
  }
  try {
    seam::check_no_self_intersection(soup, "fuzz");
  } catch (const seam::InvalidInput&) {
  }
  try {
    const auto mesh = seam::mesh_from_soup<seam::Filtered>(soup, "fuzz");
    if (mesh.number_of_faces() != soup.triangles.size()) throw ContractViolation("faces lost by mesh_from_soup");
  } catch (const seam::Error& e) {
    throw ContractViolation(std::string("a validated mesh failed to convert: ") + e.what());
  }
}

/// Polyline reader.
inline void polyline_reader(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    const auto polylines = seam::parse_polylines(text, "fuzz");
    if (polylines.empty()) throw ContractViolation("parse_polylines returned no polyline");
    for (const auto& p : polylines)
      if (p.empty()) throw ContractViolation("parse_polylines returned a polyline without points");
    // A UTF-8 byte-order mark changes nothing (issue 22, class 5).
    if (text.substr(0, 3) != "\xEF\xBB\xBF" &&
        seam::parse_polylines("\xEF\xBB\xBF" + std::string(text), "fuzz").size() != polylines.size())
      throw ContractViolation("a byte-order mark changed the polylines");
  } catch (const seam::Error&) {
  }
}

/// The small closed meshes the pair target decodes: fixed connectivity, vertex positions from
/// the input bytes (on a grid of 1/8, so coplanar faces, shared points and touching are common).
struct Shape {
  std::size_t vertices;
  std::vector<std::array<std::size_t, 3>> triangles;
};

inline const std::array<Shape, 4>& shapes() {
  static const std::array<Shape, 4> s = {{
      {4, {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}}},  // tetrahedron
      {5, {{0, 1, 2}, {0, 2, 3}, {0, 3, 1}, {4, 2, 1}, {4, 3, 2}, {4, 1, 3}}},  // triangular bipyramid
      {6, {{0, 2, 1}, {0, 3, 2}, {0, 4, 3}, {0, 1, 4}, {5, 1, 2}, {5, 2, 3}, {5, 3, 4}, {5, 4, 1}}},  // octahedron
      {8, {{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7}, {0, 1, 5}, {0, 5, 4},  // cube (box) of 12 triangles
           {1, 2, 6}, {1, 6, 5}, {2, 3, 7}, {2, 7, 6}, {3, 0, 4}, {3, 4, 7}}},
  }};
  return s;
}

/// Decodes one mesh: a shape byte, then 3 bytes per vertex (signed, / 8). False when the input is
/// too short.
inline bool decode_mesh(const std::uint8_t*& p, const std::uint8_t* end, seam::TriangleSoup& soup) {
  if (p == end) return false;
  const Shape& shape = shapes()[*p++ % shapes().size()];
  if (std::size_t(end - p) < 3 * shape.vertices) return false;
  soup.points.resize(shape.vertices);
  for (auto& point : soup.points)
    for (double& c : point) c = double(static_cast<std::int8_t>(*p++)) / 8.0;
  soup.triangles = shape.triangles;
  return true;
}

/// The pair pipeline on two small meshes decoded from `data`: byte 0 the kernel (exact, filtered,
/// float), byte 1 options (bit 0: automatic snapping, else none; bit 1: refinement to 20 degrees,
/// else none; bit 2: two more bytes follow, a scale 2^(3 s) and an offset +-2^(3 |o|) applied to
/// both meshes, signed bytes, reaching 1e-115..1e115), then the two meshes (see decode_mesh).
/// Inputs that are not valid meshes (zero-area faces, self-intersections) are refused by the
/// validation the CLI runs, as the CLI would; meshes outside seam::SupportedCoordinates must be
/// refused by seam::pair itself (InvalidInput, never a signal). A result must pass seam check
/// as written (rounded to doubles, exact kernel) at the tolerance pair verified it at.
inline void pair_pipeline(const std::uint8_t* data, std::size_t size) {
  const std::uint8_t* p = data;
  const std::uint8_t* end = data + size;
  if (size < 2) return;
  const int kernel = p[0] % 3;
  const std::uint8_t flags = p[1];
  p += 2;
  double scale = 1, offset = 0;
  if (flags & 4) {
    if (end - p < 2) return;
    scale = std::ldexp(1.0, 3 * int(static_cast<std::int8_t>(p[0])));
    const int o = static_cast<std::int8_t>(p[1]);
    offset = o == 0 ? 0.0 : std::copysign(std::ldexp(1.0, 3 * std::abs(o)), double(o));
    p += 2;
  }
  seam::TriangleSoup sa, sb;
  if (!decode_mesh(p, end, sa) || !decode_mesh(p, end, sb)) return;
  for (auto* s : {&sa, &sb})
    for (auto& point : s->points)
      for (double& c : point) c = c * scale + offset;
  bool in_range = true;
  try {
    for (const auto* s : {&sa, &sb}) seam::check_coordinate_range(s->points, "fuzz");
  } catch (const seam::InvalidInput&) {
    in_range = false;
  }
  if (!in_range) {  // refused by the library itself, before any arithmetic
    seam::with_kernel(seam::KernelKind::exact, [&](auto k) {
      using K = decltype(k);
      // mesh_from_soup converts doubles exactly and checks only the connectivity.
      seam::Mesh<K> a, b;
      try {
        a = seam::mesh_from_soup<K>(sa, "a");
        b = seam::mesh_from_soup<K>(sb, "b");
      } catch (const seam::InvalidInput&) {
        return 0;
      }
      try {
        seam::pair<K>(a, b, seam::PairOptions{});
      } catch (const seam::InvalidInput&) {
        return 0;
      }
      throw ContractViolation("pair accepted meshes outside the supported coordinates");
    });
    return;
  }
  try {
    for (const auto* s : {&sa, &sb}) {
      seam::validate_triangle_mesh(*s, "fuzz");
      seam::check_no_self_intersection(*s, "fuzz");
    }
  } catch (const seam::InvalidInput&) {
    return;
  }
  seam::PairOptions options;
  options.embed.snap_tol = (flags & 1) ? -1.0 : 0.0;
  options.embed.min_angle_deg = (flags & 2) ? 20.0 : 0.0;
  const seam::KernelKind kinds[3] = {seam::KernelKind::exact, seam::KernelKind::filtered, seam::KernelKind::float_};
  seam::with_kernel(kinds[kernel], [&](auto k) {
    using K = decltype(k);
    try {
      auto a = seam::mesh_from_soup<K>(sa, "a");
      auto b = seam::mesh_from_soup<K>(sb, "b");
      const auto result = seam::pair<K>(a, b, options);
      if (!result.stats.verified) throw ContractViolation("pair returned an unverified result");
      const auto exact = [](const seam::TriangleSoup& s) { return seam::mesh_from_soup<seam::Exact>(s, "x"); };
      const auto report = seam::check_pair<seam::Exact>(
          exact(sa), exact(sb), exact(seam::soup_from_mesh<K>(a)), exact(seam::soup_from_mesh<K>(b)),
          seam::to_kernel<seam::Exact>(seam::to_doubles<K>(result.curves)), result.stats.verify_tolerance);
      if (!report.ok()) throw ContractViolation("pair's outputs, as written, fail seam check: " + report.problems.front());
    } catch (const seam::Error&) {
    }
    return 0;
  });
}

}  // namespace seam_fuzz
