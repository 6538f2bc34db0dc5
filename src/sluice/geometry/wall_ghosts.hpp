// The ghost node of each wall particle for the modified dynamic boundary (mDBC, English et al. 2022,
// physics/mdbc.hpp): the wall particle's mirror image through the wall surface nearest to it, seen
// from the water, x_g = 2 q - x_w with q that surface point. At a concave corner q is the corner, so
// the ghost is mirrored through it.
//
// q is the nearest point of any face that water touches: the faces of the tank's inside (a box, open
// at the top without a lid) and of every wall region (case [[wall]]), each taken at its point nearest
// to the particle, counted only if the water side of it is water — just past q, away from the
// particle, lies inside the tank and in no wall region. So a face covered by another solid (the
// floor under an obstacle) does not count, and a particle in the floor next to the obstacle's foot is
// mirrored through the corner between them. A wall particle with no such point has no ghost: it faces
// no water. A moving wall (one with a motion law) covers nothing, and its own particles are mirrored
// through its own faces only; their ghost nodes are those of the start pose, which the solver carries
// with the body.
//
// `p` holds the particles as the set-up built them (walls at their start pose).
#pragma once

#include <cstdint>
#include <vector>

#include "sluice/case/case.hpp"
#include "sluice/core/particles.hpp"
#include "sluice/core/vec.hpp"

namespace sluice {

template <int Dim>
struct WallGhosts {
  // By particle id: the ghost node of a wall particle, and whether it has one.
  std::vector<Vec<Dim>> node;
  std::vector<std::uint8_t> has;

  [[nodiscard]] bool of(std::uint32_t id) const { return id < has.size() && has[id] != 0; }
};

template <int Dim>
WallGhosts<Dim> wall_ghosts(const Particles<Dim>& p, const Case& c);

}  // namespace sluice
