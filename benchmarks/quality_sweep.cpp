// The quality sweep: seam::pair with the default options on the generated crossovers that the
// quality figures of docs/results.md are measured on, each result checked with seam::check_pair at the snapping
// tolerance. Two sets: "sweep" (a weft against a warp of either section, resolutions 5-24,
// overlaps 0.15-0.3: the set the remeshing was tuned on) and "held-out" (generated differently:
// a wider, thicker warp, turned by 90 or 65 degrees, tilted by 0 or 9 degrees, both sections on
// both tows). Prints one JSON object per crossover and a summary per set.
//   quality_sweep [sweep|held-out|all] [--snap-factor F]
// SPDX-License-Identifier: GPL-3.0-or-later
#include <seam/check.h>
#include <seam/generate.h>
#include <seam/io.h>
#include <seam/pair.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

namespace {

struct Case {
  std::string name;
  seam::TowOptions weft, warp;
};

std::vector<Case> sweep() {
  std::vector<Case> cases;
  for (int r : {5, 6, 8, 10, 12, 14, 16, 20, 24})
    for (double overlap : {0.15, 0.2, 0.25, 0.3})
      for (int lenticular : {0, 1}) {
        const auto t = seam::make_crossover(6 * r, 2 * r + 4, 4 * r + 3, r + 7,
                                            lenticular ? seam::Section::lenticular : seam::Section::elliptical,
                                            0.7 - overlap);
        char name[64];
        std::snprintf(name, sizeof name, "r%d_%g_%d", r, overlap, lenticular);
        cases.push_back({name, t.weft, t.warp});
      }
  return cases;
}

std::vector<Case> held_out() {
  std::vector<Case> cases;
  for (int r : {7, 11, 18})
    for (double overlap : {0.17, 0.27})
      for (int sections = 0; sections < 3; ++sections)
        for (double degrees : {90.0, 65.0})
          for (double tilt : {0.0, 9.0}) {
            Case c;
            c.weft.segments_along = 5 * r + 1;
            c.weft.segments_around = 2 * r + 3;
            c.weft.translate = {-5.0, 0.0, 0.0};
            c.weft.section = sections == 2 ? seam::Section::lenticular : seam::Section::elliptical;
            c.warp.half_width = 0.8;
            c.warp.half_height = 0.3;
            c.warp.crimp_amplitude = -0.25;
            c.warp.section = sections >= 1 ? seam::Section::lenticular : seam::Section::elliptical;
            c.warp.segments_along = 3 * r + 5;
            c.warp.segments_around = r + 9;
            const double t = degrees * M_PI / 180;
            c.warp.rotate_z = t;
            c.warp.rotate_x = tilt * M_PI / 180;
            c.warp.translate = {-5.0 * std::cos(t), -5.0 * std::sin(t) * std::cos(c.warp.rotate_x),
                                0.65 - overlap - 5.0 * std::sin(t) * std::sin(c.warp.rotate_x)};
            char name[64];
            std::snprintf(name, sizeof name, "h%d_%g_%d_%g_%g", r, overlap, sections, degrees, tilt);
            c.name = name;
            cases.push_back(c);
          }
  return cases;
}

std::string quoted(const std::string& s) {
  std::string out = "\"";
  for (char ch : s) out += ch == '"' || ch == '\\' ? std::string("\\") + ch : std::string(1, ch);
  return out + "\"";
}

void run(const char* set, const std::vector<Case>& cases, double snap_factor) {
  using K = seam::Exact;
  std::size_t faces = 0, b10 = 0, b20 = 0, failed = 0, verified = 0, remeshed = 0;
  double worst = 180;
  for (const Case& c : cases) {
    const auto a = seam::mesh_from_soup<K>(seam::make_tow(c.weft), "weft");
    const auto b = seam::mesh_from_soup<K>(seam::make_tow(c.warp), "warp");
    auto a2 = a, b2 = b;
    seam::PairOptions options;
    if (snap_factor != 1)
      options.embed.snap_tol = snap_factor * 0.1 * std::min(seam::mean_edge_length<K>(a), seam::mean_edge_length<K>(b));
    const auto t0 = std::chrono::steady_clock::now();
    try {
      const auto r = seam::pair<K>(a2, b2, options);
      const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
#ifdef SEAM_QUALITY_SWEEP_OLD_API  // (to measure an earlier version: no verification figures)
      const double tol = std::max(r.stats.snap_tol * (1 + 1e-9), 1e-12);
      const bool is_verified = false;
#else
      const double tol = r.stats.verify_tolerance;
      const bool is_verified = r.stats.verified;
#endif
      const auto report = seam::check_pair<K>(a, b, a2, b2, r.curves, tol);
      const std::size_t nf = report.new_faces_a + report.new_faces_b;
      const std::size_t n10 = report.below_10_a + report.below_10_b, n20 = report.below_20_a + report.below_20_b;
      faces += nf, b10 += n10, b20 += n20;
      verified += is_verified, remeshed += r.stats.improved;
      worst = std::min({worst, report.min_angle_deg_a, report.min_angle_deg_b});
      // The faces left below 10 degrees, with the cause the quality stage gives for each.
      std::string below_10_causes;
      for (const auto& sf : r.stats.improve.shortfalls)
        if (sf.min_angle_deg < 10)
          below_10_causes += std::string(below_10_causes.empty() ? "" : ", ") + "\"" + seam::shortfall_cause_name(sf.cause) + "\"";
      std::printf("{\"set\": \"%s\", \"case\": \"%s\", \"ok\": %s, \"verified\": %s, \"improved\": %s, \"shortfalls\": %zu, \"below_10_causes\": [%s], \"new_faces\": %zu, "
                  "\"below_10\": %zu, \"below_20\": %zu, \"curves\": %zu, \"closed\": %zu, \"seconds\": %.2f, \"note\": %s}\n",
                  set, c.name.c_str(), report.ok() ? "true" : "false", is_verified ? "true" : "false",
                  r.stats.improved ? "true" : "false", r.stats.improve.shortfalls.size(), below_10_causes.c_str(), nf, n10, n20, r.stats.curves, r.stats.closed_curves, seconds,
                  quoted(r.stats.note).c_str());
    } catch (const std::exception& e) {
      ++failed;
      std::printf("{\"set\": \"%s\", \"case\": \"%s\", \"error\": %s}\n", set, c.name.c_str(), quoted(e.what()).c_str());
    }
    std::fflush(stdout);
  }
  std::printf("{\"set\": \"%s\", \"summary\": true, \"cases\": %zu, \"failed\": %zu, \"verified\": %zu, \"remeshed\": %zu, "
              "\"new_faces\": %zu, \"below_10\": %zu, \"below_20\": %zu, \"min_angle_deg\": %.2f}\n",
              set, cases.size(), failed, verified, remeshed, faces, b10, b20, worst);
}

}  // namespace

int main(int argc, char** argv) {
  std::string which = "all";
  double snap_factor = 1;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--snap-factor") && i + 1 < argc)
      snap_factor = std::atof(argv[++i]);
    else
      which = argv[i];
  }
  if (which == "sweep" || which == "all") run("sweep", sweep(), snap_factor);
  if (which == "held-out" || which == "all") run("held-out", held_out(), snap_factor);
  return 0;
}
