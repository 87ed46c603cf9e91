// seam internal: seam::embed with curve points whose location in the mesh is known in advance.
//
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <seam/embed.h>
#include <seam/internal/retriangulate.h>
#include <seam/internal/surface_point.h>

namespace seam::internal {

/// seam::embed, except that curve nodes found in `known` (may be null) are taken as lying where
/// it says instead of being located (see KnownSites). Ignored when the mesh has garbage to collect
/// (its indices would change) or when snapping (options.snap_tol) moves a vertex.
/// `keep_away` (may be null): Steiner points of the re-triangulation stay that far from its points.
template <class K>
EmbedResult<K> embed_with_known_sites(Mesh<K>& mesh, const std::vector<Polyline<K>>& curves,
                                      const EmbedOptions& options, const KnownSites<K>* known,
                                      KeepAway* keep_away = nullptr);

}  // namespace seam::internal
