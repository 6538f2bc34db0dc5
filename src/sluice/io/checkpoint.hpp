// Checkpoints: the complete state of a run (its case, clock and particles in their current order),
// from which `sluice run --restart` continues bit for bit. Binary, versioned, CRC-32 checked.
//
// Layout (version 7, little-endian): "SLUICECK", u32 version, u32 dimension, u64 case length, the case
// as TOML, the clock (f64 time, i64 step, f64 last dt, i64 leaks, f64 wall seconds), u8 rates carried
// (0 or 1: the leapfrog's rates of the current state, Clock::rates_carried) and when 1 their summary
// (f64 max acceleration, f64 max relative speed, f64 max density, f64 min fluid distance), i64 outflow
// (fluid particles removed after leaving an open tank: the ids run below the particle count plus
// this), u32 n and n f64 (the absorbing pistons' states, Clock::absorbers), u32 n and n f64 (the
// floating bodies' states, Clock::floating), u64 particle count, u32
// field count, then per field: u16 name length, name, u8 element type (1 f64, 2 u8, 3 u32), u8
// components, and its arrays component by component; last the CRC-32 of everything before it.
// The fields are those the particle registry marks `checkpoint` (core/particles.hpp), and when the
// rates are carried those it marks `carried` (acceleration, density_rate).
//
// Version 6 is version 7 without the floating bodies' states (none). Version 5 is version 6 without the absorbing pistons' states (none). Version 4 is version 5 without
// the body field (the solver gives each particle its body from the case, by id). Version 3 is version
// 4 without the outflow (none), version 2 is version 3 without the rates-carried byte (and so without
// carried rates): their files, from before outflow and before the leapfrog, are read as well.
#pragma once

#include <filesystem>
#include <string>
#include <string_view>

#include "sluice/case/case.hpp"
#include "sluice/io/npz.hpp"  // ByteSink
#include "sluice/simulation.hpp"

namespace sluice {

inline constexpr std::uint32_t checkpoint_format_version = 7;
// The largest step, leak or outflow count a checkpoint may hold: 2^53, far above any run's and far
// below the largest 64-bit integer, so that a run's own counts add to it without overflow.
inline constexpr std::int64_t kLargestCount = std::int64_t{1} << 53;

struct Checkpoint {
  Case config;
  Clock clock;
  AnyParticles particles;
  double wall_seconds = 0.0;  // wall time of the run up to the checkpoint
};

// With several processes: collective; every process's particles, on the root in particle-id order
// (the other processes write nothing: `out` is called on the root only, and checkpoint_bytes gives
// them ""; write_checkpoint writes on the root only). write_checkpoint_bytes streams the checkpoint
// to `out`, the particles' arrays without a copy.
void write_checkpoint_bytes(const Simulation& sim, double wall_seconds, const ByteSink& out);
std::string checkpoint_bytes(const Simulation& sim, double wall_seconds);
Checkpoint parse_checkpoint(const std::string& bytes, const std::string& source);
// Whether a checkpoint's bytes end in the CRC-32 of all that comes before them (parse_checkpoint's
// first check), for files of any size.
bool checkpoint_checksum_matches(std::string_view bytes);
void write_checkpoint(const std::filesystem::path& path, const Simulation& sim, double wall_seconds);
Checkpoint read_checkpoint(const std::filesystem::path& path);

}  // namespace sluice
