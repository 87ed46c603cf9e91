// seam internal: one call of TetGen 1.5 (libtet). See include/seam/internal/tetgen_call.h.
// SPDX-License-Identifier: GPL-3.0-or-later
#include <seam/internal/tetgen_call.h>

#include <seam/errors.h>

#define TETLIBRARY
#include <tetgen.h>

#include <limits>
#include <new>
#include <vector>

namespace seam::internal {

namespace {

std::string tetgen_failure(int code) {
  switch (code) {
    case 1: return "TetGen ran out of memory";
    case 2: return "TetGen reported an internal error";
    case 3: return "TetGen found a self-intersection in the combined surfaces (faces closer than its tolerance)";
    case 4: return "TetGen found a very small input feature (below its tolerance -T)";
    case 5: return "TetGen found two very close input facets";
    case 10: return "TetGen found an input error";
    default: return "TetGen failed with code " + std::to_string(code);
  }
}

/// Fills TetGen's input (its arrays are freed by ~tetgenio with delete[]).
void fill_input(const TetgenInput& input, tetgenio& in) {
  if (input.points.size() > static_cast<std::size_t>(std::numeric_limits<int>::max() / 3) ||
      input.triangles.size() > static_cast<std::size_t>(std::numeric_limits<int>::max()))
    throw InternalError("the model is too large for TetGen (int indices)");
  in.firstnumber = 0;
  in.numberofpoints = static_cast<int>(input.points.size());
  in.pointlist = new REAL[input.points.size() * 3];
  for (std::size_t i = 0; i < input.points.size(); ++i)
    for (int k = 0; k < 3; ++k) in.pointlist[3 * i + k] = input.points[i][k];
  in.numberoffacets = static_cast<int>(input.triangles.size());
  in.facetlist = new tetgenio::facet[input.triangles.size()];
  for (std::size_t f = 0; f < input.triangles.size(); ++f) {
    tetgenio::facet& facet = in.facetlist[f];
    tetgenio::init(&facet);
    facet.numberofpolygons = 1;
    facet.polygonlist = new tetgenio::polygon[1];
    tetgenio::init(&facet.polygonlist[0]);
    facet.polygonlist[0].numberofvertices = 3;
    facet.polygonlist[0].vertexlist = new int[3];
    for (int k = 0; k < 3; ++k) facet.polygonlist[0].vertexlist[k] = static_cast<int>(input.triangles[f][k]);
  }
  in.numberofregions = static_cast<int>(input.seeds.size());
  if (!input.seeds.empty()) {
    in.regionlist = new REAL[input.seeds.size() * 5];
    for (std::size_t r = 0; r < input.seeds.size(); ++r) {
      for (int k = 0; k < 3; ++k) in.regionlist[5 * r + k] = input.seeds[r][k];
      in.regionlist[5 * r + 3] = input.seed_attributes[r];
      in.regionlist[5 * r + 4] = -1.0;  // no volume constraint of its own
    }
  }
}

TetgenOutput read_output(const tetgenio& out) {
  TetgenOutput result;
  if (out.numberofcorners != 4) throw InternalError("TetGen returned elements of " + std::to_string(out.numberofcorners) + " corners");
  const int first = out.firstnumber;
  result.points.resize(static_cast<std::size_t>(out.numberofpoints));
  for (std::size_t i = 0; i < result.points.size(); ++i)
    for (int k = 0; k < 3; ++k) result.points[i][k] = out.pointlist[3 * i + k];
  const auto n_tets = static_cast<std::size_t>(out.numberoftetrahedra);
  result.tets.resize(n_tets);
  result.attribute.assign(n_tets, 0);
  for (std::size_t t = 0; t < n_tets; ++t) {
    for (int k = 0; k < 4; ++k) {
      const int v = out.tetrahedronlist[4 * t + k] - first;
      if (v < 0 || v >= out.numberofpoints) throw InternalError("TetGen returned a tet corner out of range");
      result.tets[t][k] = static_cast<std::size_t>(v);
    }
    if (out.numberoftetrahedronattributes > 0)
      result.attribute[t] = static_cast<int>(out.tetrahedronattributelist[t * out.numberoftetrahedronattributes]);
  }
  return result;
}

}  // namespace

TetgenOutput run_tetgen(const TetgenInput& input) {
  tetgenio in, out;
  fill_input(input, in);
  std::vector<char> switches(input.switches.begin(), input.switches.end());
  switches.push_back('\0');
  try {
    tetrahedralize(switches.data(), &in, &out);
  } catch (int code) {
    if (code == 1) throw std::bad_alloc();
    throw InternalError(tetgen_failure(code));
  }
  return read_output(out);
}

}  // namespace seam::internal
