// Checkpoints: the complete state of a run (its case, clock and particles in their current order),
// from which `sluice run --restart` continues bit for bit. Binary, versioned, CRC-32 checked.
//
// Layout (version 2, little-endian): "SLUICECK", u32 version, u32 dimension, u64 case length, the case
// as TOML, the clock (f64 time, i64 step, f64 last dt, i64 leaks, f64 wall seconds), u64 particle
// count, u32 field count, then per field: u16 name length, name, u8 element type (1 f64, 2 u8, 3 u32),
// u8 components, and its arrays component by component; last the CRC-32 of everything before it.
// The fields are those the particle registry marks `checkpoint` (core/particles.hpp).
#pragma once

#include <filesystem>
#include <string>

#include "sluice/case/case.hpp"
#include "sluice/simulation.hpp"

namespace sluice {

inline constexpr std::uint32_t checkpoint_format_version = 2;

struct Checkpoint {
  Case config;
  Clock clock;
  AnyParticles particles;
  double wall_seconds = 0.0;  // wall time of the run up to the checkpoint
};

std::string checkpoint_bytes(const Simulation& sim, double wall_seconds);
Checkpoint parse_checkpoint(const std::string& bytes, const std::string& source);
void write_checkpoint(const std::filesystem::path& path, const Simulation& sim, double wall_seconds);
Checkpoint read_checkpoint(const std::filesystem::path& path);

}  // namespace sluice
