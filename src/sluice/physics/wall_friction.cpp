#include "sluice/physics/wall_friction.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "sluice/core/parallel.hpp"
#include "sluice/geometry/near_solids.hpp"
#include "sluice/physics/kernel.hpp"

namespace sluice {

namespace {
constexpr double kappa = 0.41;  // von Karman
constexpr double log_e = 9.793; // E, smooth wall
// Where u+ = y+ meets u+ = ln(E y+) / kappa.
constexpr double sublayer_edge = 11.53;
}  // namespace

double friction_velocity(double u, double y, double nu) {
  if (!(u > 0.0)) return 0.0;
  // The viscous sublayer: u = u_tau^2 y / nu.
  const double laminar = std::sqrt(nu * u / y);
  if (laminar * y / nu <= sublayer_edge) return laminar;
  // The log layer: g(s) = s ln(E y s / nu) - kappa u = 0. g is convex and increasing where
  // E y s / nu > 1/e, which holds from the sublayer's value on (E y+ > 100 there). Newton's method from
  // the larger of that value and the log law's root for u+ = 20 (one step of the fixed point
  // s = kappa u / ln(E y s / nu) from s = u / 20): the root is near it wherever y+ is from 10^2 to 10^4,
  // and after the first step the iterates descend to it from above.
  const double scale = log_e * y / nu;
  double s = std::max(laminar, kappa * u / std::log(scale * u / 20.0));
  for (int k = 0; k < 30; ++k) {
    const double l = std::log(scale * s);
    const double step = (s * l - kappa * u) / (l + 1.0);
    s -= step;
    // Quadratic convergence: after a step under 1e-6 s the error is of order 1e-12 s.
    if (std::abs(step) <= 1e-6 * s) break;
  }
  return s;
}

template <int Dim>
WallFrictionResult add_wall_friction(Particles<Dim>& p, const Solids<Dim>& solids,
                                     const WallFrictionSettings& settings, int threads, const SolidReach<Dim>* near,
                                     const std::uint8_t* skip) {
  const double reach = 2.0 * settings.h;
  if (near != nullptr && !(near->reach() >= reach))
    throw std::invalid_argument("add_wall_friction: the SolidReach's reach is below 2h");
  const CubicSpline<1> profile(settings.h);
  const double nu = settings.kinematic_viscosity;
  const double y_least = 0.1 * settings.dx;
  const std::vector<near_solids::Bounded<Dim>> boxes = near_solids::bounded<Dim>(solids, reach);
  // Adds the friction of every wall within 2h to particle i; true if one acted.
  const auto friction_on = [&](long i) -> bool {
    if (p.kind[i] != Kind::fluid || (skip != nullptr && skip[i] != 0)) return false;
    const Vec<Dim> x = near_solids::position_of(p, i);
    if (near != nullptr && near->clear(x)) return false;
    Vec<Dim> v{};
    for (int d = 0; d < Dim; ++d) v[d] = p.velocity[d][i];
    bool felt = false;
    for (const near_solids::Bounded<Dim>& b : boxes) {
      if (!near_solids::in_box<Dim>(b, x)) continue;
      // Outside the solid, the closest surface point q and the direction from it to x give the
      // distance and the wall's normal in one query; for a box (the tank's walls), q is x clamped
      // into it.
      Vec<Dim> off{};
      if (b.box) {
        for (int d = 0; d < Dim; ++d) off[d] = x[d] - std::clamp(x[d], b.solid_lower[d], b.solid_upper[d]);
        if (!(dot(off, off) > 0.0)) continue;  // inside the box, or on its surface
      } else {
        const SurfacePoint<Dim> q = b.solid->closest_surface_point(x);
        off = x - q.point;
        if (!(dot(off, q.normal) > 0.0)) continue;  // inside the solid, or on its surface
      }
      const double distance = norm(off);
      if (distance >= reach) continue;
      const Vec<Dim> normal = (1.0 / distance) * off;
      const Vec<Dim> relative = b.moving ? v - b.solid->velocity_at(x) : v;  // relative to the wall
      const Vec<Dim> tangential = relative - dot(relative, normal) * normal;
      const double u = norm(tangential);
      if (!(u > 0.0)) continue;
      const double y = std::max(distance, y_least);
      const double u_tau = friction_velocity(u, y, nu);
      const double f = 2.0 * profile.value(distance) * u_tau * u_tau / u;
      for (int d = 0; d < Dim; ++d) p.acceleration[d][i] -= f * tangential[d];
      felt = true;
    }
    return felt;
  };
  const long n = static_cast<long>(p.size());
  std::size_t felt_total = 0;
  double max_a2 = 0.0;
  parallel::for_chunks(n, threads, [&](long begin, long end) {
    std::size_t felt_here = 0;
    double max_a2_here = 0.0;
    for (long i = begin; i < end; ++i)
      if (friction_on(i)) {
        ++felt_here;
        double a2 = 0.0;
        for (int d = 0; d < Dim; ++d) a2 += p.acceleration[d][i] * p.acceleration[d][i];
        max_a2_here = std::max(max_a2_here, a2);
      }
#pragma omp critical(sluice_wall_friction)
    {
      felt_total += felt_here;
      max_a2 = std::max(max_a2, max_a2_here);
    }
  });
  return {felt_total, std::sqrt(max_a2)};
}

template WallFrictionResult add_wall_friction<2>(Particles<2>&, const Solids<2>&, const WallFrictionSettings&, int,
                                                 const SolidReach<2>*, const std::uint8_t*);
template WallFrictionResult add_wall_friction<3>(Particles<3>&, const Solids<3>&, const WallFrictionSettings&, int,
                                                 const SolidReach<3>*, const std::uint8_t*);

}  // namespace sluice
