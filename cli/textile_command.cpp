// seam textile: every interpenetration among the tows of a unit cell, embedded at once.
// SPDX-License-Identifier: GPL-3.0-or-later
#include "common.h"

#include <seam/resolve.h>
#include <seam/textile.h>

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/partitioner.h>
#include <tbb/task_arena.h>

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <exception>
#include <fstream>
#include <iostream>
#include <map>
#include <memory>
#include <set>
#include <sstream>

namespace seam_cli {

namespace {

/// --threads above this is refused (a task arena of a million slots is not a request for work).
constexpr double max_threads = 1024;

struct TextileArgs {
  std::vector<std::string> tows;
  std::string tows_list, out_dir, report, kernel = "exact";
  NumberText threads, min_angle, max_area, snap_tol, bound_reach;
  bool quiet = false, resolve = false;
  seam::TextileOptions options;
};

/// --resolve: seam::resolve_pairs on the tows as written (doubles), the smaller tow of each pair
/// keeping its overlap (as `seam resolve --keep auto`). `soups` are replaced by the resolved tows.
/// Throws InternalError naming the pair on a failure (the inputs were valid: the pipeline's own
/// outputs are what resolve refused).
std::vector<seam::ResolveStats> resolve_tows(std::vector<seam::TriangleSoup>& soups,
                                             const std::vector<std::pair<std::size_t, std::size_t>>& pairs,
                                             const std::vector<std::string>& names) {
  std::vector<seam::Mesh<seam::Exact>> tows;
  for (std::size_t i = 0; i < soups.size(); ++i) tows.push_back(seam::mesh_from_soup<seam::Exact>(soups[i], names[i]));
  std::vector<seam::ResolveStats> stats;
  try {
    stats = seam::resolve_pairs<seam::Exact>(tows, pairs, names);
  } catch (const seam::InvalidInput& e) {
    throw seam::InternalError(std::string("--resolve: ") + e.what());
  } catch (const seam::InternalError& e) {
    throw seam::InternalError(std::string("--resolve: ") + e.what() + " (nothing written)");
  }
  for (std::size_t i = 0; i < soups.size(); ++i) soups[i] = seam::soup_from_mesh<seam::Exact>(tows[i]);
  return stats;
}

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

/// A path made absolute and canonical as far as it exists (symbolic links resolved); empty on error.
fs::path canonical_or_empty(const fs::path& p) {
  std::error_code ec;
  const fs::path abs = fs::absolute(p, ec);
  if (ec) return {};
  fs::path c = fs::weakly_canonical(abs, ec);
  return ec ? fs::path() : c;
}

/// The outputs in DIR: tow i's mesh, and the curves of the pair (a, b).
std::string mesh_output(const fs::path& dir, const std::vector<std::string>& names, std::size_t i) {
  return (dir / (names[i] + ".off")).string();
}
std::string curves_file_name(const std::vector<std::string>& names, std::size_t a, std::size_t b) {
  return names[a] + "__" + names[b] + ".polylines.txt";
}
std::string curves_output(const fs::path& dir, const std::vector<std::string>& names, std::size_t a, std::size_t b) {
  return (dir / curves_file_name(names, a, b)).string();
}

/// Refuses, before any work, a curves file name DIR/<A>__<B>.polylines.txt that two pairs share,
/// that is an input (a tow or the --tows list, also through a symbolic link in DIR) or the
/// report, or that exists and is not a regular file. Every pair A < B is checked, whether it will
/// intersect or not: the names depend on the tows' names only.
void check_curve_outputs(const fs::path& dir, const std::vector<std::string>& names,
                         const std::vector<std::string>& inputs, const std::string& report) {
  const fs::path canonical_dir = canonical_or_empty(dir);
  std::set<fs::path> input_paths;
  for (const auto& in : inputs)
    if (const fs::path c = canonical_or_empty(in); !c.empty()) input_paths.insert(c);
  const fs::path report_path = report.empty() ? fs::path() : canonical_or_empty(report);
  // The entries of DIR that exist: where each leads (a symbolic link, to its target).
  std::map<std::string, fs::path> existing;
  std::error_code ec;
  if (fs::is_directory(dir, ec))
    for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec))
      existing[it->path().filename().string()] = canonical_or_empty(it->path());
  std::map<std::string, std::pair<std::size_t, std::size_t>> by_name;
  for (std::size_t a = 0; a < names.size(); ++a)
    for (std::size_t b = a + 1; b < names.size(); ++b) {
      const std::string name = curves_file_name(names, a, b);
      const std::string path = (dir / name).string();
      const auto [it, inserted] = by_name.emplace(name, std::make_pair(a, b));
      if (!inserted)
        throw seam::InvalidInput(path + ": the curves of tows '" + names[it->second.first] + "' and '" +
                                 names[it->second.second] + "' and of tows '" + names[a] + "' and '" + names[b] +
                                 "' would both be written here (rename a tow: '__' in tow names makes pair names "
                                 "ambiguous)");
      const auto e = existing.find(name);
      const fs::path target = e != existing.end() ? e->second : canonical_dir.empty() ? fs::path() : canonical_dir / name;
      if (target.empty()) continue;
      if (input_paths.count(target) > 0)
        throw seam::InvalidInput(path + ": the curves of tows '" + names[a] + "' and '" + names[b] +
                                 "' would be written over an input (refusing to overwrite an input)");
      if (!report_path.empty() && target == report_path)
        throw seam::InvalidInput(report + ": the same path is given for two outputs (" + path + ")");
      if (e != existing.end()) seam::check_output_path(path);
    }
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

/// Output names: the base name of each input, which must be unique.
std::vector<std::string> output_names(const std::vector<std::string>& inputs) {
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
  return names;
}

/// The summary line on stdout.
template <class K>
void print_summary(const seam::TextileResult<K>& result, const TextileArgs& args,
                   const std::vector<seam::ResolveStats>& resolved) {
  const auto& st = result.stats;
  std::size_t curves = 0, snapped = 0;
  for (const auto& p : result.pairs) curves += p.stats.curves;
  for (const auto& t : result.tows) snapped += t.vertices_snapped;
  std::cout << "seam textile: " << result.tows.size() << " tows, " << st.candidate_pairs << " candidate pairs, "
            << st.intersecting_pairs << " intersecting (" << curves << " curves), " << st.touching_pairs
            << " touching only; " << snapped << " vertices snapped; " << st.threads
            << (st.threads == 1 ? " thread" : " threads");
  if (st.improved)
    std::cout << "; quality stage (tolerance " << st.improve_tolerance << "): " << st.improve.shortfalls.size()
              << " new faces below " << args.options.embed.min_angle_deg << " degrees";
  if (st.verified) std::cout << "; verified (seam check --tol " << tolerance_text(st.verify_tolerance) << ")";
  if (args.resolve) {
    double overlap = 0;
    for (const auto& r : resolved) overlap += r.overlap_volume;
    std::cout << "; resolved: " << resolved.size() << " pairs, overlap " << overlap
              << " given to one tow of each, checked (no overlap left)";
  }
  if (!st.note.empty()) std::cout << "; " << st.note;
  std::cout << "; outputs in " << args.out_dir << "\n";
}

/// The report: the library's, with each tow's files, each pair's curves file and what --resolve
/// did to it.
template <class K>
nlohmann::json textile_report(const seam::TextileResult<K>& result, const TextileArgs& args,
                              const std::vector<std::string>& inputs, const std::vector<std::string>& names,
                              const std::vector<std::pair<std::size_t, std::size_t>>& resolved_pairs,
                              const std::vector<seam::ResolveStats>& resolved) {
  const fs::path dir = args.out_dir;
  nlohmann::json j = textile_report_json<K>(result, names);
  for (std::size_t i = 0; i < inputs.size(); ++i) {
    j["tows"][i]["file"] = inputs[i];
    j["tows"][i]["out"] = mesh_output(dir, names, i);
  }
  for (std::size_t k = 0; k < result.pairs.size(); ++k) {
    const auto& s = result.pairs[k].stats;
    const bool has_file = s.curves + s.contact_points > 0 && !args.resolve;
    j["pairs"][k]["polylines"] = has_file ? nlohmann::json(curves_output(dir, names, s.a, s.b)) : nlohmann::json(nullptr);
    const auto done = std::find(resolved_pairs.begin(), resolved_pairs.end(), std::make_pair(s.a, s.b));
    if (done != resolved_pairs.end()) {
      const seam::ResolveStats& rs = resolved[std::size_t(done - resolved_pairs.begin())];
      nlohmann::json r = resolve_report_json(seam::kernel_traits<seam::Exact>::kind, rs, {});
      r.erase("verified");
      r.erase("check");
      r["keeper"] = names[rs.keeper == seam::Keeper::a ? s.a : s.b];
      j["pairs"][k]["resolve"] = r;
    }
  }
  return j;
}

int run_textile(TextileArgs& args) {
  // Every option before any work.
  seam::EmbedOptions& o = args.options.embed;
  const int threads =
      static_cast<int>(number_option("--threads", args.threads, NumberRange::integer_between(0, max_threads, "0: every core"), 0));
  o.min_angle_deg = number_option("--min-angle", args.min_angle, NumberRange::between(0, 60, "degrees"), o.min_angle_deg);
  o.max_area = number_option("--max-area", args.max_area, NumberRange::non_negative(), o.max_area);
  o.snap_tol = number_option("--snap-tol", args.snap_tol, NumberRange::non_negative_or_auto(), o.snap_tol);
  read_bound_reach_option(args.bound_reach, args.options.quality.bound_reach);
  seam::validate_options(args.options.embed);
  std::vector<std::string> inputs = args.tows;
  if (!args.tows_list.empty()) {
    const auto listed = read_tow_list(args.tows_list);
    inputs.insert(inputs.end(), listed.begin(), listed.end());
  }
  if (inputs.empty()) throw seam::InvalidInput("no tow given (TOW files or --tows LIST)");

  const std::vector<std::string> names = output_names(inputs);
  const fs::path dir = args.out_dir;
  auto mesh_out = [&](std::size_t i) { return mesh_output(dir, names, i); };
  std::vector<std::string> all_inputs = inputs;
  if (!args.tows_list.empty()) all_inputs.push_back(args.tows_list);
  {
    std::vector<std::string> outputs;
    for (std::size_t i = 0; i < inputs.size(); ++i) outputs.push_back(mesh_out(i));
    outputs.push_back(args.report);
    refuse_overwrite(all_inputs, outputs);
    std::error_code ec;
    if (fs::exists(dir, ec) && !fs::is_directory(dir, ec))
      throw seam::InvalidInput(args.out_dir + ": --out-dir exists and is not a directory");
    // Every pair's curves file too, although only the pairs that intersect will write one: two
    // pairs may not share a name (tows 'a__b' and 'c', 'a' and 'b__c'), and none may be an input
    // (the --tows list) or the report.
    check_curve_outputs(dir, names, all_inputs, args.report);
  }
  // The output directory and the temporary files of the meshes and the report, before any work;
  // the curves files' once the pairs are known. Renamed at the end: meshes, curves, report.
  seam::OutputFiles files;
  files.create_directory(args.out_dir);
  std::vector<std::size_t> mesh_file(inputs.size());
  for (std::size_t i = 0; i < inputs.size(); ++i) mesh_file[i] = files.add(mesh_out(i));
  const std::size_t report_file = args.report.empty() ? no_output : files.add(args.report, /*last=*/true);

  args.options.threads = threads;
  tbb::task_arena arena(threads > 0 ? threads : tbb::task_arena::automatic);
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
    std::vector<std::pair<std::size_t, std::size_t>> resolved_pairs;
    std::vector<seam::ResolveStats> resolved;
    if (args.resolve) {
      const auto t2 = Clock::now();
      for (const auto& p : result.pairs)  // pairs that only touch do not overlap
        if (p.stats.curves > 0) resolved_pairs.emplace_back(p.stats.a, p.stats.b);
      resolved = resolve_tows(out_soups, resolved_pairs, names);
      st.stage_seconds["resolve"] = std::chrono::duration<double>(Clock::now() - t2).count();
    }
    // The curves files (not with --resolve: the resolved tows are not seam check's pairs any more).
    std::vector<std::vector<std::vector<seam::Point3d>>> out_curves;
    std::vector<std::size_t> curve_file;
    for (const auto& p : result.pairs)
      if (!p.curves.empty() && !args.resolve) {
        out_curves.push_back(seam::to_doubles<K>(p.curves));
        curve_file.push_back(files.add(curves_output(dir, names, p.stats.a, p.stats.b)));
      }
    const std::size_t n = out_soups.size() + out_curves.size();
    parallel_indices(arena, n, [&](std::size_t i) {
      if (i < out_soups.size())
        files.write(mesh_file[i], [&](std::ostream& os) { seam::write_triangle_mesh(out_soups[i], os, "off"); });
      else
        files.write(curve_file[i - out_soups.size()],
                    [&](std::ostream& os) { seam::write_polylines(out_curves[i - out_soups.size()], os); });
    });
    st.stage_seconds["write"] = std::chrono::duration<double>(Clock::now() - t1).count();
    if (report_file != no_output) {
      const nlohmann::json j = textile_report<K>(result, args, inputs, names, resolved_pairs, resolved);
      files.write(report_file, [&](std::ostream& os) { write_json(j, os); });
    }
    files.commit();
    print_summary<K>(result, args, resolved);
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
      "parallel. Writes DIR/<name>.off per tow and DIR/<A>__<B>.polylines.txt per pair that meets (A before B "
      "in input order). Vertices within a tiny distance of a curve are snapped onto it first; then the quality stage "
      "refines the faces along the curves of all tows at once, and every pair is checked as written: "
      "`seam check A B DIR/A.off DIR/B.off DIR/A__B.polylines.txt --tol T` passes for each, with the T printed. Where three tows overlap in one place, the exact kernel makes the point a vertex of all three, and where a tow crosses a flat contact of two others, their common curve segments edges of all three; where three tows coincide over an area with different faces there (or under a rounded kernel) the run stops with exit 2 naming them.");
  cmd->add_option("TOW", ta.tows, "Input tow meshes (.off, .obj, .ply, .stl); outputs are named after their base names");
  cmd->add_option("--tows", ta.tows_list,
                  "A file listing tow meshes, one path per line (relative paths from the list's directory; blank "
                  "lines and # comments skipped), after the TOW arguments");
  cmd->add_option("--out-dir", ta.out_dir, "Output directory (created if missing)")->required();
  cmd->add_option("--report", ta.report, "Write a JSON report: per tow the embedding figures, per pair the curves and the quality of the new faces along them");
  add_number_option(cmd, "--threads", ta.threads,
                    "Worker threads, 0 to 1024; 0: every core (default). Results are identical for any value");
  cmd->add_flag("--quiet", ta.quiet, "No progress line on stderr");
  cmd->add_flag("--resolve", ta.resolve,
                "Then give each intersecting pair's overlap to its smaller tow (as seam resolve --keep auto), pair "
                "by pair, so that the tows touch along shared contact surfaces without overlapping; checked as "
                "seam resolve checks; no curves files are written");
  cmd->add_flag_callback(
      "--no-improve", [&ta] { ta.options.improve = false; },
      "No quality stage: the faces along the curves are left as the re-triangulation made them (every pair is "
      "still checked as written)");
  cmd->add_option("--kernel", ta.kernel, "exact (Epeck, default), filtered (Epick) or float (double)")
      ->check(CLI::IsMember({"exact", "filtered", "float"}));
  add_number_option(cmd, "--min-angle", ta.min_angle,
                    "Minimum angle (degrees, 0..60) refinement aims for in re-triangulated faces (default: 20)");
  add_number_option(cmd, "--max-area", ta.max_area, "Largest area of a new triangle: the re-triangulation and the quality stage refine to it; 0: no bound (default: 0)");
  add_number_option(cmd, "--snap-tol", ta.snap_tol,
                    "Move tow vertices within this distance of a curve onto it, then compute those curves again; 0 "
                    "disables (default: auto, 1e-10 x the smallest tow bounding-box diagonal, below seam check's "
                    "default tolerance)");
  add_bound_reach_option(cmd, ta.bound_reach);
  return {cmd, [args] { return run_textile(*args); }};
}

}  // namespace seam_cli
