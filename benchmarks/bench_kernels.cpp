// Benchmark of a whole `seam pair` run per kernel, stage by stage, on generated tow crossovers
// of about 1k to 1M faces per tow, with CGAL's corefine on the same pairs as the peer; and the
// peak memory of each run against the memory of holding the two input meshes.
//
// Input (generated once per size, outside every timed region, written as OFF files to a
// temporary directory removed at exit): a weft along x (seam::make_tow, elliptical, crimped)
// and a lenticular warp along y crossing its middle and dipping 0.25 into it (as bench_pair), each
// with 2 * around segments along and `around` around, around = sqrt(faces / 4): about `faces`
// triangles per tow. Non-degenerate: the meshes cross transversally in one closed curve.
//
// kernels/<tool>/faces:<N>/run:<r>, tool = exact | filtered | float | corefine; one iteration per
// run, the runs of one size alternate between the tools (exact, filtered, float, corefine,
// exact, ...; --kernels_runs=R, default 3) so that drifts of the shared machine affect all alike.
// Manual time = the wall-clock time of read both OFF files + compute + write both OFF files, as a
// command-line run does. seam: seam::pair<K> with snap_tol 0 (the surfaces unchanged, as
// corefine) and the default minimum angle (20 degrees). corefine: CGAL::Polygon_mesh_processing::
// corefine on Epeck meshes. Counters (seconds): read_s, write_s; seam: intersect_s (the
// intersection curves), snap_s, locate_s, cross_s, coarsen_s, retriangulate_s, splice_s (the
// embed stages of EmbedStats::stage_seconds summed over both meshes), embed_rest_s (rest of the two
// embed calls), embed_wall_s (the longer of the two embed calls, which run concurrently),
// pair_other_s (rest of the pair call), pair_s (the whole pair call); corefine:
// corefine_s. Also input_faces (of both tows), curve_vertices, output_faces. (pair_other_s leaves
// out the stages after the embedding, flat_contacts_s, improve_s, separate_s and verify_output_s,
// reported apart since stop 50; before, it held them.)
//
// memory/<tool>/faces:<N>: the same run (read, compute, write) in a fresh process (this program
// re-executed with --kernels_memory_child=...), reporting input_mb, the heap in use once both
// input meshes are read (mallinfo2: uordblks + hblkhd, the OFF text and soups freed), and peak_mb, the peak resident
// size of the process (getrusage maxrss) minus its resident size before reading; peak_ratio =
// peak_mb / input_mb.
//
// --kernels_max_faces=N skips sizes above N (default 1,000,000); --kernels_runs=R.
//
// --kernels_defaults: the growth of a whole run with the default options instead (the quality
// stage on, its tolerance automatic, the outputs verified as written): families
// defaults/<tool>/faces:<N>/run:<r> and defaults_memory/<tool>/faces:<N>, tool = exact |
// corefine, with the counters above and improve_s, flat_contacts_s, separate_s and
// verify_output_s (PairStats::stage_seconds; pair_other_s is then the rest). Like bench_pair's,
// the read does not check the inputs for self-intersections (the command line does).
//
// SPDX-License-Identifier: GPL-3.0-or-later
#include <seam/generate.h>
#include <seam/io.h>
#include <seam/kernels.h>
#include <seam/pair.h>

#include <CGAL/Polygon_mesh_processing/corefinement.h>

#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <malloc.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

struct Size {
  int faces = 0;  // nominal faces per tow
  std::string a, b;  // OFF files
  std::size_t input_faces = 0;
};

/// --kernels_defaults: seam::pair with the default options, not snap_tol 0.
bool& default_options() {
  static bool on = false;
  return on;
}

seam::PairOptions pair_options() {
  seam::PairOptions options;
  if (!default_options()) options.embed.snap_tol = 0;
  return options;
}

std::filesystem::path& temp_dir() {
  static std::filesystem::path dir;
  return dir;
}

Size prepare(int faces) {
  const int around = std::max(8, int(std::lround(std::sqrt(faces / 4.0))));
  // The warp's segments along not the weft's: no two rings meet at the same place.
  const auto [weft, warp] = seam::make_crossover(2 * around, around, 2 * around - 1, around, seam::Section::lenticular, 0.45);
  const seam::TriangleSoup sa = seam::make_tow(weft), sb = seam::make_tow(warp);
  Size s;
  s.faces = faces;
  s.a = (temp_dir() / ("weft_" + std::to_string(faces) + ".off")).string();
  s.b = (temp_dir() / ("warp_" + std::to_string(faces) + ".off")).string();
  seam::write_triangle_mesh(sa, s.a);
  seam::write_triangle_mesh(sb, s.b);
  s.input_faces = sa.triangles.size() + sb.triangles.size();
  return s;
}

struct Timings {
  std::map<std::string, double> s;
  std::size_t curve_vertices = 0, output_faces = 0;
};

template <class K> void read_both(const Size& size, std::optional<seam::Mesh<K>>& a, std::optional<seam::Mesh<K>>& b) {
  {
    const seam::TriangleSoup sa = seam::read_triangle_mesh(size.a);
    a.emplace(seam::mesh_from_soup<K>(sa, size.a));
  }
  const seam::TriangleSoup sb = seam::read_triangle_mesh(size.b);
  b.emplace(seam::mesh_from_soup<K>(sb, size.b));
}

template <class K> void write_both(const seam::Mesh<K>& a, const seam::Mesh<K>& b, const std::string& tag) {
  seam::write_triangle_mesh(seam::soup_from_mesh<K>(a), (temp_dir() / (tag + "_a.off")).string());
  seam::write_triangle_mesh(seam::soup_from_mesh<K>(b), (temp_dir() / (tag + "_b.off")).string());
}

double stage(const std::map<std::string, double>& m, const char* name) {
  auto it = m.find(name);
  return it == m.end() ? 0.0 : it->second;
}

/// One whole run: read, seam::pair<K> (snap_tol 0, or the defaults), write.
template <class K> Timings run_seam(const Size& size) {
  Timings t;
  std::optional<seam::Mesh<K>> a, b;
  auto c = Clock::now();
  read_both<K>(size, a, b);
  t.s["read"] = seconds_since(c);
  c = Clock::now();
  const seam::PairResult<K> r = seam::pair<K>(*a, *b, pair_options());
  const double pair_s = seconds_since(c);
  c = Clock::now();
  write_both<K>(*a, *b, "seam");
  t.s["write"] = seconds_since(c);
  t.s["pair"] = pair_s;
  const auto& st = r.stats.stage_seconds;
  t.s["intersect"] = stage(st, "intersect");
  double embed_stages = 0;
  for (const char* name : {"snap", "locate", "cross", "coarsen", "retriangulate", "splice"}) {
    const double v = stage(r.a.stats.stage_seconds, name) + stage(r.b.stats.stage_seconds, name);
    t.s[name] = v;
    embed_stages += v;
  }
  t.s["snap"] += stage(st, "snap");
  // The two embeddings run concurrently: their stages are summed (CPU time of both), the
  // embedding's share of the pair call is the longer of the two.
  t.s["embed_rest"] = stage(st, "embed_a") + stage(st, "embed_b") - embed_stages;
  t.s["embed_wall"] = std::max(stage(st, "embed_a"), stage(st, "embed_b"));
  double after_embedding = 0;
  for (const char* name : {"flat_contacts", "improve", "separate", "verify_output"}) {
    t.s[name] = stage(st, name);
    after_embedding += t.s[name];
  }
  t.s["pair_other"] = pair_s - stage(st, "intersect") - stage(st, "snap") - t.s["embed_wall"] - after_embedding;
  t.curve_vertices = r.stats.curve_vertices;
  t.output_faces = a->number_of_faces() + b->number_of_faces();
  return t;
}

Timings run_corefine(const Size& size) {
  using K = seam::Exact;
  Timings t;
  std::optional<seam::Mesh<K>> a, b;
  auto c = Clock::now();
  read_both<K>(size, a, b);
  t.s["read"] = seconds_since(c);
  c = Clock::now();
  CGAL::Polygon_mesh_processing::corefine(*a, *b);
  t.s["corefine"] = seconds_since(c);
  c = Clock::now();
  write_both<K>(*a, *b, "corefine");
  t.s["write"] = seconds_since(c);
  t.output_faces = a->number_of_faces() + b->number_of_faces();
  return t;
}

Timings run_tool(const std::string& tool, const Size& size) {
  if (tool == "exact") return run_seam<seam::Exact>(size);
  if (tool == "filtered") return run_seam<seam::Filtered>(size);
  if (tool == "float") return run_seam<seam::Float>(size);
  return run_corefine(size);
}

void BM_run(benchmark::State& state, std::string tool, const Size* size) {
  for (auto _ : state) {
    Timings t;
    try {
      t = run_tool(tool, *size);
    } catch (const std::exception& e) {
      state.SkipWithError(e.what());
      break;
    }
    state.SetIterationTime(t.s["read"] + (tool == "corefine" ? t.s["corefine"] : t.s["pair"]) + t.s["write"]);
    for (const auto& [k, v] : t.s) state.counters[k + "_s"] = v;
    state.counters["input_faces"] = double(size->input_faces);
    state.counters["curve_vertices"] = double(t.curve_vertices);
    state.counters["output_faces"] = double(t.output_faces);
  }
  state.SetLabel(tool);
}

long rss_kb() {  // current resident size
  std::ifstream in("/proc/self/statm");
  long pages = 0, resident = 0;
  in >> pages >> resident;
  return resident * (::sysconf(_SC_PAGESIZE) / 1024);
}

/// In a fresh process: read, hold, compute, write; prints "input_bytes peak_kb base_kb".
int memory_child(const std::string& tool, const std::string& fa, const std::string& fb, const std::string& dir) {
  temp_dir() = dir;
  Size size;
  size.a = fa;
  size.b = fb;
  const long base_kb = rss_kb();
  // Heap in use: small blocks (uordblks) and the large ones glibc maps on their own (hblkhd).
  auto heap = [] {
    const struct mallinfo2 m = mallinfo2();
    return m.uordblks + m.hblkhd;
  };
  const std::size_t heap0 = heap();
  std::size_t input_bytes = 0;
  auto run = [&](auto k) {
    using K = decltype(k);
    std::optional<seam::Mesh<K>> a, b;
    read_both<K>(size, a, b);
    input_bytes = heap() - heap0;
    if constexpr (std::is_same_v<K, seam::Exact>) {
      if (tool == "corefine") {
        CGAL::Polygon_mesh_processing::corefine(*a, *b);
        write_both<K>(*a, *b, "memory");
        return;
      }
    }
    seam::pair<K>(*a, *b, pair_options());
    write_both<K>(*a, *b, "memory");
  };
  if (tool == "filtered") run(seam::Filtered{});
  else if (tool == "float") run(seam::Float{});
  else run(seam::Exact{});
  rusage u{};
  ::getrusage(RUSAGE_SELF, &u);
  std::printf("%zu %ld %ld\n", input_bytes, long(u.ru_maxrss), base_kb);
  return 0;
}

void BM_memory(benchmark::State& state, std::string tool, const Size* size) {
  for (auto _ : state) {
    const std::string cmd = "/proc/self/exe --kernels_memory_child=" + tool + "," + size->a + "," + size->b + "," +
                            temp_dir().string() + (default_options() ? " --kernels_defaults" : "");
    // /proc/self/exe of the shell would be the shell: resolve ours.
    char self[4096];
    const ssize_t n = ::readlink("/proc/self/exe", self, sizeof self - 1);
    if (n <= 0) {
      state.SkipWithError("readlink /proc/self/exe failed");
      break;
    }
    self[n] = 0;
    const std::string command = std::string(self) + cmd.substr(std::strlen("/proc/self/exe"));
    const auto start = Clock::now();
    FILE* p = ::popen(command.c_str(), "r");
    std::size_t input_bytes = 0;
    long peak_kb = 0, base_kb = 0;
    const int got = p ? std::fscanf(p, "%zu %ld %ld", &input_bytes, &peak_kb, &base_kb) : 0;
    const int status = p ? ::pclose(p) : -1;
    if (got != 3 || status != 0) {
      state.SkipWithError("the memory run failed");
      break;
    }
    state.SetIterationTime(seconds_since(start));  // the whole child process
    state.counters["input_mb"] = double(input_bytes) / 1048576.0;
    state.counters["peak_mb"] = double(peak_kb - base_kb) / 1024.0;
    state.counters["peak_ratio"] = input_bytes ? double(peak_kb - base_kb) * 1024.0 / double(input_bytes) : 0.0;
    state.counters["input_faces"] = double(size->input_faces);
  }
  state.SetLabel(tool);
}

}  // namespace

int main(int argc, char** argv) {
  int runs = 3;
  long max_faces = 1000000;
  std::vector<char*> args;
  for (int i = 1; i < argc; ++i)  // (before a memory child's run, which takes it too)
    if (std::strcmp(argv[i], "--kernels_defaults") == 0) default_options() = true;
  for (int i = 0; i < argc; ++i) {
    if (i > 0 && std::strncmp(argv[i], "--kernels_memory_child=", 23) == 0) {
      std::stringstream s(argv[i] + 23);
      std::string tool, fa, fb, dir;
      std::getline(s, tool, ',');
      std::getline(s, fa, ',');
      std::getline(s, fb, ',');
      std::getline(s, dir, ',');
      try {
        return memory_child(tool, fa, fb, dir);
      } catch (const std::exception& e) {
        std::cerr << "bench_kernels memory run: " << e.what() << "\n";
        return 1;
      }
    }
    if (i > 0 && std::strcmp(argv[i], "--kernels_defaults") == 0) continue;
    if (i > 0 && std::strncmp(argv[i], "--kernels_runs=", 15) == 0) {
      runs = std::max(1, std::atoi(argv[i] + 15));
      continue;
    }
    if (i > 0 && std::strncmp(argv[i], "--kernels_max_faces=", 20) == 0) {
      max_faces = std::atol(argv[i] + 20);
      continue;
    }
    args.push_back(argv[i]);
  }
  int n = static_cast<int>(args.size());
  benchmark::Initialize(&n, args.data());
  if (benchmark::ReportUnrecognizedArguments(n, args.data())) return 1;

  temp_dir() = std::filesystem::temp_directory_path() / ("seam_bench_kernels." + std::to_string(::getpid()));
  std::filesystem::create_directories(temp_dir());
  static std::vector<Size> sizes;
  int status = 0;
  try {
    for (int faces : {1000, 3000, 10000, 30000, 100000, 300000, 1000000})
      if (faces <= max_faces) sizes.push_back(prepare(faces));
  } catch (const std::exception& e) {
    std::cerr << "bench_kernels: " << e.what() << "\n";
    status = 1;
  }
  if (status == 0) {
    const std::vector<std::string> tools = default_options() ? std::vector<std::string>{"exact", "corefine"}
                                                             : std::vector<std::string>{"exact", "filtered", "float", "corefine"};
    const std::string family = default_options() ? "defaults" : "kernels";
    const std::string memory_family = default_options() ? "defaults_memory" : "memory";
    for (const Size& s : sizes) {
      const std::string f = "/faces:" + std::to_string(s.faces);
      for (int r = 1; r <= runs; ++r)
        for (const auto& tool : tools)
          benchmark::RegisterBenchmark((family + "/" + tool + f + "/run:" + std::to_string(r)).c_str(), BM_run, tool, &s)
              ->Iterations(1)->UseManualTime()->Unit(benchmark::kMillisecond);
      for (const auto& tool : tools)
        benchmark::RegisterBenchmark((memory_family + "/" + tool + f).c_str(), BM_memory, tool, &s)
            ->Iterations(1)->UseManualTime()->Unit(benchmark::kMillisecond);
    }
    benchmark::RunSpecifiedBenchmarks();
    benchmark::Shutdown();
  }
  std::error_code ec;
  std::filesystem::remove_all(temp_dir(), ec);
  return status;
}
