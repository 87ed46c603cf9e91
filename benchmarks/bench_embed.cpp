// Benchmark of seam::embed with the three kernels on a generated tow of about 100k faces.
//
// Input (generated once, outside every timed region): a tow of 1000 x 50 segments (100 100
// triangles with the caps) and three dense closed tilted rings on its smooth surface, 20001
// samples each (coprime with the 50 vertices around, so no sample lies on a line of vertices
// by construction), at three stations along the tow. Each ring spans s in [c - 0.8, c + 0.8],
// i.e. 160 rings of mesh vertices, so it crosses a few thousand faces.
//
// BM_embed_whole<K>: the whole seam::embed call (real time). Each iteration gets a fresh mesh
// and fresh curves, built from the double data while the timer is paused (a fresh mesh, not a
// copy, so that no lazy exact value computed by one iteration is shared with the next).
// Counters: the per-stage seconds of EmbedStats::stage_seconds (snap_s, locate_s, cross_s,
// coarsen_s, retriangulate_s, splice_s) averaged over the iterations, and faces_crossed,
// crossing_points, new_faces, min_angle of the last iteration (identical in every iteration).
//
// SPDX-License-Identifier: GPL-3.0-or-later
#include <seam/embed.h>
#include <seam/generate.h>
#include <seam/io.h>
#include <seam/kernels.h>

#include <benchmark/benchmark.h>

#include <optional>
#include <string>
#include <vector>

namespace {

struct Input {
  seam::TriangleSoup tow;
  std::vector<std::vector<seam::Point3d>> curves;
};

const Input& input() {
  static const Input data = [] {
    Input in;
    seam::TowOptions opt;
    opt.segments_along = 1000;
    opt.segments_around = 50;
    in.tow = seam::make_tow(opt);
    // Stations between vertex rings (0.01 apart): 2.505, 5.003, 7.507; tilt 0.8.
    for (double s : {2.505, 5.003, 7.507}) in.curves.push_back(seam::make_ring_curve(opt, s, 0.8, 20001));
    return in;
  }();
  return data;
}

template <class K> void BM_embed_whole(benchmark::State& state) {
  const Input& in = input();
  seam::EmbedOptions options;
  options.min_angle_deg = 20.0;

  const char* stages[] = {"snap", "locate", "cross", "coarsen", "retriangulate", "splice"};
  double stage_sum[6] = {0, 0, 0, 0, 0, 0};
  seam::EmbedStats last;
  std::optional<seam::Mesh<K>> mesh;
  std::vector<seam::Polyline<K>> curves;
  for (auto _ : state) {
    state.PauseTiming();
    mesh.reset();  // the previous iteration's output is destroyed outside the timed region
    mesh.emplace(seam::mesh_from_soup<K>(in.tow, "tow"));
    curves = seam::to_kernel<K>(in.curves);
    state.ResumeTiming();
    try {
      auto result = seam::embed<K>(*mesh, curves, options);
      benchmark::DoNotOptimize(result.curve_vertices.data());
      state.PauseTiming();  // `result` is destroyed and the stages summed outside the timed region
      last = std::move(result.stats);
    } catch (const seam::Error& e) {
      state.SkipWithError(e.what());
      break;
    }
    for (int i = 0; i < 6; ++i) {
      auto it = last.stage_seconds.find(stages[i]);
      if (it != last.stage_seconds.end()) stage_sum[i] += it->second;
    }
    state.ResumeTiming();
  }
  state.SetLabel(seam::kernel_name(seam::kernel_traits<K>::kind));
  for (int i = 0; i < 6; ++i)
    state.counters[std::string(stages[i]) + "_s"] = benchmark::Counter(stage_sum[i], benchmark::Counter::kAvgIterations);
  state.counters["input_faces"] = double(last.input_faces);
  state.counters["faces_crossed"] = double(last.faces_crossed);
  state.counters["crossing_points"] = double(last.crossing_points);
  state.counters["new_faces"] = double(last.faces_added);
  state.counters["min_angle"] = last.min_angle_deg_new;
}

}  // namespace

BENCHMARK_TEMPLATE(BM_embed_whole, seam::Exact)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(3);
BENCHMARK_TEMPLATE(BM_embed_whole, seam::Filtered)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(3);
BENCHMARK_TEMPLATE(BM_embed_whole, seam::Float)->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(3);

BENCHMARK_MAIN();
