// A damping zone ([damping]): the end of a wave flume that absorbs the waves running into it instead
// of reflecting them. Across the zone, from the plane through `start` normal to `direction`, over
// `length`, the water's velocity relaxes at the rate strength s^2, s the depth into the zone over its
// length (0 at its start, 1 at its end and beyond): each step multiplies it by exp(-strength s^2 dt).
// The quadratic growth lets a wave enter without reflecting off the zone's start; the exponential
// never overshoots to a reversed velocity, whatever the strength and the step.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>

#include "sluice/case/case.hpp"
#include "sluice/core/parallel.hpp"
#include "sluice/core/particles.hpp"
#include "sluice/core/vec.hpp"

namespace sluice {

template <int Dim>
struct DampingZone {
  Vec<Dim> start{}, direction{};  // direction: a unit vector
  double length = 0.0, strength = 0.0;

  static DampingZone of(const Case& c) {
    DampingZone z;
    double norm2 = 0.0;
    for (int d = 0; d < Dim; ++d) norm2 += c.damping_direction[d] * c.damping_direction[d];
    const double inv = 1.0 / std::sqrt(norm2);
    for (int d = 0; d < Dim; ++d) {
      z.start[d] = c.damping_start[d];
      z.direction[d] = c.damping_direction[d] * inv;
    }
    z.length = c.damping_length;
    z.strength = c.damping_strength;
    return z;
  }

  // The factor on the velocity of water at x over a step dt.
  [[nodiscard]] double factor(const Vec<Dim>& x, double dt) const {
    double s = 0.0;
    for (int d = 0; d < Dim; ++d) s += (x[d] - start[d]) * direction[d];
    s /= length;
    if (!(s > 0.0)) return 1.0;
    s = std::min(s, 1.0);
    return std::exp(-strength * dt * s * s);
  }
};

// The zone applied to the water among the particles [begin, end) over a step dt.
template <int Dim>
void damp(Particles<Dim>& p, const DampingZone<Dim>& zone, double dt, long begin, long end) {
  for (long k = begin; k < end; ++k) {
    const auto i = static_cast<std::size_t>(k);
    if (!p.is_fluid(i)) continue;
    Vec<Dim> x{};
    for (int d = 0; d < Dim; ++d) x[d] = p.position[d][i];
    const double f = zone.factor(x, dt);
    for (int d = 0; d < Dim; ++d) p.velocity[d][i] *= f;
  }
}

// The zone applied to the first `owned` particles' water over a step dt.
template <int Dim>
void apply_damping(Particles<Dim>& p, std::size_t owned, const DampingZone<Dim>& zone, double dt, int threads) {
  parallel::for_chunks(static_cast<long>(owned), threads,
                       [&](long begin, long end) { damp(p, zone, dt, begin, end); });
}

}  // namespace sluice
