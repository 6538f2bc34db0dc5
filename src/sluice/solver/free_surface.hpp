// The free surface on a vertical line, as the kernel sees it: what a surface gauge reads
// (io/probes.hpp) and what an absorbing piston measures in front of it (Solver::absorb).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <type_traits>
#include <variant>
#include <vector>

#include "sluice/core/vec.hpp"
#include "sluice/solver/solver.hpp"

namespace sluice {

// The free surface on the vertical line up from `point` as the kernel sees it: the water fraction
// phi(y) = sum_j (m / rho_j) W(x - x_j) over the fluid particles, sampled every dx/8 from the foot
// (point[up]) to a support above the highest particle within a support of the line (summed over
// processes); the level is the highest y where phi reaches 1/2, linear between the two samples around
// it (a flat surface of particles dx/2 below it gives phi = 1/2 there). Where phi never reaches 1/2
// (a dry bed, or water thinner than the kernel sees) the foot's height: no water over it.
template <int Dim>
double kernel_surface(const Solver<Dim>& solver, const Vec<Dim>& point) {
  constexpr int up = Dim - 1;
  const Particles<Dim>& p = solver.particles();
  const double step = 0.125 * solver.config().dx, foot = point[up];
  return std::visit(
      [&](const auto& kernel) -> double {
        const double support = std::decay_t<decltype(kernel)>::support * kernel.h;
        struct Near {
          double across2, y, volume;  // squared distance from the line, height, m / rho
        };
        std::vector<Near> near;
        Vec<Dim> lower = point, upper = point;
        for (int d = 0; d < up; ++d) lower[d] -= support, upper[d] += support;
        lower[up] = -std::numeric_limits<double>::infinity();
        upper[up] = std::numeric_limits<double>::infinity();
        double highest = -std::numeric_limits<double>::infinity();
        solver.for_each_range_in_box(lower, upper, [&](std::uint32_t begin, std::uint32_t end) {
          for (std::uint32_t i = begin; i < end; ++i) {
            if (!p.is_fluid(i)) continue;
            double across2 = 0.0;
            for (int d = 0; d < up; ++d) across2 += (p.position[d][i] - point[d]) * (p.position[d][i] - point[d]);
            if (across2 >= support * support) continue;
            near.push_back({across2, p.position[up][i], solver.particle_mass() / p.density[i]});
            highest = std::max(highest, p.position[up][i]);
          }
        });
        highest = solver.reducer().max(highest);
        if (!(highest + support > foot)) return foot;
        const auto samples = static_cast<std::size_t>(std::ceil((highest + support - foot) / step)) + 1;
        std::vector<double> phi(samples, 0.0);
        for (const Near& q : near) {
          const double reach = std::sqrt(support * support - q.across2);
          const double k0 = std::max(0.0, std::ceil((q.y - reach - foot) / step));
          const double k1 = std::min(static_cast<double>(samples - 1), std::floor((q.y + reach - foot) / step));
          for (auto k = static_cast<std::size_t>(k0); static_cast<double>(k) <= k1; ++k) {
            const double dy = foot + static_cast<double>(k) * step - q.y;
            phi[k] += q.volume * kernel.value(std::sqrt(q.across2 + dy * dy));
          }
        }
        phi = solver.reducer().sum(std::move(phi));
        for (std::size_t k = samples - 1; k > 0; --k)
          if (phi[k - 1] >= 0.5 && phi[k] < 0.5)
            return foot + step * (static_cast<double>(k - 1) + (phi[k - 1] - 0.5) / (phi[k - 1] - phi[k]));
        return foot;
      },
      solver.kernel());
}

}  // namespace sluice
