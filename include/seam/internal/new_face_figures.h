// seam internal: the figures of a mesh's new faces (seam/quality.h) copied into its EmbedStats,
// the same way by seam embed, seam embed's quality stage and seam pair.
//
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <seam/embed.h>
#include <seam/quality.h>

namespace seam::internal {

/// The smallest angle, the counts below 10 and 20 degrees, the largest area and the faces above
/// the area bound. (The "unforced" count and the face counts are each caller's own.)
inline void record_new_face_figures(const NewFaceQuality& q, EmbedStats& st) {
  st.min_angle_deg_new = q.min_angle_deg;
  st.new_faces_below_10 = q.below_10;
  st.new_faces_below_20 = q.below_20;
  st.largest_new_area = q.largest_area;
  st.new_faces_above_max_area = q.above_max_area;
}

}  // namespace seam::internal
