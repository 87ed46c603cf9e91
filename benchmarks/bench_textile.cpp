// Benchmark of `seam textile` on a generated 4x4 plain weave, against `seam pair` run on each of
// its crossings one after another, and with 1 thread against 2.
//
// Input (generated once, outside every timed region): seam::make_weave with 4 warps and 4 wefts
// (the default proportions: spacing 2, half width 0.6, half height 0.15, overlap 0.03),
// `--textile_resolution=R` segments per crossing along the wefts (default 122) and R/2 + 3
// around (make_weave raises it to 66 and 70 for the warps); warps get one more segment per tow
// along. With the defaults: 532,592 faces in all, 16 crossings. Written as OFF files
// to a temporary directory (removed at exit).
//
// Each run does what the command line does, from files to files, under the exact kernel:
//   textile/threads:T   read the 8 OFF files (concurrently), seam::textile<Exact> with T threads
//                       (default options: automatic snapping, minimum angle 20), write 8 meshes and
//                       16 polylines files (concurrently), as `seam textile --threads T`.
//   pairs/snap:S        for each of the 16 crossings in turn: read both OFF files,
//                       seam::pair<Exact>, write both meshes and the curves (what 16 runs of
//                       `seam pair` do). S = default: seam pair's default snapping (0.1 x mean edge
//                       length; better faces, more intersection rounds); S = 0: --snap-tol 0.
// Counter cpu_all_threads_s: CPU time of every thread of the process during the run (how much
// work the threads did, against how long it took).
//   calibration/threads:T  a fixed amount of perfectly parallel arithmetic on T threads: the
//                       machine is shared, and its ratio (1 thread / 2 threads) says how much of
//                       a second core was free at the time (2: all of it).
// One iteration per run, wall-clock (manual) time. After the runs the ratios are printed:
// pairs/textile for both pair variants, textile 1 thread / 2 threads, and the calibration's.
// `--benchmark_filter='calib|textile'` skips the pair runs (pairs/snap:default takes 40 s or more).
//
// SPDX-License-Identifier: GPL-3.0-or-later
#include <seam/generate.h>
#include <seam/io.h>
#include <seam/kernels.h>
#include <seam/pair.h>
#include <seam/textile.h>

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <benchmark/benchmark.h>

#include <chrono>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <map>
#include <string>
#include <vector>

#include <sys/resource.h>
#include <unistd.h>

namespace {

using K = seam::Exact;
using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

/// CPU time (user + system) of the whole process so far, every thread.
double process_cpu_seconds() {
  rusage u{};
  ::getrusage(RUSAGE_SELF, &u);
  return double(u.ru_utime.tv_sec + u.ru_stime.tv_sec) + 1e-6 * double(u.ru_utime.tv_usec + u.ru_stime.tv_usec);
}

int resolution = 122;
std::filesystem::path dir;
std::vector<std::string> names, files;
std::vector<std::pair<std::size_t, std::size_t>> crossings;  // (weft, warp) indices
std::map<std::string, double> seconds;                      // benchmark name -> time of its run

void prepare() {
  seam::WeaveOptions o;
  o.warps = o.wefts = 4;
  o.segments_per_crossing = resolution;
  o.segments_around = resolution / 2 + 3;
  char tmpl[] = "/tmp/seam_bench_textile_XXXXXX";
  if (!::mkdtemp(tmpl)) throw std::runtime_error("cannot create a temporary directory");
  dir = tmpl;
  std::size_t faces = 0;
  for (const auto& t : seam::make_weave(o)) {
    const auto soup = seam::make_tow(t.options);
    faces += soup.triangles.size();
    names.push_back(t.name);
    files.push_back((dir / (t.name + ".off")).string());
    seam::write_triangle_mesh(soup, files.back());
  }
  for (std::size_t j = 0; j < 4; ++j)
    for (std::size_t i = 0; i < 4; ++i) crossings.emplace_back(j, 4 + i);
  std::cerr << "bench_textile: " << names.size() << " tows, " << faces << " faces in all, " << crossings.size()
            << " crossings, in " << dir << "\n";
}

template <class F> void parallel(tbb::task_arena& arena, std::size_t n, F&& f) {
  arena.execute([&] { tbb::parallel_for(std::size_t(0), n, [&](std::size_t i) { f(i); }); });
}

void BM_textile(benchmark::State& state) {
  const int threads = int(state.range(0));
  const auto out = dir / ("textile_" + std::to_string(threads));
  std::filesystem::create_directories(out);
  for (auto _ : state) {
    const auto t0 = Clock::now();
    const double cpu0 = process_cpu_seconds();
    tbb::task_arena arena(threads);
    std::vector<seam::Mesh<K>> meshes(files.size());
    parallel(arena, files.size(), [&](std::size_t i) {
      meshes[i] = seam::mesh_from_soup<K>(seam::read_triangle_mesh(files[i]), files[i]);
    });
    const double read = seconds_since(t0);
    seam::TextileOptions options;
    options.threads = threads;
    const auto result = seam::textile<K>(meshes, names, options);
    const auto t1 = Clock::now();
    std::vector<seam::TriangleSoup> soups(meshes.size());
    parallel(arena, meshes.size(), [&](std::size_t i) { soups[i] = seam::soup_from_mesh<K>(meshes[i]); });
    std::vector<std::vector<std::vector<seam::Point3d>>> curves;
    for (const auto& p : result.pairs) curves.push_back(seam::to_doubles<K>(p.curves));
    parallel(arena, soups.size() + curves.size(), [&](std::size_t i) {
      if (i < soups.size()) {
        seam::write_triangle_mesh(soups[i], (out / (names[i] + ".off")).string());
      } else {
        const auto& s = result.pairs[i - soups.size()].stats;
        seam::write_polylines(curves[i - soups.size()], (out / (names[s.a] + "__" + names[s.b] + ".polylines.txt")).string());
      }
    });
    const double write = seconds_since(t1);
    const double total = seconds_since(t0);
    const double cpu = process_cpu_seconds() - cpu0;
    state.SetIterationTime(total);
    seconds["textile/threads:" + std::to_string(threads)] = total;
    seconds["textile_cpu/threads:" + std::to_string(threads)] = cpu;
    state.counters["cpu_all_threads_s"] = cpu;
    state.counters["read_s"] = read;
    state.counters["write_s"] = write;
    for (const auto& [stage, s] : result.stats.stage_seconds) state.counters[stage + "_s"] = s;
    state.counters["pairs"] = double(result.stats.intersecting_pairs);
    std::size_t snapped = 0, below_10 = 0, added = 0;
    for (const auto& t : result.tows) snapped += t.vertices_snapped, below_10 += t.new_faces_below_10, added += t.faces_added;
    state.counters["vertices_snapped"] = double(snapped);
    state.counters["new_faces"] = double(added);
    state.counters["new_below_10"] = double(below_10);
    if (result.stats.intersecting_pairs != crossings.size()) state.SkipWithError("not every crossing was found");
    state.PauseTiming();  // destroying the meshes is not timed
    meshes.clear();
    state.ResumeTiming();
  }
}

void BM_pairs(benchmark::State& state) {
  const bool snap = state.range(0) != 0;
  const auto out = dir / (snap ? "pairs_snap" : "pairs_nosnap");
  std::filesystem::create_directories(out);
  for (auto _ : state) {
    const auto t0 = Clock::now();
    std::size_t found = 0;
    for (const auto& [a, b] : crossings) {
      auto ma = seam::mesh_from_soup<K>(seam::read_triangle_mesh(files[a]), files[a]);
      auto mb = seam::mesh_from_soup<K>(seam::read_triangle_mesh(files[b]), files[b]);
      seam::PairOptions o;
      if (!snap) o.embed.snap_tol = 0;
      const auto r = seam::pair<K>(ma, mb, o);
      found += r.curves.empty() ? 0 : 1;
      seam::write_triangle_mesh(seam::soup_from_mesh<K>(ma), (out / (names[a] + ".off")).string());
      seam::write_triangle_mesh(seam::soup_from_mesh<K>(mb), (out / (names[b] + ".off")).string());
      seam::write_polylines(seam::to_doubles<K>(r.curves), (out / (names[a] + "__" + names[b] + ".polylines.txt")).string());
    }
    const double total = seconds_since(t0);
    state.SetIterationTime(total);
    seconds[snap ? "pairs/snap:default" : "pairs/snap:0"] = total;
    if (found != crossings.size()) state.SkipWithError("not every crossing was found");
  }
}

/// The machine's parallel capacity at the time of the run (it is shared): the same fixed,
/// perfectly parallel CPU work (independent loops, no memory traffic) on 1 and on 2 threads.
void BM_calibration(benchmark::State& state) {
  const int threads = int(state.range(0));
  for (auto _ : state) {
    const auto t0 = Clock::now();
    tbb::task_arena arena(threads);
    std::vector<double> sums(16, 0.0);
    parallel(arena, sums.size(), [&](std::size_t i) {
      volatile double x = 0;
      for (long k = 0; k < 30000000; ++k) x = x + 1e-9;
      sums[i] = x;
    });
    const double total = seconds_since(t0);
    state.SetIterationTime(total);
    seconds["calibration/threads:" + std::to_string(threads)] = total;
  }
}

}  // namespace

int main(int argc, char** argv) {
  // Own option (removed before benchmark sees it): --textile_resolution=R.
  std::vector<char*> args;
  for (int i = 0; i < argc; ++i) {
    if (i > 0 && std::strncmp(argv[i], "--textile_resolution=", 21) == 0) {
      resolution = std::max(2, std::atoi(argv[i] + 21));
      continue;
    }
    args.push_back(argv[i]);
  }
  int n = static_cast<int>(args.size());
  benchmark::Initialize(&n, args.data());
  if (benchmark::ReportUnrecognizedArguments(n, args.data())) return 1;
  int status = 0;
  try {
    prepare();
    benchmark::RegisterBenchmark("calibration/threads:1", BM_calibration)->Arg(1)->Iterations(1)->UseManualTime()->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark("calibration/threads:2", BM_calibration)->Arg(2)->Iterations(1)->UseManualTime()->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark("textile/threads:1", BM_textile)->Arg(1)->Iterations(1)->UseManualTime()->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark("textile/threads:2", BM_textile)->Arg(2)->Iterations(1)->UseManualTime()->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark("pairs/snap:0", BM_pairs)->Arg(0)->Iterations(1)->UseManualTime()->Unit(benchmark::kMillisecond);
    benchmark::RegisterBenchmark("pairs/snap:default", BM_pairs)->Arg(1)->Iterations(1)->UseManualTime()->Unit(benchmark::kMillisecond);
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
    auto at = [](const std::string& prefix) {
      for (const auto& [name, s] : seconds)
        if (name.rfind(prefix, 0) == 0) return s;
      return 0.0;
    };
    const double t1 = at("textile/threads:1"), t2 = at("textile/threads:2"), p0 = at("pairs/snap:0"),
                 pd = at("pairs/snap:default");
    const double c1 = at("calibration/threads:1"), c2 = at("calibration/threads:2");
    if (c1 > 0 && c2 > 0)
      std::cerr << "calibration (perfectly parallel loops), 1 thread / 2 threads: " << c1 / c2
                << " (2 would mean two free cores)\n";
    if (t1 > 0 && t2 > 0) std::cerr << "textile, 1 thread / 2 threads: " << t1 / t2 << "\n";
    const double u1 = at("textile_cpu/threads:1"), u2 = at("textile_cpu/threads:2");
    if (t2 > 0 && u2 > 0)
      std::cerr << "textile, 2 threads: CPU time of all threads " << u2 << " s in " << t2 << " s (" << u2 / t2
                << " cores busy on average); 1 thread: " << u1 << " s CPU\n";
    if (t1 > 0 && p0 > 0) std::cerr << "16 x pair --snap-tol 0 / textile (1 thread): " << p0 / t1 << "\n";
    if (t1 > 0 && pd > 0) std::cerr << "16 x pair (default snapping) / textile (1 thread): " << pd / t1 << "\n";
    if (t2 > 0 && pd > 0) std::cerr << "16 x pair (default snapping) / textile (2 threads): " << pd / t2 << "\n";
  } catch (const std::exception& e) {
    std::cerr << "bench_textile: " << e.what() << "\n";
    status = 1;
  }
  std::error_code ec;
  if (!dir.empty()) std::filesystem::remove_all(dir, ec);
  return status;
}
