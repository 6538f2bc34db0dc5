// A wall's motion laws as the case gives them (MotionLawSpec) made a RigidMotion the solver moves it
// by. Part of the motion library, so that the solver needs nothing of the case reader.
#pragma once

#include "sluice/case/case.hpp"
#include "sluice/geometry/motion.hpp"
#include "sluice/geometry/wave_theory.hpp"

namespace sluice {

// The prescribed motion of a wall, from its laws (a rotation's degrees made radians). An absorbing
// piston (law = "absorber", or "wave" with absorb = true) gets its AbsorbingLaw, with gravity `g`, and
// measures the surface `gauge_distance` in front of its face.
template <int Dim>
RigidMotion<Dim> rigid_motion_of(const Region& wall, double g = waves::kGravity, double gauge_distance = 0.0);

}  // namespace sluice
