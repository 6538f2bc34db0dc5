// A wall's motion laws as the case gives them (MotionLawSpec) made a RigidMotion the solver moves it
// by. Part of the motion library, so that the solver needs nothing of the case reader.
#pragma once

#include "sluice/case/case.hpp"
#include "sluice/geometry/motion.hpp"

namespace sluice {

// The prescribed motion of a wall, from its laws (a rotation's degrees made radians).
template <int Dim>
RigidMotion<Dim> rigid_motion_of(const Region& wall);

}  // namespace sluice
