// seam Python bindings: the library's operations on plain arrays. See calls.h.
//
// The conversions are those of the CLI with arrays in place of files: the caller's arrays are
// copied into a seam::TriangleSoup (what a reader returns) and checked as a reader checks a file
// (seam::validate_triangle_mesh, then seam::check_no_self_intersection where the CLI runs it),
// then seam::mesh_from_soup<K>; the results come back through seam::soup_from_mesh<K> and
// seam::to_doubles<K>. Every kernel-dependent function called here is instantiated in the library.
//
// SPDX-License-Identifier: GPL-3.0-or-later
#include "calls.h"

#include "report.h"  // cli/report.h: the JSON reports of the CLI

#include <seam/check.h>
#include <seam/embed.h>
#include <seam/errors.h>
#include <seam/generate.h>
#include <seam/io.h>
#include <seam/kernels.h>
#include <seam/pair.h>
#include <seam/textile.h>

#include <CGAL/exceptions.h>

#include <tbb/parallel_invoke.h>

#include <chrono>
#include <cmath>
#include <cstring>
#include <limits>
#include <utility>

namespace seam_python {

namespace {

static_assert(sizeof(Point) == 3 * sizeof(double), "a Point is three packed doubles (NumPy's (n, 3) rows)");
static_assert(std::is_same_v<Point, seam::Point3d>, "calls.h's Point is seam's");

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

[[noreturn]] void invalid(const std::string& name, const std::string& what) {
  throw seam::InvalidInput(name + ": " + what);
}

seam::KernelKind kernel_kind(const Kernel& k) {
  if (k.name == "exact") return seam::KernelKind::exact;
  if (k.name == "filtered") return seam::KernelKind::filtered;
  if (k.name == "float") return seam::KernelKind::float_;
  throw seam::InvalidInput("kernel '" + k.name + "': must be 'exact', 'filtered' or 'float'");
}

/// Runs `f`, turning a CGAL failure (a precondition or assertion of CGAL's) into InternalError,
/// as the CLI reports it (exit 3).
template <class F> auto guarded(F&& f) {
  try {
    return f();
  } catch (const CGAL::Failure_exception& e) {
    throw seam::InternalError("CGAL: " + e.message() + " (" + e.expression() + ")");
  }
}

bool finite(const Point& p) { return std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]); }

/// The caller's mesh as a soup, checked as a file is: finite coordinates in the supported range
/// (messages name the vertex array), indices in range (the face array), then
/// seam::validate_triangle_mesh (degenerate faces, orientation, non-manifold edges and vertices:
/// the face array) and, with `self_intersection`, seam::check_no_self_intersection.
seam::TriangleSoup soup_from_view(const MeshView& m, bool self_intersection) {
  if (m.nv == 0) invalid(m.vertices_name, "no vertices");
  if (m.nf == 0) invalid(m.faces_name, "no faces");
  seam::TriangleSoup soup;
  soup.points.resize(m.nv);
  std::memcpy(soup.points.data(), m.vertices, m.nv * sizeof(Point));
  for (std::size_t i = 0; i < m.nv; ++i)
    if (!finite(soup.points[i])) invalid(m.vertices_name, "vertex " + std::to_string(i) + " has a non-finite coordinate");
  seam::check_coordinate_range(soup.points, m.vertices_name);
  soup.triangles.resize(m.nf);
  const auto* bytes = static_cast<const unsigned char*>(m.faces);
  for (std::size_t f = 0; f < m.nf; ++f)
    for (std::size_t k = 0; k < 3; ++k) {
      std::int64_t index = 0;
      std::memcpy(&index, bytes + (3 * f + k) * sizeof(index), sizeof(index));
      if (index < 0)
        invalid(m.faces_name, "face " + std::to_string(f) + " has a negative vertex index " + std::to_string(index));
      if (static_cast<std::uint64_t>(index) >= m.nv)
        invalid(m.faces_name, "face " + std::to_string(f) + " has a vertex index " + std::to_string(index) +
                                  " out of range (" + m.vertices_name + " has " + std::to_string(m.nv) + " vertices)");
      soup.triangles[f][k] = static_cast<std::size_t>(index);
    }
  seam::validate_triangle_mesh(soup, m.faces_name);
  if (self_intersection) seam::check_no_self_intersection(soup, m.faces_name);
  return soup;
}

/// The caller's curves, each named "curves[i]" in messages: at least `min_points` points (a curve
/// of one point is an isolated point of contact, which only seam check takes), finite.
std::vector<std::vector<seam::Point3d>> curves_from_views(const std::vector<CurveView>& views, std::size_t min_points) {
  std::vector<std::vector<seam::Point3d>> curves(views.size());
  for (std::size_t c = 0; c < views.size(); ++c) {
    const std::string name = "curves[" + std::to_string(c) + "]";
    if (views[c].n == 0) invalid(name, "no points");
    if (views[c].n < min_points) invalid(name, "a curve needs at least " + std::to_string(min_points) + " points");
    curves[c].resize(views[c].n);
    std::memcpy(curves[c].data(), views[c].points, views[c].n * sizeof(Point));
    for (std::size_t i = 0; i < curves[c].size(); ++i)
      if (!finite(curves[c][i])) invalid(name, "point " + std::to_string(i) + " has a non-finite coordinate");
    seam::check_coordinate_range(curves[c], name, /*whole_mesh=*/false);
  }
  return curves;
}

/// The mesh's vertices and faces as soup_from_mesh gives them, and each face's provenance.
template <class K> MeshOut mesh_out(const seam::Mesh<K>& mesh) {
  using F = typename seam::Mesh<K>::Face_index;
  seam::TriangleSoup soup = seam::soup_from_mesh<K>(mesh);
  MeshOut out;
  out.vertices = std::move(soup.points);
  out.faces.reserve(soup.triangles.size());
  for (const auto& t : soup.triangles)
    out.faces.push_back({std::int64_t(t[0]), std::int64_t(t[1]), std::int64_t(t[2])});
  // The face properties seam::embed adds (seam/types.h); a mesh seam did not change has none.
  // A face remeshed next to the curves, in no single input face, has source uint32 max.
  const auto [source, has_source] = mesh.template property_map<F, std::uint32_t>(seam::source_face_property);
  const auto [is_new, has_new] = mesh.template property_map<F, bool>(seam::new_face_property);
  constexpr std::uint32_t remeshed = std::numeric_limits<std::uint32_t>::max();
  out.source_face.reserve(out.faces.size());
  out.new_face.reserve(out.faces.size());
  std::int64_t i = 0;
  for (F f : mesh.faces()) {
    out.source_face.push_back(!has_source ? i : source[f] == remeshed ? -1 : std::int64_t(source[f]));
    out.new_face.push_back(has_new && is_new[f] ? 1 : 0);
    ++i;
  }
  return out;
}

MeshOut soup_out(seam::TriangleSoup soup) {
  MeshOut out;
  out.vertices = std::move(soup.points);
  for (const auto& t : soup.triangles) out.faces.push_back({std::int64_t(t[0]), std::int64_t(t[1]), std::int64_t(t[2])});
  return out;
}

std::string dump(const nlohmann::json& j) { return j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace); }

}  // namespace

PairOut pair(const MeshView& av, const MeshView& bv, const PairArgs& args) {
  return guarded([&] {
    const auto t0 = Clock::now();
    const seam::KernelKind kind = kernel_kind(args.kernel);
    seam::PairOptions options;
    options.embed.snap_tol = args.snap_tol;
    options.embed.min_angle_deg = args.min_angle;
    options.embed.max_area = args.max_area;
    options.quality.bound_reach = args.bound_reach;
    options.improve = args.improve;
    seam::validate_options(options.embed);
    seam::TriangleSoup soup_a, soup_b;
    tbb::parallel_invoke([&] { soup_a = soup_from_view(av, true); }, [&] { soup_b = soup_from_view(bv, true); });
    const auto given = curves_from_views(args.curves, 2);
    return seam::with_kernel(kind, [&](auto kernel) {
      using K = decltype(kernel);
      seam::Mesh<K> a, b;
      tbb::parallel_invoke([&] { a = seam::mesh_from_soup<K>(soup_a, av.faces_name); },
                           [&] { b = seam::mesh_from_soup<K>(soup_b, bv.faces_name); });
      const double from_arrays = seconds_since(t0);
      seam::PairResult<K> result;
      if (!args.given_curves) {
        result = seam::pair<K>(a, b, options);
      } else {
        try {
          result = seam::pair_with_curves<K>(a, b, seam::to_kernel<K>(given), options);
        } catch (const seam::InvalidInput& e) {
          throw seam::InvalidInput(std::string("curves: ") + e.what());
        }
      }
      const auto t1 = Clock::now();
      PairOut out;
      tbb::parallel_invoke([&] { out.a = mesh_out<K>(a); }, [&] { out.b = mesh_out<K>(b); });
      out.curves = seam::to_doubles<K>(result.curves);
      auto& st = result.stats;
      st.stage_seconds["from_arrays"] = from_arrays;
      st.stage_seconds["to_arrays"] = seconds_since(t1);
      out.report = dump(seam_cli::pair_report_json(kind, st, result.a.stats, result.b.stats,
                                                   seam_cli::curve_summaries<K>(result.curves)));
      return out;
    });
  });
}

EmbedOut embed(const MeshView& view, const std::vector<CurveView>& curve_views, const EmbedArgs& args) {
  return guarded([&] {
    const auto t0 = Clock::now();
    const seam::KernelKind kind = kernel_kind(args.kernel);
    seam::EmbedOptions options;
    options.snap_tol = args.snap_tol;
    options.min_angle_deg = args.min_angle;
    options.max_area = args.max_area;
    options.max_distance = args.max_distance;
    options.curve_tol = args.curve_tol;
    seam::validate_options(options);
    const seam::TriangleSoup soup = soup_from_view(view, true);
    const auto polylines = curves_from_views(curve_views, 2);
    return seam::with_kernel(kind, [&](auto kernel) {
      using K = decltype(kernel);
      seam::Mesh<K> mesh = seam::mesh_from_soup<K>(soup, view.faces_name);
      const auto curves = seam::to_kernel<K>(polylines);
      const double from_arrays = seconds_since(t0);
      seam::EmbedResult<K> result;
      try {
        result = seam::embed<K>(mesh, curves, options);
      } catch (const seam::InvalidInput& e) {
        throw seam::InvalidInput(std::string("curves: ") + e.what());
      }
      const auto t1 = Clock::now();
      EmbedOut out;
      out.mesh = mesh_out<K>(mesh);
      out.curves = seam::to_doubles<K>(result.curves);
      // Vertex indices of the mesh as soup_from_mesh numbers them (in the order of mesh.vertices()).
      std::vector<std::int64_t> index(mesh.num_vertices(), -1);
      std::int64_t next = 0;
      for (auto v : mesh.vertices()) index[std::size_t(v)] = next++;
      for (const auto& vs : result.curve_vertices) {
        std::vector<std::int64_t> ids;
        ids.reserve(vs.size());
        for (auto v : vs) ids.push_back(index[std::size_t(v)]);
        out.curve_vertices.push_back(std::move(ids));
      }
      result.stats.stage_seconds["from_arrays"] = from_arrays;
      result.stats.stage_seconds["to_arrays"] = seconds_since(t1);
      out.report = dump(seam_cli::stats_json(result.stats));
      return out;
    });
  });
}

CheckOut check(const MeshView& av, const MeshView& bv, const MeshView& a2v, const MeshView& b2v,
               const std::vector<CurveView>& curve_views, double tol, const Kernel& kernel) {
  return guarded([&] {
    const seam::KernelKind kind = kernel_kind(kernel);
    if (!(tol < 0 || std::isfinite(tol))) throw seam::InvalidInput("tol: must be 'auto' or a finite number >= 0");
    // As `seam check` reads its files: valid triangle meshes, self-intersections left to the checks.
    const seam::TriangleSoup sa = soup_from_view(av, false), sb = soup_from_view(bv, false),
                             sa2 = soup_from_view(a2v, false), sb2 = soup_from_view(b2v, false);
    const auto polylines = curves_from_views(curve_views, 1);
    if (tol < 0) tol = seam_cli::default_check_tolerance(sa, sb);  // as `seam check`
    return seam::with_kernel(kind, [&](auto k) {
      using K = decltype(k);
      const auto ma = seam::mesh_from_soup<K>(sa, av.faces_name), mb = seam::mesh_from_soup<K>(sb, bv.faces_name);
      const auto ma2 = seam::mesh_from_soup<K>(sa2, a2v.faces_name), mb2 = seam::mesh_from_soup<K>(sb2, b2v.faces_name);
      const seam::PairCheckReport r = seam::check_pair<K>(ma, mb, ma2, mb2, seam::to_kernel<K>(polylines), tol);
      CheckOut out;
      out.ok = r.ok();
      out.problems = r.problems;
      out.report = dump(seam_cli::check_report_json(r, seam::kernel_name(kind)));
      return out;
    });
  });
}

TextileOut textile(const std::vector<MeshView>& views, const std::vector<std::string>& names, const TextileArgs& args) {
  return guarded([&] {
    const auto t0 = Clock::now();
    const seam::KernelKind kind = kernel_kind(args.kernel);
    if (names.size() != views.size())
      throw seam::InvalidInput("names: " + std::to_string(names.size()) + " names for " + std::to_string(views.size()) +
                               " tows");
    if (views.empty()) throw seam::InvalidInput("tows: no tow given");
    if (args.threads < 0 || args.threads > 1024) throw seam::InvalidInput("threads: must be an integer from 0 to 1024");
    seam::TextileOptions options;
    options.embed.snap_tol = args.snap_tol;
    options.embed.min_angle_deg = args.min_angle;
    options.embed.max_area = args.max_area;
    options.threads = args.threads;
    options.quality.bound_reach = args.bound_reach;
    options.improve = args.improve;
    seam::validate_options(options.embed);
    std::vector<seam::TriangleSoup> soups;
    for (const auto& v : views) soups.push_back(soup_from_view(v, true));
    return seam::with_kernel(kind, [&](auto kernel) {
      using K = decltype(kernel);
      std::vector<seam::Mesh<K>> meshes;
      for (std::size_t i = 0; i < soups.size(); ++i) meshes.push_back(seam::mesh_from_soup<K>(soups[i], views[i].faces_name));
      const double from_arrays = seconds_since(t0);
      seam::TextileResult<K> result = seam::textile<K>(meshes, names, options);
      const auto t1 = Clock::now();
      TextileOut out;
      for (const auto& m : meshes) out.tows.push_back(mesh_out<K>(m));
      for (const auto& p : result.pairs) out.pairs.push_back({p.stats.a, p.stats.b, seam::to_doubles<K>(p.curves)});
      result.stats.stage_seconds["from_arrays"] = from_arrays;
      result.stats.stage_seconds["to_arrays"] = seconds_since(t1);
      out.report = dump(seam_cli::textile_report_json<K>(result, names));
      return out;
    });
  });
}

std::array<MeshOut, 2> make_crossover(int weft_along, int weft_around, int warp_along, int warp_around,
                                      const std::string& warp_section, double warp_height) {
  seam::Section section = seam::Section::elliptical;
  if (warp_section == "lenticular") section = seam::Section::lenticular;
  else if (warp_section != "elliptical")
    throw seam::InvalidInput("warp_section '" + warp_section + "': must be 'elliptical' or 'lenticular'");
  const seam::CrossoverTows tows =
      seam::make_crossover(weft_along, weft_around, warp_along, warp_around, section, warp_height);
  return {soup_out(seam::make_tow(tows.weft)), soup_out(seam::make_tow(tows.warp))};
}

}  // namespace seam_python
