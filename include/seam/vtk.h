// seam: a ParaView file of a conforming pair: both meshes and the shared curves in one file.
//
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <seam/types.h>

#include <ostream>
#include <string>
#include <vector>

namespace seam {

/// Writes both meshes as triangles and the curves as polylines into one VTK unstructured grid:
/// legacy ASCII (.vtk) or XML (.vtu), by extension. Cell fields: `tow` (0 for A, 1 for B, -1 for
/// a curve), `source_face` (the input face a triangle came from; -1 for curves and for faces
/// remeshed next to the curves, which have no single input face), `new` (1 for
/// triangles created by seam) and `min_angle` (degrees; 0 for curves). Written atomically.
/// Throws InvalidInput for another extension, IOError when the file cannot be written.
template <class K>
void write_pair_vtk(const std::string& path, const Mesh<K>& a, const Mesh<K>& b, const std::vector<Polyline<K>>& curves);

/// The same into a stream; `format` is "vtk" or "vtu" (with or without the dot, any case).
template <class K>
void write_pair_vtk(std::ostream& out, const std::string& format, const Mesh<K>& a, const Mesh<K>& b,
                    const std::vector<Polyline<K>>& curves);

/// The lower-case extension of `path`, ".vtk" or ".vtu"; throws InvalidInput naming `path` for
/// any other. Touches no file.
std::string vtk_format(const std::string& path);

}  // namespace seam
