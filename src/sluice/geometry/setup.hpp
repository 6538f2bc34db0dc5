// From a case to particles: water regions filled on a lattice, walls filled to a depth of 2h,
// near-coincident points removed, hydrostatic initial density.
#pragma once

#include <cstddef>
#include <vector>

#include "sluice/case/case.hpp"
#include "sluice/core/particles.hpp"
#include "sluice/geometry/polygon.hpp"

namespace sluice {

struct Setup {
  Particles<2> particles;
  std::vector<Polygon> solids;   // wall geometry, for leak detection
  Vec2 domain_lower{};           // bounding box of the walls
  Vec2 domain_upper{};
  std::size_t removed_near_coincident = 0;
};

// Number of wall particle layers: enough to fill a depth of 2h at spacing dx.
int wall_layers(const Case& c);

Setup build_setup(const Case& c);

// Removes one point of every pair closer than `min_distance` (the fluid one when a fluid point sits on
// a wall point). Returns how many were removed.
std::size_t remove_near_coincident(Particles<2>& p, double min_distance);

// Sets each particle's density to the hydrostatic value under the water above it (gravity along -y).
void set_hydrostatic_density(Particles<2>& p, const Case& c);

}  // namespace sluice
