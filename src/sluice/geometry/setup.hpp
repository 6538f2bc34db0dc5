// From a case to particles: the tank's walls and the solids filled to a depth of 2h, water regions
// filled on a lattice, near-coincident points removed, hydrostatic initial density.
#pragma once

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "sluice/case/case.hpp"
#include "sluice/core/particles.hpp"
#include "sluice/geometry/solid.hpp"

namespace sluice {

template <int Dim>
struct Setup {
  Particles<Dim> particles;
  Solids<Dim> solids;  // wall geometry, for leak detection
  std::size_t removed_near_coincident = 0;
  // What a user should know of how the case was filled: a water region that the lattice fills with
  // more than 1 % less (or more) water than it holds, near-coincident points removed. Each a sentence.
  std::vector<std::string> notes;
};

// Number of wall particle layers: enough to fill a depth of 2h at spacing dx.
int wall_layers(const Case& c);

// The solid of a region: a polygon in 2D (a box is a 4-point polygon there), a box or a mesh (its
// MeshSolid) in 3D.
template <int Dim>
std::shared_ptr<const Solid<Dim>> region_solid(const Region& r);

// An axis-aligned box [lower, upper] as a solid (a polygon in 2D).
template <int Dim>
std::shared_ptr<const Solid<Dim>> box_solid(const Vec<Dim>& lower, const Vec<Dim>& upper);

// Throws CaseError for a water region that holds no point of the lattice.
template <int Dim>
Setup<Dim> build_setup(const Case& c);

// Removes one point of every pair closer than `min_distance` (the fluid one when a fluid point sits on
// a wall point; none of a pair of wall points of two bodies when either body moves: moving[body] != 0).
// Returns how many were removed.
template <int Dim>
std::size_t remove_near_coincident(Particles<Dim>& p, double min_distance,
                                   const std::vector<std::uint8_t>& moving = {});

// Sets each particle's density to the hydrostatic value under the water above it (gravity along the
// up axis, the last one).
template <int Dim>
void set_hydrostatic_density(Particles<Dim>& p, const Case& c);

}  // namespace sluice
