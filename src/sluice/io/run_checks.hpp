// What is checked before a run starts, so that a run that cannot finish is refused before it writes
// anything: the memory its particles need, its starting state, what it will write and the room for it.
#pragma once

#include <filesystem>
#include <string>

#include "sluice/case/case.hpp"
#include "sluice/core/communicator.hpp"
#include "sluice/simulation.hpp"

namespace sluice {

// A case whose particles would not fit in memory is refused (CaseError) before the set-up allocates
// them. Collective: the least memory of any process decides, for all of them alike.
void check_memory(const Case& c, const Communicator* comm);

// The state a run starts from passes the instability guard (Solver::check_health), or CaseError:
// `restart` names the checkpoint it came from (empty for a case at t = 0). Collective.
void check_start(const Simulation& sim, const std::filesystem::path& restart);

// Intervals shorter than a step and more frames than output.max_frames are refused (CaseError).
void check_output_plan(const Simulation& sim);

// The bytes of the frames a run plans to write from its current time to its end.
[[nodiscard]] double planned_frame_bytes(const Simulation& sim);

// The output directory (existing) has room for `bytes` of frames, or IoError.
void check_room(const std::filesystem::path& dir, double bytes, const Simulation& sim);

// A moving wall outside the tank, and "N particles are bad; the first:" with a line for each offender
// the check described.
[[nodiscard]] std::string describe_offenders(const Health& health);

}  // namespace sluice
