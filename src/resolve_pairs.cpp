// seam: a whole textile resolved pair by pair (seam/resolve.h, resolve_pairs).
// SPDX-License-Identifier: GPL-3.0-or-later

#include <seam/errors.h>
#include <seam/resolve.h>

namespace seam {

template <class K>
std::vector<ResolveStats> resolve_pairs(std::vector<Mesh<K>>& tows,
                                        const std::vector<std::pair<std::size_t, std::size_t>>& pairs,
                                        const std::vector<std::string>& names, Keeper keeper) {
  if (names.size() != tows.size()) throw InvalidInput("resolve_pairs: one name per tow is needed");
  for (const auto& [a, b] : pairs)
    if (a >= tows.size() || b >= tows.size() || a == b)
      throw InvalidInput("resolve_pairs: a pair names no two distinct tows");
  std::vector<Mesh<K>> work = tows;  // the inputs stay as they are until every pair is done and checked
  const auto pair_name = [&](std::size_t a, std::size_t b) { return "tows " + names[a] + " and " + names[b]; };
  std::vector<ResolveStats> stats;
  for (const auto& [a, b] : pairs) {
    ResolveOptions options;
    options.keeper = keeper;
    options.name_a = names[a];
    options.name_b = names[b];
    try {
      stats.push_back(resolve<K>(work[a], work[b], options));
    } catch (const InvalidInput& e) {
      throw InvalidInput(pair_name(a, b) + ": " + e.what());
    }
  }
  for (const auto& [a, b] : pairs) {
    const auto check = check_resolved<K>(work[a], work[b]);
    if (!check.ok()) throw InternalError(pair_name(a, b) + " failed the check of a resolved pair: " + check.problems.front());
  }
  tows.swap(work);
  return stats;
}

#define SEAM_INSTANTIATE(K)                                                                                      \
  template std::vector<ResolveStats> resolve_pairs<K>(std::vector<Mesh<K>>&,                                      \
                                                      const std::vector<std::pair<std::size_t, std::size_t>>&, \
                                                      const std::vector<std::string>&, Keeper);
SEAM_INSTANTIATE(Exact)
SEAM_INSTANTIATE(Filtered)
SEAM_INSTANTIATE(Float)
#undef SEAM_INSTANTIATE

}  // namespace seam
