// Checkpoints: the complete state of a run (its case, clock and particles in their current order),
// from which `sluice run --restart` continues bit for bit. Binary, versioned, CRC-32 checked.
#pragma once

#include <filesystem>
#include <string>

#include "sluice/case/case.hpp"
#include "sluice/core/particles.hpp"
#include "sluice/simulation.hpp"

namespace sluice {

inline constexpr std::uint32_t checkpoint_format_version = 1;

struct Checkpoint {
  Case config;
  Clock clock;
  Particles<2> particles;
  double wall_seconds = 0.0;  // wall time of the run up to the checkpoint
};

std::string checkpoint_bytes(const Simulation& sim, double wall_seconds);
Checkpoint parse_checkpoint(const std::string& bytes, const std::string& source);
void write_checkpoint(const std::filesystem::path& path, const Simulation& sim, double wall_seconds);
Checkpoint read_checkpoint(const std::filesystem::path& path);

}  // namespace sluice
