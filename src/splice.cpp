// seam, pipeline step 6: splicing. See seam/internal/splice.h.
// SPDX-License-Identifier: GPL-3.0-or-later
#include <seam/internal/splice.h>

#include <cstdint>
#include <sstream>

namespace seam::internal {

template <class K>
Mesh<K> splice_patches(const Mesh<K>& mesh, const std::vector<typename K::Point_3>& new_points,
                       const std::map<typename MeshTypes<K>::F, FacePatch<K>>& patches) {
  using V = typename MeshTypes<K>::V;
  Mesh<K> out;
  std::size_t steiner_count = 0;
  for (const auto& [f, patch] : patches) steiner_count += patch.steiner_points.size();
  std::size_t new_faces = 0;
  for (const auto& [f, patch] : patches) new_faces += patch.triangles.size();
  const std::size_t nv = mesh.number_of_vertices() + new_points.size() + steiner_count;
  const std::size_t nf = mesh.number_of_faces() - patches.size() + new_faces;
  out.reserve(nv, 3 * nf / 2 + 3, nf);

  for (V v : mesh.vertices()) out.add_vertex(mesh.point(v));
  for (const auto& p : new_points) out.add_vertex(p);
  auto source = out.template add_property_map<typename Mesh<K>::Face_index, std::uint32_t>(source_face_property, 0).first;
  auto is_new = out.template add_property_map<typename Mesh<K>::Face_index, bool>(new_face_property, false).first;

  auto fail = [&](std::size_t f) {
    std::ostringstream msg;
    msg << "splice: a new face from input face " << f << " does not fit into the mesh";
    throw InternalError(msg.str());
  };
  auto it = patches.begin();
  for (auto f : mesh.faces()) {
    if (it != patches.end() && it->first == f) {
      const FacePatch<K>& patch = it->second;
      const std::size_t base = out.number_of_vertices();
      for (const auto& p : patch.steiner_points) out.add_vertex(p);
      for (const auto& tri : patch.triangles) {
        V vs[3];
        for (int i = 0; i < 3; ++i)
          vs[i] = V(static_cast<typename V::size_type>(tri[i] >= 0 ? std::size_t(tri[i]) : base + std::size_t(-tri[i] - 1)));
        auto nf2 = out.add_face(vs[0], vs[1], vs[2]);
        if (nf2 == Mesh<K>::null_face()) fail(std::size_t(f));
        source[nf2] = std::uint32_t(std::size_t(f));
        is_new[nf2] = true;
      }
      ++it;
      continue;
    }
    V vs[3];
    int i = 0;
    for (V v : CGAL::vertices_around_face(mesh.halfedge(f), mesh)) vs[i++] = v;
    auto nf2 = out.add_face(vs[0], vs[1], vs[2]);
    if (nf2 == Mesh<K>::null_face()) fail(std::size_t(f));
    source[nf2] = std::uint32_t(std::size_t(f));
  }
  return out;
}

template Mesh<Exact> splice_patches<Exact>(const Mesh<Exact>&, const std::vector<Exact::Point_3>&,
                                           const std::map<MeshTypes<Exact>::F, FacePatch<Exact>>&);
template Mesh<Filtered> splice_patches<Filtered>(const Mesh<Filtered>&, const std::vector<Filtered::Point_3>&,
                                                 const std::map<MeshTypes<Filtered>::F, FacePatch<Filtered>>&);
template Mesh<Float> splice_patches<Float>(const Mesh<Float>&, const std::vector<Float::Point_3>&,
                                           const std::map<MeshTypes<Float>::F, FacePatch<Float>>&);

}  // namespace seam::internal
