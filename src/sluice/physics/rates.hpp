// The pair loop, written once: for every particle i, gather over the neighbours j found by the cell
// grid and sum the pair terms of physics/pair_terms.hpp. Each i is summed by one thread in a fixed
// order, so results do not depend on the number of threads.
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

#include "sluice/core/particles.hpp"
#include "sluice/core/vec.hpp"
#include "sluice/neighbors/cell_grid.hpp"
#include "sluice/physics/eos.hpp"
#include "sluice/physics/pair_terms.hpp"

namespace sluice {

template <int Dim>
struct RateSettings {
  double mass;          // particle mass m
  double h;             // smoothing length
  double viscosity;     // mu
  double alpha;         // artificial viscosity
  double delta;         // density diffusion
  Vec<Dim> gravity;
  TaitEos eos;
};

// Per-particle terms computed once per evaluation instead of once per pair.
struct ParticleTerms {
  std::vector<double> pressure;
  std::vector<double> p_over_rho2;  // P / rho^2
  std::vector<double> inv_rho2;     // 1 / rho^2
  std::vector<double> inv_rho;      // 1 / rho
  std::vector<double> hydro_k;      // rho / c^2: d(rho)/d(P) for the hydrostatic density difference
  std::vector<double> fluid_mask;   // 1 for fluid, 0 for wall

  template <int Dim>
  void compute(const Particles<Dim>& p, const TaitEos& eos) {
    const std::size_t n = p.size();
    for (auto* v : {&pressure, &p_over_rho2, &inv_rho2, &inv_rho, &hydro_k, &fluid_mask}) v->resize(n);
    const double c0_2 = eos.sound_speed * eos.sound_speed;
    for (std::size_t i = 0; i < n; ++i) {
      const double rho = p.density[i];
      const double pressure_i = eos.pressure(rho);
      pressure[i] = pressure_i;
      inv_rho[i] = 1.0 / rho;
      inv_rho2[i] = inv_rho[i] * inv_rho[i];
      p_over_rho2[i] = pressure_i * inv_rho2[i];
      // c^2 = dP/drho = gamma (P + B) / rho
      const double c2 = eos.gamma * (pressure_i + eos.stiffness()) * inv_rho[i];
      hydro_k[i] = rho / std::max(c2, 1e-12 * c0_2);
      fluid_mask[i] = p.is_fluid(i) ? 1.0 : 0.0;
    }
  }
};

struct RateSummary {
  double max_acceleration = 0.0;    // over fluid particles, including gravity
  double max_relative_speed = 0.0;  // max |v_ij| over interacting pairs
  double max_density = 0.0;         // over all particles
};

// Fills p.acceleration (fluid) and p.density_rate (all particles).
template <int Dim, class Kernel>
RateSummary compute_rates(Particles<Dim>& p, const CellGrid<Dim>& grid, const Kernel& kernel,
                          const RateSettings<Dim>& s, const ParticleTerms& t, int threads) {
  const long n = static_cast<long>(p.size());
  const double support2 = Kernel::support * Kernel::support * s.h * s.h;
  const double min_r2 = 1e-18 * s.h * s.h;  // excludes i = j (and exactly coincident points)
  const double m = s.mass;
  const double c0 = s.eos.sound_speed;
  const double delta_h_c0 = s.delta * s.h * c0;
  const auto& cell_of = grid.cell_of();

  std::array<const double*, Dim> x{}, v{};
  std::array<double*, Dim> a{};
  for (int d = 0; d < Dim; ++d) {
    x[d] = p.position[d].data();
    v[d] = p.velocity[d].data();
    a[d] = p.acceleration[d].data();
  }
  const double* rho = p.density.data();
  const double* p_over_rho2 = t.p_over_rho2.data();
  const double* inv_rho2 = t.inv_rho2.data();
  const double* inv_rho = t.inv_rho.data();
  const double* hydro_k = t.hydro_k.data();
  const double* fluid_mask = t.fluid_mask.data();
  double* density_rate = p.density_rate.data();

  double max_accel2 = 0.0;
  double max_vij2 = 0.0;
  double max_rho = 0.0;

#pragma omp parallel for schedule(dynamic, 512) num_threads(threads) \
    reduction(max : max_accel2, max_vij2, max_rho)
  for (long i = 0; i < n; ++i) {
    max_rho = std::max(max_rho, rho[i]);
    std::array<double, Dim> xi{}, vi{};
    for (int d = 0; d < Dim; ++d) {
      xi[d] = x[d][i];
      vi[d] = v[d][i];
    }
    const double rho_i = rho[i];
    double drho = 0.0;

    if (fluid_mask[i] == 0.0) {
      // Wall particle: fixed, its density evolves by continuity with the fluid around it.
      grid.for_each_neighbor_range(cell_of[i], [&](std::uint32_t begin, std::uint32_t end) {
#pragma omp simd reduction(+ : drho)
        for (std::uint32_t j = begin; j < end; ++j) {
          double r2 = 0.0, v_dot_r = 0.0;
          for (int d = 0; d < Dim; ++d) {
            const double dx = xi[d] - x[d][j];
            r2 += dx * dx;
            v_dot_r += (vi[d] - v[d][j]) * dx;
          }
          const bool inside = r2 < support2 && r2 > min_r2;
          const double r = std::sqrt(r2);
          const double inv_r = inside ? 1.0 / r : 0.0;
          const double dW = inside ? kernel.derivative(r) : 0.0;
          drho += pair::continuity(m, dW, v_dot_r * inv_r);
        }
      });
      density_rate[i] = drho;
      continue;
    }

    const double pr_i = p_over_rho2[i];
    const double ir2_i = inv_rho2[i];
    const double k_i = hydro_k[i];
    std::array<double, Dim> acc{};
    double vij2_max = 0.0;
    grid.for_each_neighbor_range(cell_of[i], [&](std::uint32_t begin, std::uint32_t end) {
      double acc0 = 0.0, acc1 = 0.0, acc2 = 0.0;
#pragma omp simd reduction(+ : acc0, acc1, acc2, drho) reduction(max : vij2_max)
      for (std::uint32_t j = begin; j < end; ++j) {
        std::array<double, Dim> dx{}, vij{};
        double r2 = 0.0, v_dot_r = 0.0, vij2 = 0.0, g_dot_r = 0.0;
        for (int d = 0; d < Dim; ++d) {
          dx[d] = xi[d] - x[d][j];
          vij[d] = vi[d] - v[d][j];
          r2 += dx[d] * dx[d];
          v_dot_r += vij[d] * dx[d];
          vij2 += vij[d] * vij[d];
          g_dot_r += s.gravity[d] * dx[d];
        }
        const bool inside = r2 < support2 && r2 > min_r2;
        const double r = std::sqrt(r2);
        const double inv_r = inside ? 1.0 / r : 0.0;
        const double dW = inside ? kernel.derivative(r) : 0.0;

        const double along_e = pair::pressure(m, pr_i, p_over_rho2[j], dW) +
                               pair::artificial_viscosity(s.alpha, c0, s.h, m, v_dot_r, r2,
                                                          0.5 * (rho_i + rho[j]), dW);
        const double along_v = pair::laminar_viscosity(s.viscosity, m, ir2_i, inv_rho2[j], dW, inv_r);
        const double drho_hydro = -0.5 * (k_i + hydro_k[j]) * g_dot_r;  // rho_j^H - rho_i^H
        drho += pair::continuity(m, dW, v_dot_r * inv_r) +
                fluid_mask[j] * pair::density_diffusion(delta_h_c0, m, rho_i, rho[j], drho_hydro, dW, inv_r,
                                                        inv_rho[j]);
        acc0 += along_e * dx[0] * inv_r + along_v * vij[0];
        if constexpr (Dim > 1) acc1 += along_e * dx[1] * inv_r + along_v * vij[1];
        if constexpr (Dim > 2) acc2 += along_e * dx[2] * inv_r + along_v * vij[2];
        vij2_max = std::max(vij2_max, inside ? vij2 : 0.0);
      }
      acc[0] += acc0;
      if constexpr (Dim > 1) acc[1] += acc1;
      if constexpr (Dim > 2) acc[2] += acc2;
    });
    double accel2 = 0.0;
    for (int d = 0; d < Dim; ++d) {
      acc[d] += s.gravity[d];
      a[d][i] = acc[d];
      accel2 += acc[d] * acc[d];
    }
    density_rate[i] = drho;
    max_accel2 = std::max(max_accel2, accel2);
    max_vij2 = std::max(max_vij2, vij2_max);
  }
  return {std::sqrt(max_accel2), std::sqrt(max_vij2), max_rho};
}

// Shepard density filter (sum includes i = j): rho_i = sum_j m W_ij / sum_j (m/rho_j) W_ij, applied
// to fluid particles for which `select(i)` is true. `out` is scratch of size n.
template <int Dim, class Kernel, class Select>
void shepard_filter(Particles<Dim>& p, const CellGrid<Dim>& grid, const Kernel& kernel, double mass,
                    std::vector<double>& out, int threads, Select select) {
  const long n = static_cast<long>(p.size());
  const double support2 = Kernel::support * Kernel::support * kernel.h * kernel.h;
  const auto& cell_of = grid.cell_of();
  out.assign(p.density.begin(), p.density.end());
#pragma omp parallel for schedule(dynamic, 512) num_threads(threads)
  for (long i = 0; i < n; ++i) {
    if (!p.is_fluid(static_cast<std::size_t>(i)) || !select(static_cast<std::size_t>(i))) continue;
    double weighted_mass = 0.0, weighted_volume = 0.0;
    grid.for_each_neighbor_range(cell_of[i], [&](std::uint32_t begin, std::uint32_t end) {
      for (std::uint32_t j = begin; j < end; ++j) {
        double r2 = 0.0;
        for (int d = 0; d < Dim; ++d) {
          const double dx = p.position[d][i] - p.position[d][j];
          r2 += dx * dx;
        }
        if (r2 >= support2) continue;
        const double w = kernel.value(std::sqrt(r2));
        weighted_mass += mass * w;
        weighted_volume += mass / p.density[j] * w;
      }
    });
    out[i] = weighted_mass / weighted_volume;
  }
  p.density.swap(out);
}

}  // namespace sluice
