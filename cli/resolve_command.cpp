// seam resolve: give the overlap of two conforming tows (seam pair's outputs) to one of them.
// SPDX-License-Identifier: GPL-3.0-or-later
#include "common.h"

#include <seam/resolve.h>

#include <tbb/parallel_invoke.h>

#include <iostream>
#include <memory>

namespace seam_cli {

namespace {

struct ResolveArgs {
  std::string a, b, out_a, out_b, report, keep = "auto", kernel = "exact";
};

seam::Keeper parse_keeper(const std::string& k) {
  if (k == "a") return seam::Keeper::a;
  if (k == "b") return seam::Keeper::b;
  return seam::Keeper::automatic;
}

int run_resolve(const ResolveArgs& args) {
  // Every output path before any work (renamed in this order at the end: meshes, report).
  refuse_overwrite({args.a, args.b}, {args.out_a, args.out_b, args.report});
  seam::check_mesh_extension(args.out_a);
  seam::check_mesh_extension(args.out_b);
  seam::OutputFiles files;
  const auto out = add_outputs(files, {args.out_a, args.out_b, args.report});
  const auto t0 = Clock::now();
  seam::TriangleSoup soup_a, soup_b;
  tbb::parallel_invoke(
      [&] {
        soup_a = seam::read_triangle_mesh(args.a);
        seam::check_no_self_intersection(soup_a, args.a);
      },
      [&] {
        soup_b = seam::read_triangle_mesh(args.b);
        seam::check_no_self_intersection(soup_b, args.b);
      });
  const double read_seconds = std::chrono::duration<double>(Clock::now() - t0).count();

  return seam::with_kernel(parse_kernel(args.kernel), [&](auto kernel) {
    using K = decltype(kernel);
    seam::Mesh<K> a = seam::mesh_from_soup<K>(soup_a, args.a), b = seam::mesh_from_soup<K>(soup_b, args.b);
    seam::ResolveOptions options;
    options.keeper = parse_keeper(args.keep);
    options.name_a = args.a;
    options.name_b = args.b;
    seam::ResolveStats st = seam::resolve<K>(a, b, options);
    st.stage_seconds["read"] = read_seconds;
    // The outputs as they will be written (their points are the inputs' doubles), verified
    // independently before anything is written.
    auto t1 = Clock::now();
    const seam::TriangleSoup out_a = seam::soup_from_mesh<K>(a), out_b = seam::soup_from_mesh<K>(b);
    const seam::ResolvedCheckReport check = seam::check_resolved<seam::Exact>(
        seam::mesh_from_soup<seam::Exact>(out_a, args.out_a), seam::mesh_from_soup<seam::Exact>(out_b, args.out_b));
    if (!check.ok())
      throw seam::InternalError("resolve: the result failed its check (" + std::to_string(check.problems.size()) +
                                " problem(s); first: " + check.problems.front() + "); nothing written");
    st.stage_seconds["verify"] = std::chrono::duration<double>(Clock::now() - t1).count();
    t1 = Clock::now();
    tbb::parallel_invoke(
        [&] {
          files.write(out[0], [&](std::ostream& os) {
            seam::write_triangle_mesh(out_a, os, fs::path(args.out_a).extension().string());
          });
        },
        [&] {
          files.write(out[1], [&](std::ostream& os) {
            seam::write_triangle_mesh(out_b, os, fs::path(args.out_b).extension().string());
          });
        });
    st.stage_seconds["write"] = std::chrono::duration<double>(Clock::now() - t1).count();
    if (out[2] != no_output) {
      nlohmann::json j = resolve_report_json(seam::kernel_traits<K>::kind, st, check);
      j["files"] = {{"a", args.a}, {"b", args.b}, {"out_a", args.out_a}, {"out_b", args.out_b}};
      files.write(out[2], [&](std::ostream& os) { write_json(j, os); });
    }
    files.commit();
    const bool a_keeps = st.keeper == seam::Keeper::a;
    std::cout << "seam resolve: " << (a_keeps ? "A" : "B") << " keeps the overlap (volume " << st.overlap_volume
              << "); A " << st.volume_a_before << " -> " << st.volume_a_after << ", B " << st.volume_b_before << " -> "
              << st.volume_b_after << "; " << st.contact_faces << " contact faces (" << (a_keeps ? "B" : "A")
              << " lost " << st.faces_removed << " faces, gained " << st.faces_added << "); verified";
    if (!st.note.empty()) std::cout << "; " << st.note;
    std::cout << "\n";
    return 0;
  });
}

}  // namespace

Command add_resolve_command(CLI::App& app) {
  auto args = std::make_shared<ResolveArgs>();
  ResolveArgs& ra = *args;
  auto* cmd = app.add_subcommand(
      "resolve",
      "Give the overlap of two conforming tows (the outputs of seam pair) to one of them: the other keeps its part "
      "outside the keeper, closed by the keeper's faces inside it, so that the two no longer overlap and touch "
      "along a shared contact surface (the same faces in both outputs). Faces are classified exactly, one side "
      "test per patch between the curves; the outputs are checked before they are written.");
  cmd->add_option("A2", ra.a, "First tow, curves embedded (seam pair --out-a)")->required();
  cmd->add_option("B2", ra.b, "Second tow, curves embedded (seam pair --out-b)")->required();
  cmd->add_option("--out-a", ra.out_a, "Output for A (format by extension)")->required();
  cmd->add_option("--out-b", ra.out_b, "Output for B")->required();
  cmd->add_option("--keep", ra.keep,
                  "Which tow keeps the overlap: a, b, or auto (default: the smaller tow keeps it, so that the other "
                  "loses the smaller fraction of its volume)")
      ->check(CLI::IsMember({"a", "b", "auto"}));
  cmd->add_option("--report", ra.report, "Write a JSON report: volumes before and after, overlap, contact faces");
  cmd->add_option("--kernel", ra.kernel,
                  "exact (default), filtered or float: the type of the meshes; every decision and volume is exact "
                  "under all three")
      ->check(CLI::IsMember({"exact", "filtered", "float"}));
  return {cmd, [args] { return run_resolve(*args); }};
}

}  // namespace seam_cli
