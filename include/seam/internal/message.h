// seam internal: one-line messages built from parts (17 significant digits for numbers).
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <sstream>
#include <string>

namespace seam::internal {

template <class... T> std::string say(const T&... parts) {
  std::ostringstream out;
  out.precision(17);
  (out << ... << parts);
  return out.str();
}

/// Adds `part` to a report's note, after "; " when the note already says something.
inline void append_note(std::string& note, const std::string& part) { note += (note.empty() ? "" : "; ") + part; }

}  // namespace seam::internal
