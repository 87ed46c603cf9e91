// seam fuzzing: one libFuzzer target per entry function of fuzz_entry.h, chosen at compile time
// by SEAM_FUZZ_TARGET (fuzz/CMakeLists.txt builds off, obj, ply, stl, polylines and pair).
// SPDX-License-Identifier: GPL-3.0-or-later
#include "fuzz_entry.h"

#define SEAM_FUZZ_STR2(x) #x
#define SEAM_FUZZ_STR(x) SEAM_FUZZ_STR2(x)

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string target = SEAM_FUZZ_STR(SEAM_FUZZ_TARGET);
  if (target == "polylines") seam_fuzz::polyline_reader(data, size);
  else if (target == "pair") seam_fuzz::pair_pipeline(data, size);
  else seam_fuzz::mesh_reader(data, size, target.c_str());
  return 0;
}
