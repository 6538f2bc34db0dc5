// The motion of the walls at the time of a force evaluation, as the wall treatments and the
// continuity equation read it: each body's state (geometry/motion.hpp) by body id (core/particles.hpp,
// body_id), and whether it moves. A wall particle of a fixed body is at rest.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <variant>
#include <vector>

#include "sluice/core/parallel.hpp"
#include "sluice/core/particles.hpp"
#include "sluice/core/vec.hpp"
#include "sluice/geometry/motion.hpp"
#include "sluice/neighbors/cell_grid.hpp"
#include "sluice/physics/kernel.hpp"

namespace sluice {

template <int Dim>
struct WallMotion {
  std::vector<std::uint8_t> moving;    // by body id: 1 if the body moves
  std::vector<BodyState<Dim>> state;   // by body id: its pose and rates now (at rest for a fixed body)
  bool any = false;                    // any body moves
  // Where the moving walls are now: each moving body's bounding box (MovingSolid), by body id.
  std::vector<Vec<Dim>> lower, upper;

  [[nodiscard]] bool moves(std::uint8_t body) const { return body < moving.size() && moving[body] != 0; }
  // The velocity and acceleration of wall particle i (zero for a fixed body's).
  [[nodiscard]] Vec<Dim> velocity(const Particles<Dim>& p, std::size_t i) const {
    return moves(p.body[i]) ? motion_at<Dim>(state[p.body[i]], position(p, i)).velocity : Vec<Dim>{};
  }
  [[nodiscard]] Vec<Dim> acceleration(const Particles<Dim>& p, std::size_t i) const {
    return moves(p.body[i]) ? motion_at<Dim>(state[p.body[i]], position(p, i)).acceleration : Vec<Dim>{};
  }

 private:
  static Vec<Dim> position(const Particles<Dim>& p, std::size_t i) {
    Vec<Dim> x{};
    for (int d = 0; d < Dim; ++d) x[d] = p.position[d][i];
    return x;
  }
};

// The continuity equation's part of the walls' own motion. The pair loop sees every wall particle at
// rest (physics/wcsph_pair-inl.hpp: a wall treatment's velocity is for the viscous terms), which
// costs walls at rest nothing; a moving wall particle j adds, for each fluid particle i within the
// kernel's support,
//   to i:  -m (u_j . grad_i W_ij),     to j (its density integrated: dynamic walls):  +m (u_j . grad_i W_ij),
// so that the pair's relative velocity is v_i - u_j; the walls' part only when their density is
// integrated (`walls_integrated`: dynamic walls; mDBC and Adami set it from the water instead). Only
// the particles within the support of a moving body's bounding box are visited; each particle's
// additions are summed by one thread in cell order (no races, the same bits on any thread count). The
// grid must be binned on the current order.
template <int Dim, class Kernel>
void add_moving_wall_continuity(Particles<Dim>& p, const CellGrid<Dim>& grid, const Kernel& kernel, double mass,
                                const WallMotion<Dim>& motion, bool walls_integrated, int threads) {
  if (!motion.any) return;
  const double support = Kernel::support * kernel.h, support2 = support * support;
  // The moving bodies' boxes, grown by the support.
  std::vector<std::array<Vec<Dim>, 2>> near;
  for (std::size_t b = 0; b < motion.moving.size(); ++b) {
    if (!motion.moving[b]) continue;
    std::array<Vec<Dim>, 2> box{motion.lower[b], motion.upper[b]};
    for (int d = 0; d < Dim; ++d) {
      box[0][d] -= support;
      box[1][d] += support;
    }
    near.push_back(box);
  }
  // The moving walls' particles before each (sorted) index: a fluid particle passes over the ranges
  // of its neighbour cells that hold none.
  std::vector<std::uint32_t> moving_before(p.size() + 1, 0);
  for (std::size_t k = 0; k < p.size(); ++k)
    moving_before[k + 1] = moving_before[k] + (!p.is_fluid(k) && motion.moves(p.body[k]) ? 1u : 0u);
  parallel::for_each_dynamic(static_cast<long>(p.size()), threads, 256, [&](long index) {
    const auto i = static_cast<std::size_t>(index);
    const bool fluid = p.is_fluid(i);
    if (!fluid && (!walls_integrated || !motion.moves(p.body[i]))) return;
    Vec<Dim> xi{};
    for (int d = 0; d < Dim; ++d) xi[d] = p.position[d][i];
    const bool close = std::any_of(near.begin(), near.end(), [&](const auto& box) {
      for (int d = 0; d < Dim; ++d)
        if (!(xi[d] >= box[0][d] && xi[d] <= box[1][d])) return false;
      return true;
    });
    if (!close) return;
    const Vec<Dim> ui = fluid ? Vec<Dim>{} : motion.velocity(p, i);
    double sum = 0.0;
    grid.for_each_neighbor_range(grid.cell_of()[i], [&](std::uint32_t begin, std::uint32_t end) {
      if (fluid && moving_before[end] == moving_before[begin]) return;
      for (std::uint32_t j = begin; j < end; ++j) {
        // Fluid i with a moving wall j; a moving wall i with fluid j.
        if (fluid ? (p.is_fluid(j) || !motion.moves(p.body[j])) : !p.is_fluid(j)) continue;
        Vec<Dim> r{};
        double r2 = 0.0;
        for (int d = 0; d < Dim; ++d) {
          r[d] = xi[d] - p.position[d][j];
          r2 += r[d] * r[d];
        }
        if (!(r2 < support2) || r2 == 0.0) continue;
        const double rr = std::sqrt(r2);
        const double F = kernel.gradient_factor(rr, 1.0 / rr);  // grad_i W_ij = F r_ij
        const Vec<Dim> u = fluid ? motion.velocity(p, j) : ui;
        // i fluid: -m u_j . F r_ij; i a wall: +m u_i . F r_ij (r_ij from the wall to the fluid: the same
        // pair term as the fluid's, with the sign of the pair's other side).
        sum += (fluid ? -mass : mass) * F * dot(u, r);
      }
    });
    p.density_rate[i] += sum;
  });
}

}  // namespace sluice
