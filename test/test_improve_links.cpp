// Tests of the quality stage's curve bookkeeping: the linked positions of the curves along their
// points stay consistent when a segment is split.
#include <catch2/catch.hpp>

#include <seam/internal/improve_state.h>

#include <vector>

namespace {

using State = seam::internal::ImproveState<seam::Exact>;

/// Appends an open curve through the given points, linking its nodes and segments.
void add_curve(State& s, const std::vector<int>& points) {
  const int curve = int(s.curves.size());
  s.curves.emplace_back();
  int prev = -1;
  for (const int p : points) {
    const int node = int(s.nodes.size());
    s.nodes.push_back({p, prev, -1, curve});
    s.points[std::size_t(p)].nodes.push_back(node);
    if (prev >= 0) {
      s.nodes[std::size_t(prev)].next = node;
      const int a = s.nodes[std::size_t(prev)].point;
      s.segment_node[{std::min(a, p), std::max(a, p)}] = prev;
    }
    if (s.curves.back().first < 0) s.curves.back().first = node;
    prev = node;
  }
}

/// The points of curve c, from its first node.
std::vector<int> walk(const State& s, int c) {
  std::vector<int> out;
  for (int n = s.curves[std::size_t(c)].first; n >= 0; n = s.nodes[std::size_t(n)].next) out.push_back(s.nodes[std::size_t(n)].point);
  return out;
}

}  // namespace

TEST_CASE("improve: splitting a segment that two curves share splits it in both", "[improve]") {
  // Two curves run along the segment (1, 2), one of them backwards, as after a merge closed a
  // lens between them; point 5 splits it.
  State s;
  s.points.resize(6);
  add_curve(s, {0, 1, 2});
  add_curve(s, {4, 2, 1, 3});
  seam::internal::split_curve_links(s, 1, 2, 5);
  CHECK(walk(s, 0) == std::vector<int>{0, 1, 5, 2});
  CHECK(walk(s, 1) == std::vector<int>{4, 2, 5, 1, 3});
  CHECK(s.segment_node.count({1, 2}) == 0);
  REQUIRE(s.segment_node.count({1, 5}) == 1);
  REQUIRE(s.segment_node.count({2, 5}) == 1);
  CHECK(s.points[5].nodes.size() == 2);
  // Every node's neighbours point back at it.
  for (std::size_t n = 0; n < s.nodes.size(); ++n) {
    const auto& node = s.nodes[n];
    if (node.next >= 0) CHECK(s.nodes[std::size_t(node.next)].prev == int(n));
    if (node.prev >= 0) CHECK(s.nodes[std::size_t(node.prev)].next == int(n));
  }
}

TEST_CASE("improve: splitting a segment of one curve links the new point once", "[improve]") {
  State s;
  s.points.resize(4);
  add_curve(s, {0, 1, 2});
  seam::internal::split_curve_links(s, 2, 1, 3);
  CHECK(walk(s, 0) == std::vector<int>{0, 1, 3, 2});
  CHECK(s.points[3].nodes.size() == 1);
  CHECK(s.segment_node.count({1, 2}) == 0);
  CHECK_THROWS_AS(seam::internal::split_curve_links(s, 0, 2, 3), seam::InternalError);
}

TEST_CASE("improve: the predicate refuses an edit that removes a curve point's vertex", "[improve]") {
  // A 3 x 3 grid of vertices, each square split along its diagonal: the centre's star is six
  // faces. An edit that replaces that star removes the centre (the corners of the star keep faces
  // outside it). Seen on generator cell 23: a merge of two close curve points took a third one
  // between them with it, and that point lost its vertex in one mesh.
  using M = seam::Mesh<seam::Exact>;
  using P = seam::Exact::Point_3;
  M g;
  std::vector<M::Vertex_index> v;
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) v.push_back(g.add_vertex(P(i, j, 0)));
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 2; ++i) {
      const auto a = v[std::size_t(3 * j + i)], b = v[std::size_t(3 * j + i + 1)], c = v[std::size_t(3 * j + i + 4)],
                 d = v[std::size_t(3 * j + i + 3)];
      REQUIRE(g.add_face(a, b, c) != M::null_face());
      REQUIRE(g.add_face(a, c, d) != M::null_face());
    }
  const auto centre = v[4];
  State s;
  s.meshes.resize(1);
  s.meshes[0].mesh = &g;
  s.meshes[0].point = g.add_property_map<M::Vertex_index, std::int32_t>("v:point", -1).first;
  seam::internal::Edit<seam::Exact> edit;
  edit.parts.emplace_back();
  for (const auto f : CGAL::faces_around_target(g.halfedge(centre), g)) edit.parts[0].removed.push_back(f);
  REQUIRE(edit.parts[0].removed.size() == 6);
  CHECK(seam::internal::keeps_curve_points(s, edit));  // no curve point at all
  s.meshes[0].point[v[1]] = 7;  // a corner of the star on a curve: it keeps its other faces
  CHECK(seam::internal::keeps_curve_points(s, edit));
  s.meshes[0].point[centre] = 5;  // the centre on a curve: removed with the star
  CHECK_FALSE(seam::internal::keeps_curve_points(s, edit));
  edit.merged_point = 5;  // unless it is the point the edit merges away
  CHECK(seam::internal::keeps_curve_points(s, edit));
}
