// seam internal: one call of TetGen 1.5 (libtet). See include/seam/internal/tetgen_call.h.
// SPDX-License-Identifier: GPL-3.0-or-later
#include <seam/internal/tetgen_call.h>

#include <seam/errors.h>

#define TETLIBRARY
#include <tetgen.h>

#include <cerrno>
#include <csignal>
#include <cstdint>
#include <cstring>
#include <limits>
#include <new>
#include <string>
#include <vector>

#include <poll.h>
#include <sys/wait.h>
#include <unistd.h>

namespace seam::internal {

namespace {

std::string tetgen_failure(int code) {
  switch (code) {
    case 1: return "TetGen ran out of memory";
    case 2: return "TetGen reported an internal error";
    case 3: return "TetGen found a self-intersection in the combined surfaces (faces closer than its tolerance)";
    case 4: return "TetGen found a very small input feature (below its tolerance -T)";
    case 5: return "TetGen found two very close input facets";
    case 10: return "TetGen found an input error";
    default: return "TetGen failed with code " + std::to_string(code);
  }
}

/// Fills TetGen's input (its arrays are freed by ~tetgenio with delete[]).
void fill_input(const TetgenInput& input, tetgenio& in) {
  if (input.points.size() > static_cast<std::size_t>(std::numeric_limits<int>::max() / 3) ||
      input.triangles.size() > static_cast<std::size_t>(std::numeric_limits<int>::max()))
    throw InternalError("the model is too large for TetGen (int indices)");
  in.firstnumber = 0;
  in.numberofpoints = static_cast<int>(input.points.size());
  in.pointlist = new REAL[input.points.size() * 3];
  for (std::size_t i = 0; i < input.points.size(); ++i)
    for (int k = 0; k < 3; ++k) in.pointlist[3 * i + k] = input.points[i][k];
  in.numberoffacets = static_cast<int>(input.triangles.size());
  in.facetlist = new tetgenio::facet[input.triangles.size()];
  for (std::size_t f = 0; f < input.triangles.size(); ++f) {
    tetgenio::facet& facet = in.facetlist[f];
    tetgenio::init(&facet);
    facet.numberofpolygons = 1;
    facet.polygonlist = new tetgenio::polygon[1];
    tetgenio::init(&facet.polygonlist[0]);
    facet.polygonlist[0].numberofvertices = 3;
    facet.polygonlist[0].vertexlist = new int[3];
    for (int k = 0; k < 3; ++k) facet.polygonlist[0].vertexlist[k] = static_cast<int>(input.triangles[f][k]);
  }
  in.numberofregions = static_cast<int>(input.seeds.size());
  if (!input.seeds.empty()) {
    in.regionlist = new REAL[input.seeds.size() * 5];
    for (std::size_t r = 0; r < input.seeds.size(); ++r) {
      for (int k = 0; k < 3; ++k) in.regionlist[5 * r + k] = input.seeds[r][k];
      in.regionlist[5 * r + 3] = input.seed_attributes[r];
      in.regionlist[5 * r + 4] = -1.0;  // no volume constraint of its own
    }
  }
}

TetgenOutput read_output(const tetgenio& out) {
  TetgenOutput result;
  if (out.numberofcorners != 4) throw InternalError("TetGen returned elements of " + std::to_string(out.numberofcorners) + " corners");
  const int first = out.firstnumber;
  result.points.resize(static_cast<std::size_t>(out.numberofpoints));
  for (std::size_t i = 0; i < result.points.size(); ++i)
    for (int k = 0; k < 3; ++k) result.points[i][k] = out.pointlist[3 * i + k];
  const auto n_tets = static_cast<std::size_t>(out.numberoftetrahedra);
  result.tets.resize(n_tets);
  result.attribute.assign(n_tets, 0);
  for (std::size_t t = 0; t < n_tets; ++t) {
    for (int k = 0; k < 4; ++k) {
      const int v = out.tetrahedronlist[4 * t + k] - first;
      if (v < 0 || v >= out.numberofpoints) throw InternalError("TetGen returned a tet corner out of range");
      result.tets[t][k] = static_cast<std::size_t>(v);
    }
    if (out.numberoftetrahedronattributes > 0)
      result.attribute[t] = static_cast<int>(out.tetrahedronattributelist[t * out.numberoftetrahedronattributes]);
  }
  return result;
}


/// Runs TetGen in this process (the child's part of run_tetgen).
TetgenOutput run_here(const TetgenInput& input) {
  tetgenio in, out;
  fill_input(input, in);
  std::vector<char> switches(input.switches.begin(), input.switches.end());
  switches.push_back('\0');
  try {
    tetrahedralize(switches.data(), &in, &out);
  } catch (int code) {
    if (code == 1) throw std::bad_alloc();
    throw InternalError(tetgen_failure(code));
  }
  return read_output(out);
}

// ---------------------------------------------------------------- the child process and its pipe

enum class Outcome : std::uint32_t { mesh = 0, error = 1, out_of_memory = 2 };

bool write_all(int fd, const void* data, std::size_t size) {
  const char* p = static_cast<const char*>(data);
  while (size > 0) {
    const ssize_t n = ::write(fd, p, size);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) return false;
    p += n;
    size -= std::size_t(n);
  }
  return true;
}

template <class T> bool write_vector(int fd, const std::vector<T>& v) {
  const std::uint64_t n = v.size();
  return write_all(fd, &n, sizeof n) && write_all(fd, v.data(), n * sizeof(T));
}

/// The child: runs TetGen, writes the outcome and the mesh (or the message) to `fd`, and ends
/// without running the parent's exit handlers.
[[noreturn]] void child(const TetgenInput& input, int fd) {
  std::signal(SIGINT, SIG_DFL);  // the parent's handlers clean up the parent's files
  std::signal(SIGTERM, SIG_DFL);
  Outcome outcome = Outcome::mesh;
  std::string message;
  TetgenOutput mesh;
  try {
    mesh = run_here(input);
  } catch (const std::bad_alloc&) {
    outcome = Outcome::out_of_memory;
  } catch (const std::exception& e) {
    outcome = Outcome::error;
    message = e.what();
  }
  const std::vector<char> text(message.begin(), message.end());
  bool ok = write_all(fd, &outcome, sizeof outcome) && write_vector(fd, text);
  if (ok && outcome == Outcome::mesh)
    ok = write_vector(fd, mesh.points) && write_vector(fd, mesh.tets) && write_vector(fd, mesh.attribute);
  ::_exit(ok ? 0 : 1);
}

/// Reads both pipes to their end (the child's stderr too, so that neither fills up).
void drain(int data_fd, int err_fd, std::string& data, std::string& err) {
  pollfd fds[2] = {{data_fd, POLLIN, 0}, {err_fd, POLLIN, 0}};
  std::string* into[2] = {&data, &err};
  int open_fds = 2;
  char buffer[1 << 16];
  while (open_fds > 0) {
    if (::poll(fds, 2, -1) < 0) {
      if (errno == EINTR) continue;
      throw InternalError(std::string("reading TetGen's results: ") + std::strerror(errno));
    }
    for (int i = 0; i < 2; ++i) {
      if (fds[i].fd < 0 || !(fds[i].revents & (POLLIN | POLLHUP | POLLERR))) continue;
      const ssize_t n = ::read(fds[i].fd, buffer, sizeof buffer);
      if (n < 0 && errno == EINTR) continue;
      if (n <= 0) {
        fds[i].fd = -1;
        --open_fds;
      } else {
        into[i]->append(buffer, std::size_t(n));
      }
    }
  }
}

class Reader {
 public:
  explicit Reader(const std::string& bytes) : bytes_(bytes) {}
  template <class T> void read(T& x) { take(&x, sizeof x); }
  template <class T> void read(std::vector<T>& v) {
    std::uint64_t n = 0;
    read(n);
    if (n > (bytes_.size() - at_) / sizeof(T)) throw InternalError("TetGen's process sent a truncated mesh");
    v.resize(std::size_t(n));
    take(v.data(), std::size_t(n) * sizeof(T));
  }

 private:
  void take(void* out, std::size_t size) {
    if (size == 0) return;  // (an empty vector's data() may be null, which memcpy may not get)
    if (size > bytes_.size() - at_) throw InternalError("TetGen's process sent a truncated mesh");
    std::memcpy(out, bytes_.data() + at_, size);
    at_ += size;
  }
  const std::string& bytes_;
  std::size_t at_ = 0;
};

/// The first line of TetGen's stderr that says what failed, trimmed.
std::string first_line(const std::string& err) {
  std::string line = err.substr(0, err.find('\n'));
  if (line.size() > 300) line = line.substr(0, 300) + "...";
  return line;
}

}  // namespace

TetgenOutput run_tetgen(const TetgenInput& input) {
  int data[2], err[2];
  if (::pipe(data) != 0) throw InternalError(std::string("cannot run TetGen: pipe: ") + std::strerror(errno));
  if (::pipe(err) != 0) {
    ::close(data[0]), ::close(data[1]);
    throw InternalError(std::string("cannot run TetGen: pipe: ") + std::strerror(errno));
  }
  const pid_t pid = ::fork();
  if (pid < 0) {
    for (int fd : {data[0], data[1], err[0], err[1]}) ::close(fd);
    throw InternalError(std::string("cannot run TetGen: fork: ") + std::strerror(errno));
  }
  if (pid == 0) {
    ::close(data[0]);
    ::close(err[0]);
    ::dup2(err[1], STDERR_FILENO);
    child(input, data[1]);
  }
  ::close(data[1]);
  ::close(err[1]);
  std::string bytes, messages;
  try {
    drain(data[0], err[0], bytes, messages);
  } catch (...) {
    ::close(data[0]), ::close(err[0]);
    ::kill(pid, SIGKILL);
    ::waitpid(pid, nullptr, 0);
    throw;
  }
  ::close(data[0]);
  ::close(err[0]);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) throw InternalError(std::string("cannot wait for TetGen: ") + std::strerror(errno));
  if (WIFSIGNALED(status))
    throw TetgenAborted("TetGen stopped on one of its own assertions (" +
                        (messages.empty() ? "signal " + std::to_string(WTERMSIG(status)) : first_line(messages)) +
                        ")");
  Reader reader(bytes);
  Outcome outcome{};
  std::vector<char> text;
  reader.read(outcome);
  reader.read(text);
  if (outcome == Outcome::out_of_memory) throw std::bad_alloc();
  if (outcome == Outcome::error) throw InternalError(std::string(text.begin(), text.end()));
  if (outcome != Outcome::mesh || !WIFEXITED(status) || WEXITSTATUS(status) != 0)
    throw InternalError("TetGen's process ended without a mesh");
  TetgenOutput mesh;
  reader.read(mesh.points);
  reader.read(mesh.tets);
  reader.read(mesh.attribute);
  return mesh;
}

}  // namespace seam::internal
