// seam: independent checks of an embedding. See seam/verify.h.
// SPDX-License-Identifier: GPL-3.0-or-later
#include <seam/verify.h>

#include <CGAL/boost/graph/helpers.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <utility>
#include <seam/internal/message.h>

#include <sstream>

namespace seam {

namespace {
using internal::say;
}  // namespace

template <class K> std::vector<std::string> check_valid_mesh(const Mesh<K>& output, bool expect_closed) {
  std::vector<std::string> problems;
  if (!CGAL::is_valid_polygon_mesh(output)) problems.push_back("output is not a valid polygon mesh");
  if (!CGAL::is_triangle_mesh(output)) problems.push_back("output is not a triangle mesh");
  if (expect_closed && !CGAL::is_closed(output)) problems.push_back("output is not closed");
  for (auto f : output.faces()) {
    auto h = output.halfedge(f);
    if (CGAL::collinear(output.point(output.source(h)), output.point(output.target(h)),
                        output.point(output.target(output.next(h))))) {
      problems.push_back(say("output face ", std::size_t(f), " is degenerate"));
      break;
    }
  }
  return problems;
}

template <class K>
std::vector<std::string> check_curves_embedded(const Mesh<K>& output, const EmbedResult<K>& result) {
  std::vector<std::string> problems;
  for (std::size_t c = 0; c < result.curve_vertices.size(); ++c) {
    const auto& vs = result.curve_vertices[c];
    const auto& pts = result.curves[c];
    if (vs.size() != pts.size()) problems.push_back(say("curve ", c, ": vertex and point counts differ"));
    for (std::size_t i = 0; i < vs.size() && i < pts.size(); ++i)
      if (!output.is_valid(vs[i]) || output.point(vs[i]) != pts[i])
        problems.push_back(say("curve ", c, " point ", i, " is not the mesh vertex it names"));
    for (std::size_t i = 0; i + 1 < vs.size(); ++i)
      if (output.halfedge(vs[i], vs[i + 1]) == Mesh<K>::null_halfedge())
        problems.push_back(say("curve ", c, " segment ", i, " (", std::size_t(vs[i]), ", ", std::size_t(vs[i + 1]),
                               ") is not an edge of the output"));
  }
  return problems;
}

template <class K> std::vector<std::string> check_same_surface(const Mesh<K>& input, const Mesh<K>& output) {
  using Vector = typename K::Vector_3;
  std::vector<std::string> problems;
  const auto [source, has_source] =
      output.template property_map<typename Mesh<K>::Face_index, std::uint32_t>(source_face_property);
  if (!has_source) return {"output has no source-face property"};
  auto corners = [](const Mesh<K>& m, typename Mesh<K>::Face_index f) {
    auto h = m.halfedge(f);
    return std::array<typename K::Point_3, 3>{m.point(m.source(h)), m.point(m.target(h)),
                                              m.point(m.target(m.next(h)))};
  };
  auto vector_area = [](const std::array<typename K::Point_3, 3>& t) {
    return CGAL::cross_product(t[1] - t[0], t[2] - t[0]);
  };
  std::vector<Vector> sum(input.number_of_faces(), CGAL::NULL_VECTOR);
  // A lazy (Epeck) sum is a chain of nodes whose exact evaluation recurses once per term: made
  // exact every so often, it stays shallow (thousands of faces from one input face overflowed
  // the stack).
  std::vector<std::uint32_t> terms(input.number_of_faces(), 0);
  for (auto f : output.faces()) {
    const std::size_t s = source[f];
    if (s >= input.number_of_faces()) {
      problems.push_back(say("output face ", std::size_t(f), " names input face ", s, " which does not exist"));
      continue;
    }
    const auto in = corners(input, typename Mesh<K>::Face_index(static_cast<std::uint32_t>(s)));
    const auto out = corners(output, f);
    for (const auto& p : out)
      if (CGAL::orientation(in[0], in[1], in[2], p) != CGAL::COPLANAR && kernel_traits<K>::exact_constructions) {
        problems.push_back(say("a vertex of output face ", std::size_t(f), " is not in the plane of input face ", s));
        break;
      }
    const Vector n_out = vector_area(out);
    if (!CGAL::is_positive(n_out * vector_area(in)))
      problems.push_back(say("output face ", std::size_t(f), " is not oriented like input face ", s));
    sum[s] = sum[s] + n_out;
    if (++terms[s] % 64 == 0) make_exact(sum[s]);
  }
  auto same = [](const Vector& s, const Vector& n) {
    if constexpr (kernel_traits<K>::exact_constructions) {
      return s == n;
    } else {
      const double err = std::sqrt(CGAL::to_double((s - n).squared_length()));
      return err <= 1e-9 * std::sqrt(CGAL::to_double(n.squared_length())) + 1e-300;
    }
  };
  // Per input face; where a flat contact's common triangulation spans several input faces of one
  // plane (its faces name the one holding their centroid), per plane: the input faces that do
  // not add up on their own are grouped by coplanarity (exact predicates), and each group's
  // output faces must add up to the group's area.
  std::vector<typename Mesh<K>::Face_index> unmatched;
  for (auto f : input.faces())
    if (!same(sum[std::size_t(f)], vector_area(corners(input, f)))) unmatched.push_back(f);
  std::vector<std::size_t> group(unmatched.size());
  for (std::size_t i = 0; i < unmatched.size(); ++i) {
    group[i] = i;
    const auto c = corners(input, unmatched[i]);
    for (std::size_t j = 0; j < i && group[i] == i; ++j) {
      const auto d = corners(input, unmatched[j]);
      if (CGAL::coplanar(c[0], c[1], c[2], d[0]) && CGAL::coplanar(c[0], c[1], c[2], d[1]) &&
          CGAL::coplanar(c[0], c[1], c[2], d[2]))
        group[i] = group[j];
    }
  }
  std::map<std::size_t, std::pair<Vector, Vector>> sums;  // group -> (output sum, input sum)
  for (std::size_t i = 0; i < unmatched.size(); ++i) {
    auto& [out_sum, in_sum] = sums.try_emplace(group[i], CGAL::NULL_VECTOR, CGAL::NULL_VECTOR).first->second;
    out_sum = out_sum + sum[std::size_t(unmatched[i])];
    in_sum = in_sum + vector_area(corners(input, unmatched[i]));
    if (i % 64 == 63) make_exact(out_sum), make_exact(in_sum);
  }
  for (const auto& [g, s] : sums)
    if (!same(s.first, s.second))
      problems.push_back(say("the new faces of input face ", std::size_t(unmatched[g]),
                             " (and of the faces in its plane that do not add up on their own) do not add up to its area"));
  return problems;
}

template <class K>
std::vector<std::string> check_vertex_moves(const Mesh<K>& input, const Mesh<K>& output, double tolerance) {
  std::vector<std::string> problems;
  for (auto v : input.vertices()) {
    const double d = std::sqrt(CGAL::to_double(CGAL::squared_distance(input.point(v), output.point(v))));
    if (d > tolerance * (1 + 1e-12)) problems.push_back(say("vertex ", std::size_t(v), " moved ", d));
  }
  return problems;
}

#define SEAM_INSTANTIATE(K)                                                                                   \
  template std::vector<std::string> check_valid_mesh<K>(const Mesh<K>&, bool);                               \
  template std::vector<std::string> check_curves_embedded<K>(const Mesh<K>&, const EmbedResult<K>&);         \
  template std::vector<std::string> check_same_surface<K>(const Mesh<K>&, const Mesh<K>&);                   \
  template std::vector<std::string> check_vertex_moves<K>(const Mesh<K>&, const Mesh<K>&, double);
SEAM_INSTANTIATE(Exact)
SEAM_INSTANTIATE(Filtered)
SEAM_INSTANTIATE(Float)
#undef SEAM_INSTANTIATE

}  // namespace seam
