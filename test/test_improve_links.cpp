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

TEST_CASE("improve: the predicate refuses a merge that would leave a curve spike", "[improve]") {
  // Curve 0-1-2-3-4, with 1, 2 and 3 one cluster (as where a curve zigzags within 1e-13): merging
  // 1 into 3 would make the curve pass 3, 2, 3 (a spike, segment (2, 3) twice); merging 1 into
  // its neighbour 2 is no spike. (An edit with no mesh parts: only the curve test decides.)
  State s;
  s.points.resize(5);
  add_curve(s, {0, 1, 2, 3, 4});
  seam::internal::Edit<seam::Exact> edit;
  edit.keeps_surface = true;
  edit.merged_point = 1;
  edit.merged_into = 3;
  CHECK(seam::internal::accept_edit(s, edit) == seam::internal::Verdict::shape);
  edit.merged_into = 2;
  CHECK(seam::internal::accept_edit(s, edit) == seam::internal::Verdict::accepted);
  // A closed curve of three points: any merge leaves a spike.
  State t;
  t.points.resize(3);
  add_curve(t, {0, 1, 2, 0});
  seam::internal::Edit<seam::Exact> closed;
  closed.keeps_surface = true;
  closed.merged_point = 0;
  closed.merged_into = 1;
  CHECK(seam::internal::accept_edit(t, closed) == seam::internal::Verdict::shape);
}
