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

}  // namespace seam::internal
