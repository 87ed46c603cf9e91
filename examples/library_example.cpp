// Embeds a ring into a generated tow with the exact kernel and checks the result.
#include <seam/embed.h>
#include <seam/generate.h>
#include <seam/io.h>

#include <iostream>

int main() {
  using K = seam::Exact;
  seam::TowOptions tow;  // elliptical tow, length 10, crimped
  seam::Mesh<K> mesh = seam::mesh_from_soup<K>(seam::make_tow(tow), "tow");
  auto curves = seam::to_kernel<K>({seam::make_ring_curve(tow, 4.9, 0.4, 1999)});

  seam::EmbedOptions options;
  options.min_angle_deg = 20;
  seam::EmbedResult<K> result = seam::embed<K>(mesh, curves, options);

  for (const auto& vs : result.curve_vertices)  // every curve segment is a mesh edge
    for (std::size_t i = 0; i + 1 < vs.size(); ++i)
      if (mesh.halfedge(vs[i], vs[i + 1]) == seam::Mesh<K>::null_halfedge()) return 1;

  const seam::EmbedStats& s = result.stats;
  std::cout << "faces crossed " << s.faces_crossed << ", crossing points " << s.crossing_points
            << ", faces added " << s.faces_added << "\n";
  return 0;
}
