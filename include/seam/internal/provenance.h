// seam internal: which input face each face comes from once faces were cut before the
// embedding (pair's edge snapping, textile's triple points). embed's source_face_property then
// refers to the cut mesh; apply() maps it back to the input faces, counts the faces of cut faces
// as new, and measures the new faces against the input faces' own smallest angles.
//
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <seam/embed.h>
#include <seam/quality.h>
#include <seam/types.h>

#include <cstddef>
#include <cstdint>
#include <vector>

namespace seam::internal {

struct FaceProvenance {
  std::vector<std::uint32_t> origin;    ///< input face, by face of the cut mesh (empty: not started)
  std::vector<char> reshaped;           ///< cut (its faces count as new)
  std::vector<double> input_min_angle;  ///< by input face

  /// Records the input faces (once: does nothing when already started).
  template <class K> void start(const Mesh<K>& input) {
    if (!origin.empty()) return;
    for (auto f : input.faces()) {
      const auto h = input.halfedge(f);
      input_min_angle.push_back(min_angle_deg(input.point(input.source(h)), input.point(input.target(h)),
                                              input.point(input.target(input.next(h)))));
      origin.push_back(std::uint32_t(std::size_t(f)));
    }
    reshaped.assign(origin.size(), 0);
  }
  /// Faces from index `first` to `count` - 1 were cut from face `from` (which is reshaped too).
  void added(std::size_t first, std::size_t count, std::size_t from) {
    origin.resize(count, 0);
    reshaped.resize(count, 0);
    for (std::size_t f = first; f < count; ++f) origin[f] = origin[from], reshaped[f] = 1;
    reshaped[from] = 1;
  }
  /// Maps the output's source faces back to input faces, marks faces from cut faces new, and
  /// measures the new faces again.
  template <class K> void apply(Mesh<K>& out, EmbedStats& st) const {
    auto source = out.template property_map<typename Mesh<K>::Face_index, std::uint32_t>(source_face_property).first;
    auto is_new = out.template property_map<typename Mesh<K>::Face_index, bool>(new_face_property).first;
    for (auto f : out.faces()) {
      const std::size_t s = source[f];
      if (s < reshaped.size() && reshaped[s]) is_new[f] = true;
      if (s < origin.size()) source[f] = origin[s];
    }
    const auto q = new_face_quality<K>(out, &input_min_angle);
    st.min_angle_deg_new = q.min_angle_deg;
    st.new_faces_below_10 = q.below_10;
    st.new_faces_below_20 = q.below_20;
    st.new_faces_below_10_unforced = q.below_10_unforced;
    st.faces_added = q.new_faces;
  }
};

}  // namespace seam::internal
