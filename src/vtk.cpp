// seam: the ParaView file of a pair. See seam/vtk.h.
// SPDX-License-Identifier: GPL-3.0-or-later
#include <seam/io.h>
#include <seam/kernels.h>
#include <seam/quality.h>
#include <seam/vtk.h>

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <filesystem>
#include <iomanip>
#include <locale>
#include <ostream>

namespace seam {

namespace {

struct Grid {
  std::vector<Point3d> points;
  std::vector<std::vector<std::size_t>> cells;  // 3 ids: triangle; more: polyline
  std::vector<int> tow, source, is_new;
  std::vector<double> min_angle;
};

template <class K> void add_mesh(Grid& g, const Mesh<K>& m, int tow) {
  const std::size_t base = g.points.size();
  for (auto v : m.vertices()) {
    const auto p = to_filtered(m.point(v));
    g.points.push_back({p.x(), p.y(), p.z()});
  }
  const auto [source, has_source] = m.template property_map<typename Mesh<K>::Face_index, std::uint32_t>(source_face_property);
  const auto [fresh, has_new] = m.template property_map<typename Mesh<K>::Face_index, bool>(new_face_property);
  for (auto f : m.faces()) {
    std::vector<std::size_t> ids;
    for (auto v : CGAL::vertices_around_face(m.halfedge(f), m)) ids.push_back(base + std::size_t(v));
    g.cells.push_back(ids);
    g.tow.push_back(tow);
    g.source.push_back(has_source ? int(source[f]) : int(std::size_t(f)));
    g.is_new.push_back(has_new && fresh[f] ? 1 : 0);
    auto h = m.halfedge(f);
    g.min_angle.push_back(min_angle_deg(m.point(m.source(h)), m.point(m.target(h)), m.point(m.target(m.next(h)))));
  }
}

void write_legacy(std::ostream& out, const Grid& g) {
  out << "# vtk DataFile Version 3.0\nseam pair\nASCII\nDATASET UNSTRUCTURED_GRID\n";
  out << "POINTS " << g.points.size() << " double\n";
  for (const auto& p : g.points) out << p[0] << ' ' << p[1] << ' ' << p[2] << '\n';
  std::size_t size = 0;
  for (const auto& c : g.cells) size += c.size() + 1;
  out << "CELLS " << g.cells.size() << ' ' << size << '\n';
  for (const auto& c : g.cells) {
    out << c.size();
    for (auto id : c) out << ' ' << id;
    out << '\n';
  }
  out << "CELL_TYPES " << g.cells.size() << '\n';
  for (const auto& c : g.cells) out << (c.size() == 3 && g.tow[&c - g.cells.data()] >= 0 ? 5 : 4) << '\n';
  out << "CELL_DATA " << g.cells.size() << '\n';
  auto ints = [&](const char* name, const std::vector<int>& v) {
    out << "SCALARS " << name << " int 1\nLOOKUP_TABLE default\n";
    for (int x : v) out << x << '\n';
  };
  ints("tow", g.tow);
  ints("source_face", g.source);
  ints("new", g.is_new);
  out << "SCALARS min_angle double 1\nLOOKUP_TABLE default\n";
  for (double x : g.min_angle) out << x << '\n';
}

void write_xml(std::ostream& out, const Grid& g) {
  out << "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
      << "<UnstructuredGrid>\n<Piece NumberOfPoints=\"" << g.points.size() << "\" NumberOfCells=\"" << g.cells.size()
      << "\">\n<Points>\n<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n";
  for (const auto& p : g.points) out << p[0] << ' ' << p[1] << ' ' << p[2] << '\n';
  out << "</DataArray>\n</Points>\n<Cells>\n<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n";
  for (const auto& c : g.cells) {
    for (auto id : c) out << id << ' ';
    out << '\n';
  }
  out << "</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n";
  std::size_t offset = 0;
  for (const auto& c : g.cells) out << (offset += c.size()) << '\n';
  out << "</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n";
  for (std::size_t i = 0; i < g.cells.size(); ++i) out << (g.tow[i] >= 0 ? 5 : 4) << '\n';
  out << "</DataArray>\n</Cells>\n<CellData Scalars=\"tow\">\n";
  auto ints = [&](const char* name, const std::vector<int>& v) {
    out << "<DataArray type=\"Int32\" Name=\"" << name << "\" format=\"ascii\">\n";
    for (int x : v) out << x << '\n';
    out << "</DataArray>\n";
  };
  ints("tow", g.tow);
  ints("source_face", g.source);
  ints("new", g.is_new);
  out << "<DataArray type=\"Float64\" Name=\"min_angle\" format=\"ascii\">\n";
  for (double x : g.min_angle) out << x << '\n';
  out << "</DataArray>\n</CellData>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n";
}

}  // namespace

std::string vtk_format(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return char(std::tolower(c)); });
  if (ext != ".vtk" && ext != ".vtu")
    throw InvalidInput(path + ": unknown VTK format '" + ext + "' (expected .vtk or .vtu)");
  return ext;
}

template <class K>
void write_pair_vtk(std::ostream& out, const std::string& format, const Mesh<K>& a, const Mesh<K>& b,
                    const std::vector<Polyline<K>>& curves) {
  const std::string ext = vtk_format("x" + (format.empty() || format[0] == '.' ? format : "." + format));
  Grid g;
  add_mesh<K>(g, a, 0);
  add_mesh<K>(g, b, 1);
  for (const auto& c : curves) {
    std::vector<std::size_t> ids;
    for (const auto& p : c) {
      const auto q = to_filtered(p);
      ids.push_back(g.points.size());
      g.points.push_back({q.x(), q.y(), q.z()});
    }
    if (ids.size() < 2) continue;
    // A polyline cell: mark it with tow -1 (it is written as VTK_POLY_LINE, type 4).
    g.cells.push_back(ids);
    g.tow.push_back(-1);
    g.source.push_back(-1);
    g.is_new.push_back(0);
    g.min_angle.push_back(0);
  }
  out.imbue(std::locale::classic());
  out << std::setprecision(17);
  if (ext == ".vtk")
    write_legacy(out, g);
  else
    write_xml(out, g);
}

template <class K>
void write_pair_vtk(const std::string& path, const Mesh<K>& a, const Mesh<K>& b, const std::vector<Polyline<K>>& curves) {
  const std::string ext = vtk_format(path);
  write_file_atomically(path, [&](std::ostream& out) { write_pair_vtk<K>(out, ext, a, b, curves); });
}

#define SEAM_INSTANTIATE_VTK(K)                                                                                     \
  template void write_pair_vtk<K>(const std::string&, const Mesh<K>&, const Mesh<K>&, const std::vector<Polyline<K>>&); \
  template void write_pair_vtk<K>(std::ostream&, const std::string&, const Mesh<K>&, const Mesh<K>&,               \
                                  const std::vector<Polyline<K>>&);
SEAM_INSTANTIATE_VTK(Exact)
SEAM_INSTANTIATE_VTK(Filtered)
SEAM_INSTANTIATE_VTK(Float)
#undef SEAM_INSTANTIATE_VTK

}  // namespace seam
