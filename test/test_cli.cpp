// End-to-end tests of the `seam` command-line tool: the real binary (SEAM_CLI_PATH) is run
// through the shell and its exit code, stderr and output files are checked against the error
// contract of cli/main.cpp:
//   exit 0 on success; exit 2 on bad input or usage with exactly one line on stderr,
//   "seam: FILE: problem", and no output file left behind; inputs are never overwritten.
//
// SPDX-License-Identifier: GPL-3.0-or-later
#include <seam/io.h>

#include <catch2/catch.hpp>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <sys/wait.h>
#include <unistd.h>

#include "test_support.h"

#ifndef SEAM_CLI_PATH
#error "SEAM_CLI_PATH (path of the seam binary) must be defined by the build"
#endif
#ifndef SEAM_SOURCE_DIR
#error "SEAM_SOURCE_DIR must be defined by the build"
#endif

namespace fs = std::filesystem;
using Catch::Contains;
using Catch::EndsWith;
using Catch::StartsWith;

namespace {

const std::string example_mesh = SEAM_SOURCE_DIR "/examples/tow.off";
const std::string example_curves = SEAM_SOURCE_DIR "/examples/ring.polylines.txt";

using seam_test::entries;
using seam_test::read_bytes;
using seam_test::write_bytes;

/// A fresh directory under the system's temporary directory, removed with its content, with
/// three subdirectories: in/ (input files), out/ (outputs: must stay empty after a failed run)
/// and log/ (the tool's stdout and stderr).
struct TempDir : seam_test::TempDir {
  TempDir() : seam_test::TempDir("seam_test_cli") {
    fs::create_directories(path / "in");
    fs::create_directories(path / "out");
    fs::create_directories(path / "log");
  }

  std::string in(const std::string& name) const { return (path / "in" / name).string(); }
  std::string out(const std::string& name) const { return (path / "out" / name).string(); }
  std::string log(const std::string& name) const { return (path / "log" / name).string(); }
  /// Writes an input file and returns its path.
  std::string input(const std::string& name, const std::string& content) const {
    write_bytes(in(name), content);
    return in(name);
  }
};

/// Single-quotes `s` for the POSIX shell.
std::string shell_quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) {
    if (c == '\'') q += "'\\''";
    else q += c;
  }
  return q + "'";
}

struct Run {
  int code = -1;
  std::string out, err;
};

/// Runs `seam ARGS...` (in directory `cwd` if given), stdin from /dev/null, stdout and stderr
/// captured in files of dir/log.
Run run_seam(const TempDir& dir, const std::vector<std::string>& args, const std::string& cwd = "") {
  static int n = 0;
  const std::string id = std::to_string(n++);
  const std::string out = dir.log("stdout" + id), err = dir.log("stderr" + id);
  std::string cmd;
  if (!cwd.empty()) cmd = "cd " + shell_quote(cwd) + " && ";
  cmd += shell_quote(SEAM_CLI_PATH);
  for (const auto& a : args) cmd += " " + shell_quote(a);
  cmd += " </dev/null >" + shell_quote(out) + " 2>" + shell_quote(err);
  const int status = std::system(cmd.c_str());
  INFO("command: " << cmd);
  REQUIRE(status != -1);
  REQUIRE(WIFEXITED(status));
  Run r;
  r.code = WEXITSTATUS(status);
  r.out = read_bytes(out);
  r.err = read_bytes(err);
  return r;
}

/// The usual arguments: all three outputs in dir/out.
std::vector<std::string> embed_args(const TempDir& dir, const std::string& mesh, const std::string& curves) {
  return {"embed",         mesh,
          "--curves",      curves,
          "-o",            dir.out("out.off"),
          "--curves-out",  dir.out("curves.txt"),
          "--report",      dir.out("report.json")};
}

/// Checks the error contract: exit 2, exactly one line on stderr, "seam: ..." naming `names`
/// (and containing `what`), and no output (nothing at all in dir/out, not even a temporary file).
void check_input_error(const TempDir& dir, const Run& r, const std::string& names, const std::string& what = "") {
  INFO("stderr: " << r.err);
  CHECK(r.code == 2);
  CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
  CHECK((!r.err.empty() && r.err.back() == '\n'));
  CHECK_THAT(r.err, StartsWith("seam: "));
  CHECK_THAT(r.err, !StartsWith("seam: internal error"));
  CHECK_THAT(r.err, Contains(names));
  if (!what.empty()) CHECK_THAT(r.err, Contains(what));
  CHECK_FALSE(fs::exists(dir.out("out.off")));
  CHECK_FALSE(fs::exists(dir.out("curves.txt")));
  CHECK_FALSE(fs::exists(dir.out("report.json")));
  CHECK(entries(dir.path / "out").empty());
}

// A closed, outward-oriented tetrahedron and a curve on its face z = 0.
const std::string tetra_off =
    "OFF\n4 4 0\n"
    "0 0 0\n1 0 0\n0 1 0\n0 0 1\n"
    "3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n";
const std::string tetra_curve = "2 0.2 0.2 0 0.5 0.2 0\n";

/// Every undirected edge of `soup` is used by exactly two triangles (closed surface).
bool is_closed(const seam::TriangleSoup& soup) {
  std::map<std::pair<std::size_t, std::size_t>, int> uses;
  for (const auto& t : soup.triangles)
    for (int k = 0; k < 3; ++k) {
      const std::size_t a = t[k], b = t[(k + 1) % 3];
      ++uses[{std::min(a, b), std::max(a, b)}];
    }
  return std::all_of(uses.begin(), uses.end(), [](const auto& u) { return u.second == 2; });
}

/// Reads an output mesh back and checks that it is a valid closed triangle mesh.
seam::TriangleSoup check_output_mesh(const std::string& path) {
  INFO("output mesh " << path);
  seam::TriangleSoup soup;
  REQUIRE_NOTHROW(soup = seam::read_triangle_mesh(path));
  CHECK_NOTHROW(seam::validate_triangle_mesh(soup, path));
  CHECK(is_closed(soup));
  return soup;
}

}  // namespace

// ================================================================== success

TEST_CASE("cli: seam check-embed accepts seam embed's output and rejects it once a vertex is moved", "[cli]") {
  TempDir dir;
  const Run r = run_seam(dir, embed_args(dir, example_mesh, example_curves));
  INFO("stderr: " << r.err);
  REQUIRE(r.code == 0);
  CHECK_THAT(r.out, Contains("verified (seam check-embed --tol "));
  // The tolerance embed states, as printed.
  const auto at = r.out.find("--tol ") + 6;
  const std::string tol = r.out.substr(at, r.out.find(')', at) - at);
  const Run ok = run_seam(dir, {"check-embed", example_mesh, dir.out("out.off"), dir.out("curves.txt"), "--given",
                                example_curves, "--tol", tol});
  INFO("check-embed: " << ok.out << ok.err);
  CHECK(ok.code == 0);
  CHECK_THAT(ok.out, StartsWith("seam check-embed: OK"));

  // One vertex of the output moved 0.5 along z: off the input surface, and its faces cross others.
  seam::TriangleSoup soup = seam::read_triangle_mesh(dir.out("out.off"));
  soup.points[soup.triangles[0][0]][2] += 0.5;
  std::ostringstream moved;
  seam::write_triangle_mesh(soup, moved, ".off");
  const std::string bad = dir.input("moved.off", moved.str());
  const Run fail = run_seam(dir, {"check-embed", example_mesh, bad, dir.out("curves.txt"), "--tol", tol});
  CHECK(fail.code == 1);
  CHECK_THAT(fail.out, StartsWith("FAIL: "));
  CHECK_THAT(fail.out, Contains("farther than the tolerance"));

  // A curves file whose point is not a vertex of the output.
  const Run missing = run_seam(dir, {"check-embed", example_mesh, dir.out("out.off"), example_curves, "--tol", tol});
  CHECK(missing.code == 1);
  CHECK_THAT(missing.out, Contains("curve points are not vertices"));
}

TEST_CASE("cli: embed on the bundled example succeeds and writes valid outputs", "[cli]") {
  TempDir dir;
  const std::string mesh_before = read_bytes(example_mesh), curves_before = read_bytes(example_curves);
  const Run r = run_seam(dir, embed_args(dir, example_mesh, example_curves));
  INFO("stderr: " << r.err);
  REQUIRE(r.code == 0);
  CHECK(r.err.empty());
  CHECK_THAT(r.out, StartsWith("seam embed: "));
  CHECK(std::count(r.out.begin(), r.out.end(), '\n') == 1);

  // Exactly the three outputs, no temporary file left.
  CHECK(entries(dir.path / "out") == std::vector<std::string>{"curves.txt", "out.off", "report.json"});

  const std::string report = read_bytes(dir.out("report.json"));
  CHECK_THAT(report, StartsWith("{"));
  CHECK_THAT(report, Contains("\"crossing_points\""));
  CHECK_THAT(report, Contains("\"kernel\""));
  CHECK_THAT(report, EndsWith("}\n"));

  const seam::TriangleSoup input = seam::read_triangle_mesh(example_mesh);
  const seam::TriangleSoup output = check_output_mesh(dir.out("out.off"));
  CHECK(output.points.size() > input.points.size());
  CHECK(output.triangles.size() > input.triangles.size());

  // The embedded curves are readable, and every one of their points is a vertex of the output.
  std::vector<std::vector<seam::Point3d>> curves;
  REQUIRE_NOTHROW(curves = seam::read_polylines(dir.out("curves.txt")));
  REQUIRE(curves.size() == 1);
  CHECK(curves[0].size() >= 3);
  CHECK(curves[0].front() == curves[0].back());  // the ring is closed
  const std::set<seam::Point3d> vertices(output.points.begin(), output.points.end());
  for (const auto& p : curves[0]) CHECK(vertices.count(p) == 1);

  // The inputs are untouched.
  CHECK(read_bytes(example_mesh) == mesh_before);
  CHECK(read_bytes(example_curves) == curves_before);
}

TEST_CASE("cli: embed succeeds with every kernel", "[cli]") {
  for (const std::string kernel : {"exact", "filtered", "float"}) {
    INFO("--kernel " << kernel);
    TempDir dir;
    auto args = embed_args(dir, example_mesh, example_curves);
    args.insert(args.end(), {"--kernel", kernel});
    const Run r = run_seam(dir, args);
    INFO("stderr: " << r.err);
    REQUIRE(r.code == 0);
    CHECK(r.err.empty());
    check_output_mesh(dir.out("out.off"));
    CHECK_NOTHROW(seam::read_polylines(dir.out("curves.txt")));
    CHECK_THAT(read_bytes(dir.out("report.json")), Contains("\"kernel\": \"" + kernel));
  }
}

TEST_CASE("cli: two runs on the same inputs give byte-identical outputs", "[cli]") {
  TempDir dir;
  const auto run = [&](const std::string& suffix) {
    const Run r = run_seam(dir, {"embed", example_mesh, "--curves", example_curves, "-o",
                                 dir.out("out" + suffix + ".off"), "--curves-out", dir.out("curves" + suffix + ".txt")});
    INFO("stderr: " << r.err);
    REQUIRE(r.code == 0);
  };
  run("1");
  run("2");
  const std::string a = read_bytes(dir.out("out1.off")), b = read_bytes(dir.out("out2.off"));
  CHECK(!a.empty());
  CHECK(a == b);
  CHECK(read_bytes(dir.out("curves1.txt")) == read_bytes(dir.out("curves2.txt")));
}

TEST_CASE("cli: relative paths work from the working directory", "[cli]") {
  TempDir dir;
  dir.input("mesh.off", tetra_off);
  dir.input("curve.txt", tetra_curve);
  const Run r = run_seam(dir, {"embed", "mesh.off", "--curves", "curve.txt", "-o", "../out/out.off"},
                         (dir.path / "in").string());
  INFO("stderr: " << r.err);
  REQUIRE(r.code == 0);
  check_output_mesh(dir.out("out.off"));
}

TEST_CASE("cli: file names that are not UTF-8 do not break the JSON report", "[cli]") {
  TempDir dir;
  // Latin-1 e-acute: a valid POSIX file name, invalid UTF-8 (nlohmann::json::dump throws on it
  // unless told to replace it).
  const std::string mesh = dir.input("t\xe9tra.off", tetra_off);
  const std::string curves = dir.input("curve.txt", tetra_curve);
  const Run r = run_seam(dir, embed_args(dir, mesh, curves));
  INFO("stderr: " << r.err);
  REQUIRE(r.code == 0);
  CHECK(r.err.empty());
  check_output_mesh(dir.out("out.off"));
  const std::string report = read_bytes(dir.out("report.json"));
  CHECK_THAT(report, StartsWith("{"));
  CHECK_THAT(report, Contains("\"crossing_points\""));
}

TEST_CASE("cli: a failed run leaves the outputs of an earlier run alone", "[cli]") {
  // A successful run replaces existing outputs; a later failing run (bad curves) must not touch them.
  TempDir dir;
  const std::string mesh = dir.input("mesh.off", tetra_off);
  const std::string good = dir.input("good.txt", tetra_curve);
  const std::string bad = dir.input("bad.txt", "2 0.2 0.2 0 nan 0.2 0\n");
  write_bytes(dir.out("out.off"), "old content\n");
  const Run ok = run_seam(dir, embed_args(dir, mesh, good));
  REQUIRE(ok.code == 0);
  const std::string produced = read_bytes(dir.out("out.off"));
  CHECK(produced != "old content\n");
  const Run failed = run_seam(dir, embed_args(dir, mesh, bad));
  CHECK(failed.code == 2);
  CHECK(read_bytes(dir.out("out.off")) == produced);
  CHECK(entries(dir.path / "out") == std::vector<std::string>{"curves.txt", "out.off", "report.json"});
}

// ================================================================== bad meshes

TEST_CASE("cli: a bad mesh file is rejected with exit 2, one line naming it, and no output", "[cli]") {
  struct Case {
    const char* label;
    std::string file;     // name in dir/in; empty content with create = false: not created
    std::string content;
    std::string what;     // expected in the message
    bool create = true;
  };
  const std::string garbage_with_nul("\x7f" "ELF\x02\x01\x01\0\0\0\0\xff\xfe\x13\x37\x00\x80\x90", 19);
  const std::string garbage_no_nul = "\xff\xfe\xfd\x80\x81 \x9f\xe2\x82\n\xc3\x28\x01\x02\x03";
  const std::vector<Case> cases = {
      {"missing file", "missing.off", "", "cannot open", false},
      {"empty file", "empty.off", "", "empty"},
      {"only a header", "header.off", "OFF\n", "unexpected end of file"},
      {"truncated OFF", "truncated.off", "OFF\n4 4 0\n0 0 0\n1 0 0\n", "unexpected end of file"},
      {"truncated face list", "truncated2.off", "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1",
       ""},
      {"binary garbage with NUL bytes", "garbage.off", garbage_with_nul, "binary"},
      {"binary garbage without NUL bytes", "garbage2.off", garbage_no_nul, "not an OFF file"},
      {"binary garbage as STL", "garbage.stl", garbage_with_nul, ""},
      {"binary garbage as PLY", "garbage.ply", garbage_with_nul, ""},
      {"binary garbage as OBJ", "garbage.obj", garbage_with_nul, ""},
      {"text that is not a mesh", "text.off", "Dear reader,\nthis is a letter, not a mesh.\n", "not an OFF file"},
      {"unknown extension", "mesh.txt", tetra_off, "unknown mesh format"},
      {"NaN coordinate", "nan.off", "OFF\n4 4 0\n0 0 0\nnan 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n",
       "non-finite"},
      {"infinite coordinate", "inf.off",
       "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1e999 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n", "non-finite"},
      {"non-numeric coordinate", "word.off",
       "OFF\n4 4 0\n0 0 0\n1 zero 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n", "not a number"},
      {"out-of-range index", "range.off", "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 7\n3 1 2 3\n",
       "out of range"},
      {"negative index", "negative.off",
       "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 2 1\n3 0 1 3\n3 0 3 -1\n3 1 2 3\n", "out of range"},
      {"non-triangle face", "quad.off", "OFF\n4 2 0\n0 0 0\n1 0 0\n1 1 0\n0 1 0\n4 0 1 2 3\n3 0 2 1\n",
       "only triangles"},
      {"non-manifold edge", "nonmanifold.off",
       "OFF\n5 3 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n0 -1 0\n3 0 1 2\n3 1 0 3\n3 1 0 4\n", "non-manifold"},
      {"non-manifold vertex", "bowtie.off", "OFF\n5 2 0\n0 0 0\n1 0 0\n0 1 0\n-1 0 0\n0 -1 0\n3 0 1 2\n3 0 3 4\n",
       "non-manifold"},
      {"inconsistent orientation", "flipped.off",
       "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n3 0 1 2\n3 0 1 3\n3 0 3 2\n3 1 2 3\n", "orientation"},
      {"zero-area face", "flat.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n2 0 0\n3 0 1 2\n", "zero area"},
      {"zero-area face in a closed mesh", "flat2.off",
       "OFF\n4 4 0\n0 0 0\n1 0 0\n0 1 0\n0.5 0 0\n3 0 2 1\n3 0 1 3\n3 0 3 2\n3 1 2 3\n", "zero area"},
      {"repeated vertex in a face", "repeat.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 1\n", "repeats vertex"},
      {"no faces", "nofaces.off", "OFF\n3 0 0\n0 0 0\n1 0 0\n0 1 0\n", "no triangles"},
  };
  for (const Case& c : cases) {
    INFO("case: " << c.label);
    TempDir dir;
    const std::string curves = dir.input("curve.txt", tetra_curve);
    const std::string mesh = c.create ? dir.input(c.file, c.content) : dir.in(c.file);
    const Run r = run_seam(dir, embed_args(dir, mesh, curves));
    check_input_error(dir, r, mesh, c.what);
  }
}

TEST_CASE("cli: a directory given as the mesh is rejected", "[cli]") {
  for (const std::string name : {"meshdir.off", "meshdir"}) {
    INFO("directory " << name);
    TempDir dir;
    const std::string curves = dir.input("curve.txt", tetra_curve);
    const std::string mesh = dir.in(name);
    fs::create_directory(mesh);
    const Run r = run_seam(dir, embed_args(dir, mesh, curves));
    check_input_error(dir, r, mesh);
  }
}

// ================================================================== bad curves

TEST_CASE("cli: a bad curves file is rejected with exit 2, one line naming it, and no output", "[cli]") {
  struct Case {
    const char* label;
    std::string content;
    std::string what;
  };
  const std::vector<Case> cases = {
      {"empty file", "", "empty"},
      {"only comments and blank lines", "# no curve here\n\n   \n", "no polyline"},
      {"wrong count (too few coordinates)", "3 0.2 0.2 0 0.5 0.2 0\n", "expected 9 coordinates"},
      {"wrong count (too many coordinates)", "2 0.2 0.2 0 0.5 0.2 0 0.3\n", "expected 6 coordinates"},
      {"wrong count on a later line", tetra_curve + "2 0.2 0.2 0 0.5 0.2\n", "line 2"},
      {"NaN coordinate", "2 0.2 0.2 0 nan 0.2 0\n", "non-finite"},
      {"infinite coordinate", "2 0.2 0.2 0 inf 0.2 0\n", "non-finite"},
      {"no points", "0\n", "at least 1 point"},
      {"one point", "1 0.2 0.2 0\n", "fewer than 2 points"},
      {"negative count", "-2 0.2 0.2 0 0.5 0.2 0\n", "line 1"},
      {"non-numeric count", "two 0.2 0.2 0 0.5 0.2 0\n", "not a number"},
      {"non-numeric coordinate", "2 0.2 0.2 0 x 0.2 0\n", "not a number"},
      {"binary garbage", std::string("\x01\x02\0\xff\xfe", 5), "binary"},
      {"a curve far from the surface", "2 0.2 0.2 -100 0.5 0.2 0\n", "from the surface"},
      {"a curve entirely far from the surface", "2 100.2 0.2 0 100.5 0.2 0\n", "from the surface"},
  };
  for (const Case& c : cases) {
    INFO("case: " << c.label);
    TempDir dir;
    const std::string mesh = dir.input("mesh.off", tetra_off);
    const std::string curves = dir.input("curves.txt", c.content);
    const Run r = run_seam(dir, embed_args(dir, mesh, curves));
    check_input_error(dir, r, curves, c.what);
  }
}

TEST_CASE("cli: a curve far from the example surface names the curves file", "[cli]") {
  TempDir dir;
  // Node 1 is 100 units above the tow (which lies within |z| < 1).
  const std::string curves = dir.input("far.txt", "3 5 1 0 5 1 100 5 -1 0\n");
  const Run r = run_seam(dir, embed_args(dir, example_mesh, curves));
  check_input_error(dir, r, curves, "from the surface");
  CHECK_THAT(r.err, Contains("node 1"));
}

TEST_CASE("cli: a missing curves file or a directory as curves file is rejected", "[cli]") {
  {
    TempDir dir;
    const std::string mesh = dir.input("mesh.off", tetra_off);
    const Run r = run_seam(dir, embed_args(dir, mesh, dir.in("missing.txt")));
    check_input_error(dir, r, dir.in("missing.txt"), "cannot open");
  }
  {
    TempDir dir;
    const std::string mesh = dir.input("mesh.off", tetra_off);
    fs::create_directory(dir.in("curvesdir"));
    const Run r = run_seam(dir, embed_args(dir, mesh, dir.in("curvesdir")));
    check_input_error(dir, r, dir.in("curvesdir"), "directory");
  }
}

// ================================================================== outputs

TEST_CASE("cli: an output path equal to an input is refused and the input is untouched", "[cli]") {
  struct Case {
    const char* label;
    std::string option;  // -o, --curves-out or --report
    std::string path;    // relative to dir/in
    std::string input;   // the input it names: mesh.off or curves.txt
  };
  const std::vector<Case> cases = {
      {"-o is the mesh", "-o", "mesh.off", "mesh.off"},
      {"-o is the mesh, spelled differently", "-o", "./sub/../mesh.off", "mesh.off"},
      {"-o is a symbolic link to the mesh", "-o", "link.off", "mesh.off"},
      {"-o is the curves file", "-o", "curves.txt", "curves.txt"},
      {"--curves-out is the curves file", "--curves-out", "curves.txt", "curves.txt"},
      {"--curves-out is the mesh", "--curves-out", "mesh.off", "mesh.off"},
      {"--report is the mesh", "--report", "mesh.off", "mesh.off"},
      {"--report is the curves file", "--report", "curves.txt", "curves.txt"},
  };
  const std::string mesh_content = read_bytes(example_mesh), curves_content = read_bytes(example_curves);
  for (const Case& c : cases) {
    INFO("case: " << c.label);
    TempDir dir;
    const std::string mesh = dir.input("mesh.off", mesh_content);
    const std::string curves = dir.input("curves.txt", curves_content);
    fs::create_directory(dir.in("sub"));
    fs::create_symlink(mesh, dir.in("link.off"));
    const std::vector<std::string> before = entries(dir.path / "in");
    const std::string target = (dir.path / "in" / c.path).string();
    std::vector<std::string> args = {"embed", mesh, "--curves", curves};
    if (c.option != "-o") args.insert(args.end(), {"-o", dir.out("out.off")});
    args.insert(args.end(), {c.option, target});
    const Run r = run_seam(dir, args);
    check_input_error(dir, r, target, "input");
    CHECK(read_bytes(mesh) == mesh_content);
    CHECK(read_bytes(curves) == curves_content);
    CHECK(entries(dir.path / "in") == before);  // no temporary file next to the inputs
    CHECK(fs::is_symlink(dir.in("link.off")));
  }
}

TEST_CASE("cli: an output path equal to the input given relative to the working directory", "[cli]") {
  TempDir dir;
  const std::string mesh = dir.input("mesh.off", tetra_off);
  dir.input("curves.txt", tetra_curve);
  const Run r =
      run_seam(dir, {"embed", "mesh.off", "--curves", "curves.txt", "-o", "./mesh.off"}, (dir.path / "in").string());
  check_input_error(dir, r, "mesh.off", "input");
  CHECK(read_bytes(mesh) == tetra_off);
  CHECK(entries(dir.path / "in") == std::vector<std::string>{"curves.txt", "mesh.off"});
}

TEST_CASE("cli: two outputs with the same path are refused", "[cli]") {
  TempDir dir;
  const std::string mesh = dir.input("mesh.off", tetra_off);
  const std::string curves = dir.input("curves.txt", tetra_curve);
  const Run r = run_seam(dir, {"embed", mesh, "--curves", curves, "-o", dir.out("out.off"), "--report",
                               dir.out("out.off")});
  check_input_error(dir, r, dir.out("out.off"), "two outputs");

  // The same, spelled differently and relative to the working directory (no such file yet).
  const std::vector<std::vector<std::string>> spellings = {
      {"-o", "out.off", "--report", "./out.off"},
      {"-o", "out.off", "--curves-out", "../out/out.off"},
      {"-o", "x.off", "--curves-out", "c.txt", "--report", "sub/../c.txt"},
  };
  for (const auto& outputs : spellings) {
    INFO("outputs: " << outputs[1] << " " << outputs[3]);
    std::vector<std::string> args = {"embed", mesh, "--curves", curves};
    args.insert(args.end(), outputs.begin(), outputs.end());
    const Run rel = run_seam(dir, args, (dir.path / "out").string());
    CHECK(rel.code == 2);
    CHECK_THAT(rel.err, StartsWith("seam: "));
    CHECK_THAT(rel.err, Contains("two outputs"));
    CHECK(entries(dir.path / "out").empty());
  }
}

TEST_CASE("cli: an unwritable output fails with exit 2 and leaves no output at all", "[cli]") {
  struct Case {
    const char* label;
    std::string option;  // the output that cannot be written
    std::string path;    // relative to dir/out
  };
  const std::vector<Case> cases = {
      {"-o in a non-existent directory", "-o", "nodir/out.off"},
      {"--curves-out in a non-existent directory", "--curves-out", "nodir/curves.txt"},
      {"--report in a non-existent directory", "--report", "nodir/report.json"},
      {"-o below a regular file", "-o", "file/out.off"},
      {"-o is an existing directory", "-o", "dir.off"},
      {"--report is an existing directory", "--report", "dir.json"},
      {"-o with an unknown extension", "-o", "out.xyz"},
  };
  for (const Case& c : cases) {
    INFO("case: " << c.label);
    TempDir dir;
    const std::string mesh = dir.input("mesh.off", tetra_off);
    const std::string curves = dir.input("curves.txt", tetra_curve);
    // Obstacles live in dir/in so that dir/out must stay empty; the output paths point there.
    fs::create_directory(dir.in("dir.off"));
    fs::create_directory(dir.in("dir.json"));
    write_bytes(dir.in("file"), "a regular file\n");
    const bool obstacle = c.path.rfind("dir.", 0) == 0 || c.path.rfind("file/", 0) == 0;
    const std::string bad = obstacle ? dir.in(c.path) : dir.out(c.path);
    std::map<std::string, std::string> outputs = {
        {"-o", dir.out("out.off")}, {"--curves-out", dir.out("curves.txt")}, {"--report", dir.out("report.json")}};
    outputs[c.option] = bad;
    std::vector<std::string> args = {"embed", mesh, "--curves", curves};
    for (const auto& [option, path] : outputs) args.insert(args.end(), {option, path});
    const Run r = run_seam(dir, args);
    check_input_error(dir, r, bad);
    CHECK_FALSE(fs::exists(dir.out("nodir")));
    CHECK(fs::is_directory(dir.in("dir.off")));
    CHECK(fs::is_empty(dir.in("dir.off")));
    CHECK(fs::is_directory(dir.in("dir.json")));
    CHECK(read_bytes(dir.in("file")) == "a regular file\n");
  }
}

// ================================================================== usage and options

TEST_CASE("cli: usage errors exit with 2 and write nothing", "[cli]") {
  TempDir dir;
  const std::string mesh = dir.input("mesh.off", tetra_off);
  const std::string curves = dir.input("curves.txt", tetra_curve);
  const std::string out = dir.out("out.off");
  const std::vector<std::pair<const char*, std::vector<std::string>>> cases = {
      {"no arguments", {}},
      {"unknown subcommand", {"frobnicate", mesh}},
      {"embed without arguments", {"embed"}},
      {"unknown option", {"embed", mesh, "--curves", curves, "-o", out, "--bogus"}},
      {"unknown option with a value", {"embed", mesh, "--curves", curves, "-o", out, "--colour", "red"}},
      {"extra positional argument", {"embed", mesh, mesh, "--curves", curves, "-o", out}},
      {"missing --curves", {"embed", mesh, "-o", out}},
      {"missing -o", {"embed", mesh, "--curves", curves}},
      {"missing MESH", {"embed", "--curves", curves, "-o", out}},
      {"option without its value", {"embed", mesh, "--curves", curves, "-o"}},
      {"--kernel bogus", {"embed", mesh, "--curves", curves, "-o", out, "--kernel", "bogus"}},
      {"--kernel without value", {"embed", mesh, "--curves", curves, "-o", out, "--kernel"}},
      {"--min-angle not a number", {"embed", mesh, "--curves", curves, "-o", out, "--min-angle", "twenty"}},
      {"--snap-tol not a number", {"embed", mesh, "--curves", curves, "-o", out, "--snap-tol", "1x"}},
  };
  for (const auto& [label, args] : cases) {
    INFO("case: " << label);
    const Run r = run_seam(dir, args);
    INFO("stderr: " << r.err);
    CHECK(r.code == 2);
    CHECK(!r.err.empty());
    CHECK(entries(dir.path / "out").empty());
  }
  CHECK(read_bytes(mesh) == tetra_off);
  CHECK(read_bytes(curves) == tetra_curve);
}

TEST_CASE("cli: --help exits 0", "[cli]") {
  TempDir dir;
  for (const std::vector<std::string>& args :
       {std::vector<std::string>{"--help"}, std::vector<std::string>{"embed", "--help"}}) {
    const Run r = run_seam(dir, args);
    CHECK(r.code == 0);
    CHECK_THAT(r.out, Contains("embed"));
  }
}

TEST_CASE("cli: option values out of range exit with 2, one line naming the option, and no output", "[cli]") {
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"--min-angle", "70"},  {"--min-angle", "-1"},      {"--min-angle", "nan"}, {"--snap-tol", "nan"},
      {"--snap-tol", "inf"},  {"--max-distance", "inf"}, {"--max-area", "-1"},   {"--curve-tol", "-0.5"},
      {"--curve-tol", "inf"}, {"--snap-tol", "-1"},    {"--max-distance", "-1"}, {"--snap-tol", "-0.001"},
  };
  for (const auto& [option, value] : cases) {
    INFO("case: " << option << " " << value);
    TempDir dir;
    const std::string mesh = dir.input("mesh.off", tetra_off);
    const std::string curves = dir.input("curves.txt", tetra_curve);
    auto args = embed_args(dir, mesh, curves);
    args.insert(args.end(), {option, value});
    const Run r = run_seam(dir, args);
    check_input_error(dir, r, option);
    // The problem is the option, not the input files.
    CHECK_THAT(r.err, !Contains(curves));
    CHECK_THAT(r.err, !Contains(mesh));
  }
}

TEST_CASE("cli: valid option values at the ends of their ranges are accepted", "[cli]") {
  const std::vector<std::vector<std::string>> cases = {
      {"--min-angle", "0"}, {"--min-angle", "30"}, {"--snap-tol", "0"}, {"--max-area", "0"},
      {"--curve-tol", "0"}, {"--max-distance", "auto"}, {"--snap-tol", "auto"},
  };
  for (const auto& extra : cases) {
    INFO("case: " << extra[0] << " " << extra[1]);
    TempDir dir;
    const std::string mesh = dir.input("mesh.off", tetra_off);
    const std::string curves = dir.input("curves.txt", tetra_curve);
    auto args = embed_args(dir, mesh, curves);
    args.insert(args.end(), extra.begin(), extra.end());
    const Run r = run_seam(dir, args);
    INFO("stderr: " << r.err);
    CHECK(r.code == 0);
    check_output_mesh(dir.out("out.off"));
  }
}
