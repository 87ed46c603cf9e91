// seam fuzzing: the entry functions of fuzz_entry.h compiled once for every libFuzzer target
// (fuzz/fuzz_target.cpp only names its target), so that the heavy CGAL code is not compiled six
// times.
// SPDX-License-Identifier: GPL-3.0-or-later
#include "fuzz_dispatch.h"
#include "fuzz_entry.h"

#include <string>

namespace seam_fuzz {

int run_target(const char* target_name, const std::uint8_t* data, std::size_t size) {
  const std::string target = target_name;
  if (target == "polylines") polyline_reader(data, size);
  else if (target == "pair") pair_pipeline(data, size);
  else mesh_reader(data, size, target.c_str());
  return 0;
}

}  // namespace seam_fuzz
