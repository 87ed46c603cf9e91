// seam fuzzing: one libFuzzer target per entry function of fuzz_entry.h, chosen at compile time
// by SEAM_FUZZ_TARGET (fuzz/CMakeLists.txt builds off, obj, ply, stl, polylines and pair); the
// entries themselves are compiled once (fuzz_dispatch.cpp).
// SPDX-License-Identifier: GPL-3.0-or-later
#include "fuzz_dispatch.h"

#define SEAM_FUZZ_STR2(x) #x
#define SEAM_FUZZ_STR(x) SEAM_FUZZ_STR2(x)

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  return seam_fuzz::run_target(SEAM_FUZZ_STR(SEAM_FUZZ_TARGET), data, size);
}
