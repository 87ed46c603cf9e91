// make_examples: writes the example input files of seam from the generated tow geometry.
//
//   examples/tow.off               an elliptical crimped tow (seam::make_tow, 60 x 24 segments)
//   examples/ring.polylines.txt    a tilted ring curve on its smooth surface (1999 samples)
//   examples/plain_weave/          a 2 x 2 plain weave unit cell (seam::make_weave, defaults):
//                                  weft0, weft1, warp0, warp1 .off, interpenetrating by 0.03 at
//                                  each of the four crossings
//   examples/weave_4x4/            a 4 x 4 plain weave (4 warps, 4 wefts; 8 segments per crossing,
//                                  12 around): sixteen crossings, for the mesh chain's tests
//
// Usage (from the repository root):  make_examples [output-directory]   (default: examples)
//
// Not part of the CMake build; build it by hand from the repository root, e.g.
//   g++ -std=c++17 -O2 -Iinclude tools/make_examples.cpp src/generate.cpp src/io.cpp -o /tmp/make_examples -lgmp -lmpfr
//
// SPDX-License-Identifier: GPL-3.0-or-later

#include <seam/generate.h>

#include <exception>
#include <iostream>
#include <string>
#include <vector>

int main(int argc, char** argv) {
  if (argc > 2) {
    std::cerr << "usage: " << argv[0] << " [output-directory]\n";
    return 2;
  }
  const std::string dir = argc == 2 ? argv[1] : "examples";
  try {
    seam::TowOptions tow;  // defaults: length 10, semi-axes 1 x 0.35, crimp 0.3 over 10
    tow.section = seam::Section::elliptical;
    tow.segments_along = 60;
    tow.segments_around = 24;
    const seam::TriangleSoup mesh = seam::make_tow(tow);

    // Stations are 10/60 apart: s = 4.9 +- 0.4 is on none of them, so the curve crosses faces.
    // 1999 samples (prime, coprime with 24): apart from the first one (phi = 0), no sample is at
    // the angle of a ring of vertices, where it would lie on (near s = 5, where the path is
    // straight, exactly on, up to rounding) a mesh edge along the path.
    const double s_center = 4.9, tilt = 0.4;
    const int samples = 1999;
    const std::vector<std::vector<seam::Point3d>> curves = {
        seam::make_ring_curve(tow, s_center, tilt, samples)};

    const std::string mesh_path = dir + "/tow.off";
    const std::string curve_path = dir + "/ring.polylines.txt";
    seam::write_triangle_mesh(mesh, mesh_path);  // 17 significant digits, atomic
    seam::write_polylines(curves, curve_path);
    std::cout << mesh_path << ": " << mesh.points.size() << " vertices, " << mesh.triangles.size()
              << " triangles\n"
              << curve_path << ": 1 closed polyline, " << curves[0].size() << " points\n";

    for (const auto& t : seam::make_weave(seam::WeaveOptions{})) {
      const std::string path = dir + "/plain_weave/" + t.name + ".off";
      const seam::TriangleSoup tow_mesh = seam::make_tow(t.options);
      seam::write_triangle_mesh(tow_mesh, path);
      std::cout << path << ": " << tow_mesh.points.size() << " vertices, " << tow_mesh.triangles.size() << " triangles\n";
    }
    seam::WeaveOptions four;
    four.warps = four.wefts = 4;
    four.segments_per_crossing = 8;
    four.segments_around = 12;
    for (const auto& t : seam::make_weave(four)) {
      const std::string path = dir + "/weave_4x4/" + t.name + ".off";
      const seam::TriangleSoup tow_mesh = seam::make_tow(t.options);
      seam::write_triangle_mesh(tow_mesh, path);
      std::cout << path << ": " << tow_mesh.points.size() << " vertices, " << tow_mesh.triangles.size() << " triangles\n";
    }
  } catch (const std::exception& e) {
    std::cerr << "make_examples: " << e.what() << '\n';
    return 1;
  }
  return 0;
}
