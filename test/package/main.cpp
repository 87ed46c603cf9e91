// Consumer of the installed seam package: embeds a short open curve into a generated tow.
// Returns 0 when every segment of the embedded curve is an edge of the output mesh.
#include <seam/embed.h>
#include <seam/generate.h>
#include <seam/io.h>

#include <exception>
#include <iostream>

int main() {
  try {
    using K = seam::Exact;
    seam::TowOptions tow;
    tow.segments_along = 20;
    tow.segments_around = 12;
    seam::Mesh<K> mesh = seam::mesh_from_soup<K>(seam::make_tow(tow), "tow");

    // Five points across the top of the tow, on the smooth surface (near, not on, the facets).
    std::vector<seam::Point3d> curve;
    for (int i = 0; i < 5; ++i) curve.push_back(seam::tow_surface_point(tow, 4.1 + 0.4 * i, 1.2 + 0.2 * i));
    const auto result = seam::embed<K>(mesh, seam::to_kernel<K>({curve}));

    if (result.curve_vertices.size() != 1 || result.curve_vertices[0].size() < 2) return 1;
    const auto& vs = result.curve_vertices[0];
    for (std::size_t i = 0; i + 1 < vs.size(); ++i)
      if (mesh.halfedge(vs[i], vs[i + 1]) == seam::Mesh<K>::null_halfedge()) return 1;
    std::cout << "consumer: " << result.stats.faces_crossed << " faces crossed, "
              << result.stats.crossing_points << " crossing points, " << mesh.number_of_faces() << " faces\n";
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "consumer: " << e.what() << "\n";
    return 1;
  }
}
