// The quality stage's band (seam/improve.h): its border is never fixed by a distance from the
// curves. A face may join it however far away it lies, unless it is shared by two meshes (a flat
// contact) or frozen; only those, the curves and a mesh's own border hold a face below the bound.
#include <catch2/catch.hpp>

#include <seam/internal/improve_state.h>
#include <seam/internal/local_edits.h>

#include <array>
#include <vector>

namespace {

using K = seam::Exact;
using M = seam::Mesh<K>;
using P = K::Point_3;
using V = M::Vertex_index;
using F = M::Face_index;

}  // namespace

TEST_CASE("improve: a face far from the curves may join the band; shared and frozen faces may not", "[improve]") {
  // A strip of 40 x 2 unit squares in the plane z = 0, each cut in two; the curve is the strip's
  // left end (x = 0, y from 0 to 2), an open border of the mesh.
  const int columns = 40;
  M mesh;
  std::vector<std::array<V, 3>> rows(std::size_t(columns) + 1);
  for (int i = 0; i <= columns; ++i)
    for (int j = 0; j < 3; ++j) rows[std::size_t(i)][std::size_t(j)] = mesh.add_vertex(P(i, j, 0));
  std::vector<F> far_faces;
  for (int i = 0; i < columns; ++i)
    for (int j = 0; j < 2; ++j) {
      const V a = rows[std::size_t(i)][std::size_t(j)], b = rows[std::size_t(i) + 1][std::size_t(j)];
      const V c = rows[std::size_t(i) + 1][std::size_t(j) + 1], d = rows[std::size_t(i)][std::size_t(j) + 1];
      const F f1 = mesh.add_face(a, b, c), f2 = mesh.add_face(a, c, d);
      REQUIRE(f1 != M::null_face());
      REQUIRE(f2 != M::null_face());
      if (i >= columns - 3) far_faces.push_back(f1), far_faces.push_back(f2);
    }
  // Two of the far faces (30 or more mean edge lengths from the curve) are frozen and shared.
  auto frozen = mesh.add_property_map<F, bool>(seam::internal::frozen_face_property, false).first;
  auto shared = mesh.add_property_map<F, bool>(seam::internal::shared_face_property, false).first;
  frozen[far_faces[0]] = true;
  shared[far_faces[1]] = true;
  const M input = mesh;

  seam::internal::SharedCurves<K> curves;
  curves.curves = {{P(0, 0, 0), P(0, 1, 0), P(0, 2, 0)}};
  curves.vertices = {{{rows[0][0], rows[0][1], rows[0][2]}}};
  std::vector<seam::internal::ImproveMesh<K>> meshes{{&mesh, &input, nullptr}};
  seam::ImproveOptions options;
  options.tolerance = 0.01;
  seam::internal::ImproveState<K> s;
  seam::internal::init_state<K>(s, meshes, curves, options);

  // The band at the start: the four faces touching the curve (the first column) only.
  std::size_t in_band = 0;
  for (F f : mesh.faces()) in_band += s.face_in_band(0, f) ? 1 : 0;
  CHECK(in_band == 4);
  REQUIRE(s.mean_edge < 2);
  for (std::size_t k = 2; k < far_faces.size(); ++k) {
    CHECK_FALSE(s.face_in_band(0, far_faces[k]));
    CHECK(s.may_join_band(0, far_faces[k]));
  }
  // The acceptance predicate's index holds the far faces too (a face the band may reach must be
  // found by the crossing tests).
  for (F f : far_faces) {
    bool found = false;
    for (const auto& e : s.grid.query(s.face_box(0, f))) found = found || e.face == std::uint32_t(std::size_t(f));
    CHECK(found);
  }
  CHECK_FALSE(s.may_join_band(0, far_faces[0]));  // frozen
  CHECK_FALSE(s.may_join_band(0, far_faces[1]));  // shared
  for (F f : mesh.faces())
    if (s.face_in_band(0, f)) CHECK_FALSE(s.may_join_band(0, f));  // in it already
  seam::internal::drop_state_properties<K>(s);
}
