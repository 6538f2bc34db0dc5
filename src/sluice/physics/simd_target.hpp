// Which instruction set the pair loop runs on. The loop is compiled for several (Highway's targets:
// SSE4, AVX2, AVX3 = AVX-512, NEON, SVE, ... and EMU128, portable C++), and the best one the CPU
// supports is used unless another is asked for.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace sluice {

// The target in use, as Highway names it ("AVX2", "AVX3", "SSE4", "EMU128", ...).
std::string simd_target();

// The compiled targets this CPU can run, best first.
std::vector<std::string> available_simd_targets();

// Uses `name` (one of available_simd_targets(), case-insensitive) from now on, or the best again for
// "auto". Throws std::invalid_argument naming the available ones otherwise.
void use_simd_target(std::string_view name);

}  // namespace sluice
