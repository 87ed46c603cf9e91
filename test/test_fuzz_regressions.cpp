// The fuzz targets' inputs through the normal build: every committed seed (fuzz/corpus/TARGET/)
// and every input that once crashed a target (fuzz/regressions/TARGET/, the smallest input that
// showed the bug) is fed to the same entry function as the libFuzzer target (fuzz/fuzz_entry.h).
// It must return normally: success or a typed seam::Error, caught inside the entry function.
//
// SPDX-License-Identifier: GPL-3.0-or-later
#include "../fuzz/fuzz_entry.h"

#include <catch2/catch.hpp>

#include <filesystem>
#include <string>
#include <vector>

#include "test_support.h"

#ifndef SEAM_SOURCE_DIR
#error "SEAM_SOURCE_DIR must be defined by the build"
#endif

namespace fs = std::filesystem;

namespace {

/// The files of fuzz/corpus/TARGET and fuzz/regressions/TARGET, sorted.
std::vector<fs::path> inputs_of(const std::string& target) {
  std::vector<fs::path> files;
  for (const char* dir : {"corpus", "regressions"}) {
    const fs::path d = fs::path(SEAM_SOURCE_DIR) / "fuzz" / dir / target;
    if (!fs::is_directory(d)) continue;
    for (const auto& e : fs::directory_iterator(d))
      if (e.is_regular_file() && e.path().filename().string()[0] != '.') files.push_back(e.path());
  }
  std::sort(files.begin(), files.end());
  return files;
}

void run_all(const std::string& target) {
  const auto files = inputs_of(target);
  CHECK(!files.empty());
  for (const auto& file : files) {
    INFO("fuzz input " << file.string());
    const std::string bytes = seam_test::read_bytes(file.string());
    const auto* data = reinterpret_cast<const std::uint8_t*>(bytes.data());
    if (target == "polylines") CHECK_NOTHROW(seam_fuzz::polyline_reader(data, bytes.size()));
    else if (target == "pair") CHECK_NOTHROW(seam_fuzz::pair_pipeline(data, bytes.size()));
    else CHECK_NOTHROW(seam_fuzz::mesh_reader(data, bytes.size(), target.c_str()));
  }
}

}  // namespace

TEST_CASE("fuzz regressions: OFF reader", "[fuzz]") { run_all("off"); }
TEST_CASE("fuzz regressions: OBJ reader", "[fuzz]") { run_all("obj"); }
TEST_CASE("fuzz regressions: PLY reader", "[fuzz]") { run_all("ply"); }
TEST_CASE("fuzz regressions: STL reader", "[fuzz]") { run_all("stl"); }
TEST_CASE("fuzz regressions: polyline reader", "[fuzz]") { run_all("polylines"); }
TEST_CASE("fuzz regressions: pair pipeline on small meshes", "[fuzz]") { run_all("pair"); }

TEST_CASE("fuzz: the seeds of the pair target decode to valid meshes that the pipeline accepts", "[fuzz]") {
  // The shapes' connectivity must be valid, or the pair target would test nothing but validation.
  for (const auto& file : inputs_of("pair")) {
    if (file.parent_path().parent_path().filename() != "corpus") continue;
    INFO("seed " << file.string());
    const std::string bytes = seam_test::read_bytes(file.string());
    const auto* p = reinterpret_cast<const std::uint8_t*>(bytes.data()) + 2;
    const auto* end = reinterpret_cast<const std::uint8_t*>(bytes.data()) + bytes.size();
    seam::TriangleSoup a, b;
    REQUIRE(seam_fuzz::decode_mesh(p, end, a));
    REQUIRE(seam_fuzz::decode_mesh(p, end, b));
    CHECK_NOTHROW(seam::validate_triangle_mesh(a, "a"));
    CHECK_NOTHROW(seam::validate_triangle_mesh(b, "b"));
    CHECK_NOTHROW(seam::check_no_self_intersection(a, "a"));
    CHECK_NOTHROW(seam::check_no_self_intersection(b, "b"));
  }
}
