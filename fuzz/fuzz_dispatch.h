// seam fuzzing: run one fuzz entry (fuzz_entry.h) by its target name: off, obj, ply, stl,
// polylines or pair.
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <cstddef>
#include <cstdint>

namespace seam_fuzz {
int run_target(const char* target, const std::uint8_t* data, std::size_t size);
}
