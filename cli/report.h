// seam CLI and Python bindings: the JSON reports (`--report`), built in one place so that the
// command line and `import seam` give the same keys. The file names a command read and wrote are
// not part of these: each command adds its own "files" entries.
//
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <seam/check.h>
#include <seam/embed.h>
#include <seam/improve.h>
#include <seam/io.h>
#include <seam/pair.h>
#include <seam/resolve.h>
#include <seam/textile.h>

#include <nlohmann/json.hpp>

#include <cstddef>
#include <string>
#include <vector>

namespace seam_cli {

/// `seam check`'s default tolerance: 1e-9 x the diagonal of the bounding box of both inputs.
double default_check_tolerance(const seam::TriangleSoup& a, const seam::TriangleSoup& b);

/// The JSON of an embedding's statistics (the keys documented in the README).
nlohmann::json stats_json(const seam::EmbedStats& s);

/// The JSON of the quality stage's report (the keys documented in docs/algorithm.md): counts of edits
/// and refusals, the band's angles before and after, and each face left below the bound with its
/// cause (mesh names from `mesh_names`).
nlohmann::json improve_json(const seam::ImproveStats& s, bool done, const std::vector<std::string>& mesh_names);

/// One curve of a pair, for the report: its vertices (a closed curve's repeat not counted).
struct CurveSummary {
  std::size_t vertices = 0;
  bool closed = false;
};

template <class K> std::vector<CurveSummary> curve_summaries(const std::vector<seam::Polyline<K>>& curves) {
  std::vector<CurveSummary> list;
  for (const auto& c : curves) list.push_back({seam::is_closed(c) ? c.size() - 1 : c.size(), seam::is_closed(c)});
  return list;
}

/// `seam pair --report`, without "files".
nlohmann::json pair_report_json(seam::KernelKind kernel, const seam::PairStats& st, const seam::EmbedStats& a,
                                const seam::EmbedStats& b, const std::vector<CurveSummary>& curves);

/// `seam check --report`, without "files" and "seconds".
nlohmann::json check_report_json(const seam::PairCheckReport& r, const std::string& kernel);

/// `seam resolve --report`, without "files".
nlohmann::json resolve_report_json(seam::KernelKind kernel, const seam::ResolveStats& st,
                                   const seam::ResolvedCheckReport& check);

/// `seam textile --report`, without the file names ("file" and "out" of each tow, "polylines"
/// of each pair): `pairs` and `tows` by index, `names` the tows' names.
nlohmann::json textile_report_json(seam::KernelKind kernel, const seam::TextileStats& st,
                                   const std::vector<seam::TextilePairStats>& pairs,
                                   const std::vector<seam::EmbedStats>& tows, const std::vector<std::string>& names);

template <class K>
nlohmann::json textile_report_json(const seam::TextileResult<K>& result, const std::vector<std::string>& names) {
  std::vector<seam::TextilePairStats> pairs;
  for (const auto& p : result.pairs) pairs.push_back(p.stats);
  return textile_report_json(seam::kernel_traits<K>::kind, result.stats, pairs, result.tows, names);
}

}  // namespace seam_cli
