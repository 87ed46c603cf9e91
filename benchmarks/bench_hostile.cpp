// Adversarial but valid inputs must finish in bounded time and memory (issue 5, "bounded work").
// Each benchmark times the library call on inputs generated before the timed region:
//
//   hostile/zigzag_100k/K   seam::embed of a sawtooth curve that crosses the diagonal of a unit
//                           square (two triangles) 100,000 times each way: 200,001 nodes, 200,000
//                           crossing points on one edge, 100,000 curve segments in each face.
//                           (It was quadratic before: the curve deviation of the report searched
//                           every embedded segment for every node.)
//   hostile/million_nodes_10_faces/K  seam::embed of a closed ring of 1,000,000 nodes around a
//                           pentagonal bipyramid (10 faces), 0.1% off its surface.
//   hostile/million_faces_no_intersection/K  seam::pair of a tow of about 1,000,000 faces with a
//                           small tow that it does not touch: no curve, both meshes unchanged.
//   hostile/self_intersection_check  seam::check_no_self_intersection on the two tows of
//                           bench_pair (76,928 and 64,000 faces), what seam embed / pair add to
//                           every run.
//   hostile/scale/S/K      (issue 22, class 1) seam::pair of the small crossover of the tests
//                           (18 x 10 and 14 x 9 segments) with every coordinate mapped to
//                           S * c + offset: unit, 1e28 and 1e-29 (the supported limits), and unit
//                           size 1e7 from the origin. Counter `verified` must be 1.
//   hostile/max_area/K      (issue 22, class 3) seam::pair of the same crossover with
//                           --max-area 0.01, and 0.001 (it ran for minutes with the default
//                           remeshing). Counter `verified` 1, or `internal_error` 1: refused.
//   hostile/read_curve_2m   (issue 22, class 8) read_polylines + to_kernel<Exact> of a file of one
//                           curve of 2,000,000 points (17 significant digits, 122 MB); counters:
//                           file MB, growth of the peak resident memory (MB) while reading and
//                           converting.
//   hostile/embed_ring_1m_memory/K  (class 8) the whole million_nodes run from doubles in memory:
//                           to_kernel + seam::embed; counters: growth of the peak resident memory,
//                           in MB and in bytes per curve node.
//   hostile/spiral_1e6_turns/K  (class 8) seam::embed of an open curve of 4,000,000 nodes
//                           spiralling 1,000,000 times inside one face of the unit square (default
//                           options: the nodes between the two ends are dropped); counters as above.
// K: exact (Epeck) or filtered (Epick). One iteration each (manual time = wall clock of the
// call); counters give the sizes.
//
// SPDX-License-Identifier: GPL-3.0-or-later
#include <seam/embed.h>
#include <seam/generate.h>
#include <seam/io.h>
#include <seam/kernels.h>
#include <seam/pair.h>

#include <benchmark/benchmark.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <malloc.h>
#include <unistd.h>

namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

/// The unit square as two triangles sharing the diagonal (0,0)-(1,1), and a sawtooth curve
/// along that diagonal crossing it `teeth` times each way, 0.01 off it on either side.
seam::TriangleSoup square() { return {{{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}, {{0, 1, 2}, {0, 2, 3}}}; }

std::vector<seam::Point3d> sawtooth(int teeth) {
  std::vector<seam::Point3d> c;
  const int n = 2 * teeth + 1;
  for (int i = 0; i < n; ++i) {
    const double t = 0.1 + 0.8 * i / double(n - 1), side = (i % 2 == 0 ? 1 : -1) * 0.01;
    c.push_back({t + side, t - side, 0});
  }
  return c;
}

/// Pentagonal bipyramid (10 faces) and a closed ring of `nodes` nodes around its upper half at
/// height 0.3, 0.1% outside the surface.
seam::TriangleSoup bipyramid() {
  seam::TriangleSoup s;
  for (int k = 0; k < 5; ++k) s.points.push_back({std::cos(2 * M_PI * k / 5), std::sin(2 * M_PI * k / 5), 0});
  s.points.push_back({0, 0, 1});
  s.points.push_back({0, 0, -1});
  for (std::size_t k = 0; k < 5; ++k) {
    s.triangles.push_back({k, (k + 1) % 5, 5});
    s.triangles.push_back({(k + 1) % 5, k, 6});
  }
  return s;
}

std::vector<seam::Point3d> ring(int nodes) {
  const double z = 0.3, scale = (1 - z) * 1.001;
  std::vector<seam::Point3d> c;
  for (int i = 0; i < nodes; ++i) {
    const double t = 5.0 * i / nodes;
    const int k = int(t);
    const double u = t - k;
    const double x0 = std::cos(2 * M_PI * k / 5), y0 = std::sin(2 * M_PI * k / 5);
    const double x1 = std::cos(2 * M_PI * (k + 1) / 5), y1 = std::sin(2 * M_PI * (k + 1) / 5);
    c.push_back({scale * ((1 - u) * x0 + u * x1), scale * ((1 - u) * y0 + u * y1), z});
  }
  c.push_back(c.front());
  return c;
}

template <class K> void run_embed(benchmark::State& state, const seam::TriangleSoup& soup,
                                  const std::vector<seam::Point3d>& curve) {
  for (auto _ : state) {
    auto mesh = seam::mesh_from_soup<K>(soup, "mesh");
    const auto curves = seam::to_kernel<K>({curve});
    const auto t = Clock::now();
    const auto r = seam::embed<K>(mesh, curves, {});
    state.SetIterationTime(seconds_since(t));
    state.counters["nodes_in"] = double(r.stats.curve_nodes_in);
    state.counters["nodes_out"] = double(r.stats.curve_nodes_out);
    state.counters["crossing_points"] = double(r.stats.crossing_points);
    state.counters["faces_out"] = double(r.stats.output_faces);
    for (const auto& [stage, s] : r.stats.stage_seconds) state.counters[stage + "_s"] = s;
  }
}

template <class K> void zigzag(benchmark::State& state) { run_embed<K>(state, square(), sawtooth(100000)); }
template <class K> void million_nodes(benchmark::State& state) { run_embed<K>(state, bipyramid(), ring(1000000)); }

template <class K> void million_faces(benchmark::State& state) {
  seam::TowOptions big;  // 2 * 1250 * 400 + 2 * 400 = 1,000,800 faces
  big.segments_along = 1250;
  big.segments_around = 400;
  seam::TowOptions small;  // far above the big one
  small.segments_along = 30;
  small.segments_around = 12;
  small.translate = {0, 0, 5};
  const auto soup_a = seam::make_tow(big), soup_b = seam::make_tow(small);
  for (auto _ : state) {
    auto a = seam::mesh_from_soup<K>(soup_a, "a");
    auto b = seam::mesh_from_soup<K>(soup_b, "b");
    const auto t = Clock::now();
    const auto r = seam::pair<K>(a, b, {});
    state.SetIterationTime(seconds_since(t));
    if (r.stats.curves != 0) throw std::logic_error("million_faces: the tows should not intersect");
    state.counters["faces_a"] = double(a.number_of_faces());
    state.counters["curves"] = double(r.stats.curves);
  }
}

void self_intersection_check(benchmark::State& state) {
  // The two tows of bench_pair.
  const auto [weft, warp] = seam::make_crossover(600, 64, 499, 64, seam::Section::lenticular, 0.45);
  const auto a = seam::make_tow(weft), b = seam::make_tow(warp);
  for (auto _ : state) {
    const auto t = Clock::now();
    seam::check_no_self_intersection(a, "a");
    seam::check_no_self_intersection(b, "b");
    state.SetIterationTime(seconds_since(t));
    state.counters["faces"] = double(a.triangles.size() + b.triangles.size());
  }
}

/// A field of /proc/self/status in MB ("VmHWM": the peak resident memory); -1 if missing.
double status_mb(const char* field) {
  std::ifstream in("/proc/self/status");
  std::string line;
  const std::string key = std::string(field) + ":";
  while (std::getline(in, line))
    if (line.rfind(key, 0) == 0) return std::stod(line.substr(key.size())) / 1024.0;
  return -1;
}

/// Resets the peak resident memory to the current one (Linux: /proc/self/clear_refs "5"), after
/// handing freed memory back to the system (else the next benchmark reuses it without growing).
void reset_peak() {
  ::malloc_trim(0);
  std::ofstream("/proc/self/clear_refs") << "5";
}

/// The small crossover of test_hostile_pair.cpp, every coordinate c mapped to scale * c + offset.
std::pair<seam::TriangleSoup, seam::TriangleSoup> crossover_at(double scale, double offset) {
  const auto tows = seam::make_crossover(18, 10, 14, 9, seam::Section::lenticular, 0.45);
  seam::TriangleSoup a = seam::make_tow(tows.weft), b = seam::make_tow(tows.warp);
  for (seam::TriangleSoup* s : {&a, &b})
    for (seam::Point3d& p : s->points)
      for (double& c : p) c = scale * c + offset;
  return {a, b};
}

template <class K> void run_pair(benchmark::State& state, double scale, double offset, double max_area) {
  const auto [sa, sb] = crossover_at(scale, offset);
  for (auto _ : state) {
    auto a = seam::mesh_from_soup<K>(sa, "a");
    auto b = seam::mesh_from_soup<K>(sb, "b");
    seam::PairOptions options;
    options.embed.max_area = max_area * scale * scale;
    const auto t = Clock::now();
    try {
      const auto r = seam::pair<K>(a, b, options);
      state.SetIterationTime(seconds_since(t));
      state.counters["verified"] = r.stats.verified ? 1 : 0;
      state.counters["curves"] = double(r.stats.curves);
      state.counters["faces_a"] = double(a.number_of_faces());
    } catch (const seam::InternalError&) {  // refused (exit 3), no invalid output: timed too
      state.SetIterationTime(seconds_since(t));
      state.counters["internal_error"] = 1;
    }
  }
}

template <class K> void scale_unit(benchmark::State& state) { run_pair<K>(state, 1, 0, 0); }
template <class K> void scale_1e28(benchmark::State& state) { run_pair<K>(state, 1e28, 0, 0); }
template <class K> void scale_1e_29(benchmark::State& state) { run_pair<K>(state, 1e-29, 0, 0); }
template <class K> void offset_1e7(benchmark::State& state) { run_pair<K>(state, 1, 1e7, 0); }
template <class K> void max_area(benchmark::State& state) { run_pair<K>(state, 1, 0, 0.01); }
template <class K> void max_area_small(benchmark::State& state) { run_pair<K>(state, 1, 0, 0.001); }

void read_curve(benchmark::State& state) {
  const int n = 2000000;
  const std::string path = (std::filesystem::temp_directory_path() /
                            ("seam_bench_curve_" + std::to_string(::getpid()) + ".txt")).string();
  seam::write_polylines({ring(n)}, path);
  const double file_mb = double(std::filesystem::file_size(path)) / 1e6;
  for (auto _ : state) {
    reset_peak();
    const double before = status_mb("VmHWM");
    const auto t = Clock::now();
    auto polylines = seam::read_polylines(path);
    const auto curves = seam::to_kernel<seam::Exact>(polylines);
    state.SetIterationTime(seconds_since(t));
    state.counters["file_MB"] = file_mb;
    state.counters["peak_growth_MB"] = status_mb("VmHWM") - before;
    state.counters["points"] = double(curves[0].size());
  }
  std::filesystem::remove(path);
}

/// to_kernel + seam::embed of `curve` on `soup`, timed; counters: growth of the peak resident
/// memory, in MB and in bytes per curve node.
template <class K>
void run_embed_memory(benchmark::State& state, const seam::TriangleSoup& soup, const std::vector<seam::Point3d>& curve) {
  for (auto _ : state) {
    auto mesh = seam::mesh_from_soup<K>(soup, "mesh");
    reset_peak();
    const double before = status_mb("VmHWM");
    const auto t = Clock::now();
    const auto curves = seam::to_kernel<K>({curve});
    const auto r = seam::embed<K>(mesh, curves, {});
    state.SetIterationTime(seconds_since(t));
    state.counters["peak_growth_MB"] = status_mb("VmHWM") - before;
    state.counters["bytes_per_node"] = (status_mb("VmHWM") - before) * 1024 * 1024 / double(curve.size());
    state.counters["nodes_in"] = double(r.stats.curve_nodes_in);
    state.counters["nodes_out"] = double(r.stats.curve_nodes_out);
  }
}

template <class K> void embed_ring_memory(benchmark::State& state) { run_embed_memory<K>(state, bipyramid(), ring(1000000)); }

/// The unit square as two triangles sharing the diagonal (1,0)-(0,1).
seam::TriangleSoup square_other_diagonal() { return {{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}}, {{0, 1, 2}, {1, 3, 2}}}; }

/// An open spiral of `nodes` nodes turning `turns` times around (0.3, 0.3, 0), radius 0.2 down
/// to 0.05: inside the triangle (0,0,0), (1,0,0), (0,1,0) of square_other_diagonal().
std::vector<seam::Point3d> spiral(int nodes, int turns) {
  std::vector<seam::Point3d> c;
  for (int i = 0; i < nodes; ++i) {
    const double t = double(i) / (nodes - 1), a = 2 * M_PI * turns * t, r = 0.2 - 0.15 * t;
    c.push_back({0.3 + r * std::cos(a), 0.3 + r * std::sin(a), 0});
  }
  return c;
}

template <class K> void spiral_memory(benchmark::State& state) {
  run_embed_memory<K>(state, square_other_diagonal(), spiral(4000000, 1000000));
}

}  // namespace

BENCHMARK_TEMPLATE(scale_unit, seam::Exact)->Name("hostile/scale/unit/exact")->UseManualTime()->Iterations(1)->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(scale_1e28, seam::Exact)->Name("hostile/scale/1e28/exact")->UseManualTime()->Iterations(1)->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(scale_1e_29, seam::Exact)->Name("hostile/scale/1e-29/exact")->UseManualTime()->Iterations(1)->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(offset_1e7, seam::Exact)->Name("hostile/scale/offset_1e7/exact")->UseManualTime()->Iterations(1)->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(max_area, seam::Exact)->Name("hostile/max_area/exact")->UseManualTime()->Iterations(1)->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(max_area_small, seam::Exact)->Name("hostile/max_area_0.001/exact")->UseManualTime()->Iterations(1)->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(max_area, seam::Filtered)->Name("hostile/max_area/filtered")->UseManualTime()->Iterations(1)->Unit(benchmark::kMillisecond);
BENCHMARK(read_curve)->Name("hostile/read_curve_2m")->UseManualTime()->Iterations(1)->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(embed_ring_memory, seam::Exact)->Name("hostile/embed_ring_1m_memory/exact")->UseManualTime()->Iterations(1)->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(embed_ring_memory, seam::Filtered)->Name("hostile/embed_ring_1m_memory/filtered")->UseManualTime()->Iterations(1)->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(spiral_memory, seam::Exact)->Name("hostile/spiral_1e6_turns/exact")->UseManualTime()->Iterations(1)->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(spiral_memory, seam::Filtered)->Name("hostile/spiral_1e6_turns/filtered")->UseManualTime()->Iterations(1)->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(zigzag, seam::Exact)->Name("hostile/zigzag_100k/exact")->UseManualTime()->Iterations(1)->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(zigzag, seam::Filtered)->Name("hostile/zigzag_100k/filtered")->UseManualTime()->Iterations(1)->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(million_nodes, seam::Exact)->Name("hostile/million_nodes_10_faces/exact")->UseManualTime()->Iterations(1)->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(million_nodes, seam::Filtered)->Name("hostile/million_nodes_10_faces/filtered")->UseManualTime()->Iterations(1)->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(million_faces, seam::Exact)->Name("hostile/million_faces_no_intersection/exact")->UseManualTime()->Iterations(1)->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(million_faces, seam::Filtered)->Name("hostile/million_faces_no_intersection/filtered")->UseManualTime()->Iterations(1)->Unit(benchmark::kMillisecond);
BENCHMARK(self_intersection_check)->Name("hostile/self_intersection_check")->UseManualTime()->Iterations(1)->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
