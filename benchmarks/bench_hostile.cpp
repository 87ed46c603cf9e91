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
#include <stdexcept>
#include <vector>

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

}  // namespace

BENCHMARK_TEMPLATE(zigzag, seam::Exact)->Name("hostile/zigzag_100k/exact")->UseManualTime()->Iterations(1)->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(zigzag, seam::Filtered)->Name("hostile/zigzag_100k/filtered")->UseManualTime()->Iterations(1)->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(million_nodes, seam::Exact)->Name("hostile/million_nodes_10_faces/exact")->UseManualTime()->Iterations(1)->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(million_nodes, seam::Filtered)->Name("hostile/million_nodes_10_faces/filtered")->UseManualTime()->Iterations(1)->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(million_faces, seam::Exact)->Name("hostile/million_faces_no_intersection/exact")->UseManualTime()->Iterations(1)->Unit(benchmark::kMillisecond);
BENCHMARK_TEMPLATE(million_faces, seam::Filtered)->Name("hostile/million_faces_no_intersection/filtered")->UseManualTime()->Iterations(1)->Unit(benchmark::kMillisecond);
BENCHMARK(self_intersection_check)->Name("hostile/self_intersection_check")->UseManualTime()->Iterations(1)->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
