// seam: writing a tetrahedral model for finite-element tools (VTU, Abaqus .inp, Gmsh .msh 4.1).
// See include/seam/volume_mesh.h.
// SPDX-License-Identifier: GPL-3.0-or-later
#include <seam/volume_mesh.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <locale>
#include <ostream>
#include <set>

namespace seam {

namespace {

/// Region names as Abaqus and Gmsh accept them: letters, digits and '_', starting with a letter,
/// at most 64 characters, unique (a suffix _2, _3, ... where two would be equal).
std::vector<std::string> set_names(const TetMesh& mesh) {
  std::vector<std::string> names;
  std::set<std::string> taken;
  for (std::size_t r = 0; r < mesh.region_names.size(); ++r) {
    std::string name;
    for (const char c : mesh.region_names[r]) name += std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
    if (name.empty() || !std::isalpha(static_cast<unsigned char>(name[0]))) name = "R_" + name;
    if (name.size() > 64) name.resize(64);
    std::string unique = name;
    for (int k = 2; taken.count(unique); ++k) unique = name + "_" + std::to_string(k);
    taken.insert(unique);
    names.push_back(unique);
  }
  return names;
}

void write_vtu(const TetMesh& mesh, std::ostream& out) {
  out << "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
      << "<UnstructuredGrid>\n<Piece NumberOfPoints=\"" << mesh.points.size() << "\" NumberOfCells=\"" << mesh.tets.size()
      << "\">\n<Points>\n<DataArray type=\"Float64\" NumberOfComponents=\"3\" format=\"ascii\">\n";
  for (const auto& p : mesh.points) out << p[0] << ' ' << p[1] << ' ' << p[2] << '\n';
  out << "</DataArray>\n</Points>\n<Cells>\n<DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n";
  for (const auto& t : mesh.tets) out << t[0] << ' ' << t[1] << ' ' << t[2] << ' ' << t[3] << '\n';
  out << "</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n";
  for (std::size_t i = 0; i < mesh.tets.size(); ++i) out << 4 * (i + 1) << '\n';
  out << "</DataArray>\n<DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n";
  for (std::size_t i = 0; i < mesh.tets.size(); ++i) out << "10\n";
  out << "</DataArray>\n</Cells>\n<CellData Scalars=\"region\">\n<DataArray type=\"Int32\" Name=\"region\" format=\"ascii\">\n";
  for (const int r : mesh.region) out << r << '\n';
  out << "</DataArray>\n</CellData>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n";
}

/// Abaqus's C3D4 face that holds the three corners of `face` (S1: 1-2-3, S2: 1-4-2, S3: 2-4-3,
/// S4: 3-4-1), named by the corner it leaves out.
int c3d4_face(const std::array<std::size_t, 4>& tet, const std::array<std::size_t, 3>& face) {
  for (int k = 0; k < 4; ++k)
    if (std::find(face.begin(), face.end(), tet[k]) == face.end()) return k == 3 ? 1 : k == 2 ? 2 : k == 0 ? 3 : 4;
  return 0;
}

void write_inp(const TetMesh& mesh, const std::vector<ContactPatch>& contacts, std::ostream& out) {
  const auto names = set_names(mesh);
  out << "*HEADING\nseam mesh: " << mesh.tets.size() << " C3D4 elements in " << names.size()
      << " element sets (the matrix and one per tow)\n*NODE\n";
  for (std::size_t i = 0; i < mesh.points.size(); ++i)
    out << i + 1 << ", " << mesh.points[i][0] << ", " << mesh.points[i][1] << ", " << mesh.points[i][2] << '\n';
  // Elements numbered region by region (each region's block is its element set).
  std::vector<std::size_t> element(mesh.tets.size());
  std::size_t next = 1;
  for (std::size_t r = 0; r < names.size(); ++r) {
    out << "*ELEMENT, TYPE=C3D4, ELSET=" << names[r] << '\n';
    for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
      if (mesh.region[t] != static_cast<int>(r)) continue;
      element[t] = next++;
      const auto& c = mesh.tets[t];
      out << element[t] << ", " << c[0] + 1 << ", " << c[1] + 1 << ", " << c[2] + 1 << ", " << c[3] + 1 << '\n';
    }
  }
  // A contact patch: an element-based surface on tow a's side, one element set per face number.
  for (const auto& patch : contacts) {
    const std::string name = "CONTACT_" + names.at(patch.a) + "_" + names.at(patch.b);
    std::vector<std::size_t> by_face[5];
    for (std::size_t i = 0; i < patch.faces.size(); ++i)
      by_face[c3d4_face(mesh.tets[patch.tet_a[i]], patch.faces[i])].push_back(element[patch.tet_a[i]]);
    for (int s = 1; s <= 4; ++s) {
      if (by_face[s].empty()) continue;
      out << "*ELSET, ELSET=" << name << "_S" << s << '\n';
      for (std::size_t i = 0; i < by_face[s].size(); ++i)
        out << by_face[s][i] << ((i % 16 == 15 || i + 1 == by_face[s].size()) ? "\n" : ", ");
    }
    out << "*SURFACE, TYPE=ELEMENT, NAME=" << name << '\n';
    for (int s = 1; s <= 4; ++s)
      if (!by_face[s].empty()) out << name << "_S" << s << ", S" << s << '\n';
  }
}

void write_msh(const TetMesh& mesh, std::ostream& out) {
  const auto names = set_names(mesh);
  const std::size_t regions = names.size();
  out << "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$PhysicalNames\n" << regions << '\n';
  for (std::size_t r = 0; r < regions; ++r) out << "3 " << r + 1 << " \"" << names[r] << "\"\n";
  out << "$EndPhysicalNames\n";
  // One volume entity per region (tag r + 1, physical group r + 1) with its bounding box.
  std::vector<std::array<double, 6>> bounds(regions, {HUGE_VAL, HUGE_VAL, HUGE_VAL, -HUGE_VAL, -HUGE_VAL, -HUGE_VAL});
  std::vector<std::size_t> count(regions, 0);
  for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
    auto& b = bounds[static_cast<std::size_t>(mesh.region[t])];
    ++count[static_cast<std::size_t>(mesh.region[t])];
    for (const std::size_t v : mesh.tets[t])
      for (int k = 0; k < 3; ++k) {
        b[k] = std::min(b[k], mesh.points[v][k]);
        b[k + 3] = std::max(b[k + 3], mesh.points[v][k]);
      }
  }
  out << "$Entities\n0 0 0 " << regions << '\n';
  for (std::size_t r = 0; r < regions; ++r) {
    out << r + 1;
    for (const double x : bounds[r]) out << ' ' << (count[r] ? x : 0.0);
    out << " 1 " << r + 1 << " 0\n";
  }
  out << "$EndEntities\n$Nodes\n1 " << mesh.points.size() << " 1 " << mesh.points.size() << '\n'
      << "3 1 0 " << mesh.points.size() << '\n';
  for (std::size_t i = 0; i < mesh.points.size(); ++i) out << i + 1 << '\n';
  for (const auto& p : mesh.points) out << p[0] << ' ' << p[1] << ' ' << p[2] << '\n';
  std::size_t blocks = 0;
  for (const std::size_t n : count) blocks += n > 0;
  out << "$EndNodes\n$Elements\n" << blocks << ' ' << mesh.tets.size() << " 1 " << mesh.tets.size() << '\n';
  std::size_t next = 1;
  for (std::size_t r = 0; r < regions; ++r) {
    if (count[r] == 0) continue;
    out << "3 " << r + 1 << " 4 " << count[r] << '\n';
    for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
      if (mesh.region[t] != static_cast<int>(r)) continue;
      const auto& c = mesh.tets[t];
      out << next++ << ' ' << c[0] + 1 << ' ' << c[1] + 1 << ' ' << c[2] + 1 << ' ' << c[3] + 1 << '\n';
    }
  }
  out << "$EndElements\n";
}

std::string lower_extension(std::string format) {
  if (!format.empty() && format[0] == '.') format.erase(0, 1);
  for (char& c : format) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return format;
}

}  // namespace

std::string volume_mesh_format(const std::string& path) {
  const std::string ext = lower_extension(std::filesystem::path(path).extension().string());
  if (ext != "vtu" && ext != "inp" && ext != "msh")
    throw InvalidInput(path + ": unknown volume mesh format (the extension must be .vtu, .inp or .msh)");
  return "." + ext;
}

void write_volume_mesh(const TetMesh& mesh, const std::vector<ContactPatch>& contacts, std::ostream& out,
                       const std::string& format) {
  const std::string f = lower_extension(format);
  out.imbue(std::locale::classic());
  out.precision(17);
  if (f == "vtu") write_vtu(mesh, out);
  else if (f == "inp") write_inp(mesh, contacts, out);
  else if (f == "msh") write_msh(mesh, out);
  else throw InvalidInput("unknown volume mesh format '" + format + "' (vtu, inp or msh)");
}

}  // namespace seam
