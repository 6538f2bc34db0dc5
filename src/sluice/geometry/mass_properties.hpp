// The volume, centroid and second moments of a solid region's shape (a box, a 2D polygon, a 3D
// closed triangle mesh), for a floating body of uniform density: what its mass, centre of gravity
// and inertia are when the case does not give them.
#pragma once

#include <array>

#include "sluice/case/case.hpp"

namespace sluice {

struct MassProperties {
  double volume = 0.0;  // m^3; in 2D the area, m^2 (per metre of depth)
  Vec3 centroid{};
  // The inertia tensor per unit density about the centroid, I = int (|r|^2 1 - r r^T) dV: rows xx, yy,
  // zz, xy, xz, yz. In 2D only zz (the polar moment of the area) is used.
  std::array<double, 6> inertia{};
};

// Of the region's shape in a case of `dimension` (its mesh loaded, for a mesh).
MassProperties mass_properties(const Region& region, int dimension);

}  // namespace sluice
