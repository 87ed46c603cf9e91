// seam textile: every interpenetration among the tows of a unit cell, embedded at once.
// SPDX-License-Identifier: GPL-3.0-or-later
#include "common.h"

#include <seam/textile.h>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>
#include <tbb/task_arena.h>

#include <unistd.h>

#include <cstdio>
#include <exception>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <mutex>
#include <sstream>

namespace seam_cli {

namespace {

struct TextileArgs {
  std::vector<std::string> tows;
  std::string tows_list, out_dir, report, kernel = "exact";
  int threads = 0;
  bool quiet = false;
  seam::TextileOptions options;
};

/// The paths of a list file: one per line; blank lines and lines starting with '#' are skipped,
/// surrounding blanks trimmed; a relative path is relative to the list file's directory.
std::vector<std::string> read_tow_list(const std::string& list) {
  std::error_code ec;
  if (fs::is_directory(list, ec)) throw seam::IOError(list + ": is a directory, not a list of tow files");
  std::ifstream in(list);
  if (!in) throw seam::IOError(list + ": cannot open the list of tow files");
  std::vector<std::string> paths;
  std::string line;
  const fs::path base = fs::path(list).parent_path();
  while (std::getline(in, line)) {
    const auto first = line.find_first_not_of(" \t\r");
    if (first == std::string::npos || line[first] == '#') continue;
    const auto last = line.find_last_not_of(" \t\r");
    const fs::path p = line.substr(first, last - first + 1);
    paths.push_back(p.is_absolute() ? p.string() : (base / p).string());
  }
  if (in.bad()) throw seam::IOError(list + ": read error");
  if (paths.empty()) throw seam::InvalidInput(list + ": no tow file listed");
  return paths;
}

/// Runs body(i) for i in [0, n) in `arena`; rethrows the first exception in index order.
template <class Body> void parallel_indices(tbb::task_arena& arena, std::size_t n, Body&& body) {
  std::vector<std::exception_ptr> errors(n);
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        for (std::size_t i = r.begin(); i != r.end(); ++i) try {
                            body(i);
                          } catch (...) {
                            errors[i] = std::current_exception();
                          }
                      },
                      tbb::simple_partitioner());
  });
  for (const auto& e : errors)
    if (e) std::rethrow_exception(e);
}

/// The progress line: rewritten in place on a terminal, otherwise one line at most every second
/// and at the end of each stage.
class Progress {
 public:
  explicit Progress(bool quiet) : quiet_(quiet), tty_(::isatty(2) == 1) {}
  void operator()(const seam::TextileProgress& p) {
    if (quiet_) return;
    const bool last = p.done == p.total;
    if (!tty_ && !last && p.elapsed_seconds - last_line_ < 1.0) return;
    last_line_ = p.elapsed_seconds;
    std::ostringstream line;
    line.precision(3);
    line << "seam textile: " << p.stage << " " << p.done << "/" << p.total << " done, " << p.elapsed_seconds
         << " s elapsed";
    if (!last && p.done > 0) line << ", about " << p.stage_seconds / double(p.done) * double(p.total - p.done) << " s left in this stage";
    std::string text = line.str();
    if (tty_) {
      std::cerr << "\r" << text << std::string(width_ > text.size() ? width_ - text.size() : 0, ' ');
      width_ = text.size();
      if (last) std::cerr << "\n", width_ = 0;
    } else {
      std::cerr << text << "\n";
    }
    std::cerr.flush();
  }

 private:
  bool quiet_, tty_;
  double last_line_ = -1e9;
  std::size_t width_ = 0;
};

int run_textile(TextileArgs& args) {
  seam::validate_options(args.options.embed);
  if (args.threads < 0) throw seam::InvalidInput("--threads " + std::to_string(args.threads) + ": must be >= 0");
  std::vector<std::string> inputs = args.tows;
  if (!args.tows_list.empty()) {
    const auto listed = read_tow_list(args.tows_list);
    inputs.insert(inputs.end(), listed.begin(), listed.end());
  }
  if (inputs.empty()) throw seam::InvalidInput("no tow given (TOW files or --tows LIST)");

  // Output names: the base name of each input, which must be unique.
  std::vector<std::string> names;
  std::map<std::string, std::string> by_name;
  for (const auto& in : inputs) {
    const std::string name = fs::path(in).stem().string();
    if (name.empty()) throw seam::InvalidInput(in + ": no base name to name its output after");
    auto [it, inserted] = by_name.emplace(name, in);
    if (!inserted)
      throw seam::InvalidInput(in + ": has the same base name as " + it->second + " (their outputs " + name +
                               ".off would collide)");
    names.push_back(name);
  }
  const fs::path dir = args.out_dir;
  auto mesh_out = [&](std::size_t i) { return (dir / (names[i] + ".off")).string(); };
  auto curves_out = [&](std::size_t a, std::size_t b) {
    return (dir / (names[a] + "__" + names[b] + ".polylines.txt")).string();
  };
  {
    std::vector<std::string> outputs;
    for (std::size_t i = 0; i < inputs.size(); ++i) outputs.push_back(mesh_out(i));
    outputs.push_back(args.report);
    std::vector<std::string> all_inputs = inputs;
    if (!args.tows_list.empty()) all_inputs.push_back(args.tows_list);
    refuse_overwrite(all_inputs, outputs);
    std::error_code ec;
    if (fs::exists(dir, ec) && !fs::is_directory(dir, ec))
      throw seam::InvalidInput(args.out_dir + ": --out-dir exists and is not a directory");
  }

  args.options.threads = args.threads;
  tbb::task_arena arena(args.threads > 0 ? args.threads : tbb::task_arena::automatic);
  const auto t0 = Clock::now();
  std::vector<seam::TriangleSoup> soups(inputs.size());
  parallel_indices(arena, inputs.size(), [&](std::size_t i) {
    soups[i] = seam::read_triangle_mesh(inputs[i]);
    seam::check_no_self_intersection(soups[i], inputs[i]);  // names two faces that intersect
  });
  const double read_seconds = std::chrono::duration<double>(Clock::now() - t0).count();

  return seam::with_kernel(parse_kernel(args.kernel), [&](auto kernel) {
    using K = decltype(kernel);
    std::vector<seam::Mesh<K>> meshes(inputs.size());
    for (std::size_t i = 0; i < inputs.size(); ++i) {
      meshes[i] = seam::mesh_from_soup<K>(soups[i], inputs[i]);
      seam::TriangleSoup().points.swap(soups[i].points);
      std::vector<std::array<std::size_t, 3>>().swap(soups[i].triangles);
    }
    Progress progress(args.quiet);
    args.options.progress = std::ref(progress);
    seam::TextileResult<K> result = seam::textile<K>(meshes, names, args.options);
    auto& st = result.stats;
    st.stage_seconds["read"] = read_seconds;

    // Everything to plain doubles first (each tow's mesh in one task), then the files.
    const auto t1 = Clock::now();
    std::vector<seam::TriangleSoup> out_soups(meshes.size());
    parallel_indices(arena, meshes.size(), [&](std::size_t i) { out_soups[i] = seam::soup_from_mesh<K>(meshes[i]); });
    std::vector<std::vector<std::vector<seam::Point3d>>> out_curves;
    std::vector<std::string> curve_paths;
    for (const auto& p : result.pairs)
      if (!p.curves.empty()) {
        out_curves.push_back(seam::to_doubles<K>(p.curves));
        curve_paths.push_back(curves_out(p.stats.a, p.stats.b));
      }
    std::error_code ec;
    const bool created_dir = !fs::exists(dir, ec);
    fs::create_directories(dir, ec);
    if (ec) throw seam::IOError(args.out_dir + ": cannot create the output directory (" + ec.message() + ")");
    try {
      write_all_or_nothing([&](std::vector<std::string>& written) {
        std::mutex mutex;
        const std::size_t n = out_soups.size() + out_curves.size();
        parallel_indices(arena, n, [&](std::size_t i) {
          const std::string path = i < out_soups.size() ? mesh_out(i) : curve_paths[i - out_soups.size()];
          if (i < out_soups.size()) seam::write_triangle_mesh(out_soups[i], path);
          else seam::write_polylines(out_curves[i - out_soups.size()], path);
          std::lock_guard<std::mutex> lock(mutex);
          written.push_back(path);
        });
        st.stage_seconds["write"] = std::chrono::duration<double>(Clock::now() - t1).count();
        if (!args.report.empty()) {
          nlohmann::json j;
          j["kernel"] = seam::kernel_name(seam::kernel_traits<K>::kind);
          j["threads"] = st.threads;
          j["candidate_pairs"] = st.candidate_pairs;
          j["intersecting_pairs"] = st.intersecting_pairs;
          j["touching_pairs"] = st.touching_pairs;
          j["triple_points"] = st.triple_points;
          nlohmann::json tows = nlohmann::json::array();
          for (std::size_t i = 0; i < meshes.size(); ++i)
            tows.push_back({{"name", names[i]}, {"file", inputs[i]}, {"out", mesh_out(i)}, {"embed", stats_json(result.tows[i])}});
          j["tows"] = tows;
          auto quality = [](const seam::CurveFaceQuality& q) {
            return nlohmann::json{{"new_faces", q.faces},
                                  {"min_angle_deg", q.min_angle_deg},
                                  {"below_10", q.below_10},
                                  {"below_20", q.below_20}};
          };
          nlohmann::json pairs = nlohmann::json::array();
          for (const auto& p : result.pairs) {
            const auto& s = p.stats;
            nlohmann::json e = {{"a", names[s.a]},
                                {"b", names[s.b]},
                                {"curves", s.curves},
                                {"closed_curves", s.closed_curves},
                                {"curve_vertices", s.curve_vertices},
                                {"touching_only", s.touching_only},
                                {"quality", {{"a", quality(s.quality_a)}, {"b", quality(s.quality_b)}}},
                                {"intersect_seconds", s.intersect_seconds},
                                {"copy_seconds", s.copy_seconds}};
            e["polylines"] = s.curves > 0 ? nlohmann::json(curves_out(s.a, s.b)) : nlohmann::json(nullptr);
            pairs.push_back(e);
          }
          j["pairs"] = pairs;
          j["seconds"] = st.stage_seconds;
          write_json(j, args.report);
          written.push_back(args.report);
        }
      });
    } catch (...) {
      if (created_dir) fs::remove(dir, ec);  // only if empty
      throw;
    }
    std::size_t curves = 0, snapped = 0;
    for (const auto& p : result.pairs) curves += p.stats.curves;
    for (const auto& t : result.tows) snapped += t.vertices_snapped;
    std::cout << "seam textile: " << meshes.size() << " tows, " << st.candidate_pairs << " candidate pairs, "
              << st.intersecting_pairs << " intersecting (" << curves << " curves), " << st.touching_pairs
              << " touching only; " << snapped << " vertices snapped; " << st.threads
              << (st.threads == 1 ? " thread" : " threads") << "; outputs in " << args.out_dir << "\n";
    return 0;
  });
}

}  // namespace

Command add_textile_command(CLI::App& app) {
  auto args = std::make_shared<TextileArgs>();
  TextileArgs& ta = *args;
  auto* cmd = app.add_subcommand(
      "textile",
      "Make every interpenetrating pair among N tows conforming: find the pairs (bounding boxes, then the exact "
      "intersection), compute each pair's curves, and embed into each tow all the curves that involve it, in "
      "parallel. Writes DIR/<name>.off per tow and DIR/<A>__<B>.polylines.txt per intersecting pair (A before B "
      "in input order); `seam check A B DIR/A.off DIR/B.off DIR/A__B.polylines.txt` passes for each. Vertices within a tiny distance of a curve are "
      "snapped onto it first. Where three tows overlap in one place the run stops with exit 2 naming them.");
  cmd->add_option("TOW", ta.tows, "Input tow meshes (.off, .obj, .ply, .stl); outputs are named after their base names");
  cmd->add_option("--tows", ta.tows_list,
                  "A file listing tow meshes, one path per line (relative paths from the list's directory; blank "
                  "lines and # comments skipped), after the TOW arguments");
  cmd->add_option("--out-dir", ta.out_dir, "Output directory (created if missing)")->required();
  cmd->add_option("--report", ta.report, "Write a JSON report: per tow the embedding figures, per pair the curves and the quality of the new faces along them");
  cmd->add_option("--threads", ta.threads, "Worker threads; 0: every core (default). Results are identical for any value");
  cmd->add_flag("--quiet", ta.quiet, "No progress line on stderr");
  cmd->add_option("--kernel", ta.kernel, "exact (Epeck, default), filtered (Epick) or float (double)")
      ->check(CLI::IsMember({"exact", "filtered", "float"}));
  cmd->add_option("--min-angle", ta.options.embed.min_angle_deg,
                  "Minimum angle (degrees, 0..60) refinement aims for in re-triangulated faces (default: 20)");
  cmd->add_option("--max-area", ta.options.embed.max_area, "Largest area of a new triangle; 0: no bound");
  cmd->add_option("--snap-tol", ta.options.embed.snap_tol,
                  "Move tow vertices within this distance of a curve onto it, then compute those curves again; 0 "
                  "disables (default: 1e-10 x the smallest tow bounding-box diagonal, below seam check's default "
                  "tolerance)");
  return {cmd, [args] { return run_textile(*args); }};
}

}  // namespace seam_cli
