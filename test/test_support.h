// Helpers shared by the test files: temporary directories and whole-file reads and writes.
#pragma once

#include <catch2/catch.hpp>
#include <seam/kernels.h>
#include <seam/types.h>

#include <cmath>
#include <cstdlib>

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

namespace seam_test {

/// True in the AddressSanitizer build (scripts/test.sh --sanitize, clang), where the heaviest
/// end-to-end tests run a subset of their cases to stay within ctest's timeout; the Release
/// build runs them all.
#if defined(__has_feature)
#if __has_feature(address_sanitizer)
#define SEAM_TEST_SANITIZED 1
#endif
#endif
#if defined(__SANITIZE_ADDRESS__)
#define SEAM_TEST_SANITIZED 1
#endif
#ifdef SEAM_TEST_SANITIZED
inline constexpr bool sanitized_build = true;
#else
inline constexpr bool sanitized_build = false;
#endif

namespace fs = std::filesystem;

/// A field of /proc/self/status in kB ("VmRSS", "VmHWM": the peak resident memory); -1 if missing.
inline long status_kb(const std::string& field) {
  std::ifstream in("/proc/self/status");
  std::string line;
  while (std::getline(in, line))
    if (line.rfind(field + ":", 0) == 0) return std::stol(line.substr(field.size() + 1));
  return -1;
}

/// Runs a shell command; its exit code, or -1 when it did not exit normally.
inline int run_command(const std::string& command) {
  const int status = std::system(command.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

inline std::string read_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

inline void write_bytes(const std::string& path, const std::string& content) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << content;
  out.close();
  REQUIRE(out.good());
}

/// The names in a directory, sorted.
inline std::vector<std::string> entries(const fs::path& dir) {
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  return names;
}

/// Faces marked new (seam::new_face_property) whose area (doubles) is larger than `area`.
template <class K> std::size_t new_faces_larger_than(const seam::Mesh<K>& m, double area) {
  using F = typename seam::Mesh<K>::Face_index;
  const auto found = m.template property_map<F, bool>(seam::new_face_property);
  if (!found.second) return 0;
  std::size_t count = 0;
  for (auto f : m.faces()) {
    if (!found.first[f]) continue;
    const auto h = m.halfedge(f);
    const auto p = seam::to_filtered(m.point(m.source(h))), q = seam::to_filtered(m.point(m.target(h))),
               r = seam::to_filtered(m.point(m.target(m.next(h))));
    if (0.5 * std::sqrt(CGAL::cross_product(q - p, r - p).squared_length()) > area * (1 + 1e-9)) ++count;
  }
  return count;
}

/// A fresh directory under the system's temporary directory, removed with its content.
class TempDir {
 public:
  explicit TempDir(const std::string& prefix) {
    static int counter = 0;
    std::random_device rd;
    path = fs::temp_directory_path() / (prefix + "_" + std::to_string(::getpid()) + "_" +
                                        std::to_string(counter++) + "_" + std::to_string(rd()));
    fs::create_directories(path);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;

  std::string file(const std::string& name) const { return (path / name).string(); }
  std::vector<std::string> entries() const { return seam_test::entries(path); }

  fs::path path;
};

}  // namespace seam_test
