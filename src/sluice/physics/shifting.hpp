// Particle shifting: a small displacement of every fluid particle, added to its position at the end of
// each step, away from where the particles are crowded and towards where they are sparse. It keeps
// the particles near a regular arrangement, and with them the pressure field smooth, where the flow
// would otherwise leave them disordered (after an impact, in a jet). It moves no mass and no momentum.
//
// The shift is Fickian (Lind et al. 2012, J. Comput. Phys. 231:1499), with the diffusion coefficient
// of Skillen et al. (2013), D = A h |v_i| dt, and the anti-clumping weight of Sun et al. (2017,
// delta-plus-SPH), so that
//   delta r_i = -A h |v_i| dt grad C^R_i          (grad C^R: physics/shifting_pair-inl.hpp).
// Free surface (Lind et al. 2012; Sun et al. 2017): a fluid particle whose position divergence div r
// is below the threshold (about Dim inside the water) has its support cut by the surface; it and every
// fluid particle within its support are "near the surface" and shift only along the surface: the
// component along the normal n = -grad C / |grad C| is removed, delta r <- (I - n n) delta r, so that
// the surface neither swells nor thins. Wall particles fill the support near walls, so walls are not
// taken for a free surface.
//
// The sums are computed on the positions of the step's last force evaluation; the shift is applied
// after the step's update (Solver::step). The other fields are not corrected for the displacement
// (as in DualSPHysics; Lind et al. correct them by a Taylor expansion).
#pragma once

#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <functional>
#include <vector>

#include "sluice/core/parallel.hpp"
#include "sluice/core/particles.hpp"
#include "sluice/neighbors/cell_grid.hpp"
#include "sluice/physics/rates.hpp"

namespace sluice {

struct ShiftingSettings {
  double coefficient = 0.0;        // A; 0 = off
  double surface_threshold = 1.5;  // div r below which a fluid particle is on the free surface
};

// Where a fluid particle is, for the shift.
enum class SurfaceZone : std::uint8_t { inside = 0, near_surface = 1, surface = 2 };

template <int Dim>
class ParticleShifting {
 public:
  // Computes the shift velocity s_i of every fluid particle (delta r_i = dt s_i) from the current
  // positions and velocities. `fluid` is 1 for fluid, 0 for wall particles; `grid` is binned on the
  // current particle order, which must not change before apply(). With several processes,
  // `refresh_divergence` gives the ghosts their owners' div r before the surface is found.
  void compute(const Particles<Dim>& p, const CellGrid<Dim>& grid, const AnyKernel<Dim>& kernel,
               const ShiftingSums& sums, const ShiftingSettings& settings, const double* fluid, int threads,
               const std::function<void(std::vector<double>&)>& refresh_divergence = {}) {
    const std::size_t n = p.size();
    std::array<double*, 2 * Dim + 1> out{};
    for (std::size_t k = 0; k < sums_.size(); ++k) {
      sums_[k].resize(n);
      out[k] = sums_[k].data();
    }
    shifting_sums(p, grid, kernel, sums, fluid, out, threads);
    if (refresh_divergence) refresh_divergence(sums_[2 * Dim]);
    classify(p, grid, sums.h, settings.surface_threshold, fluid, threads);
    const double scale = -settings.coefficient * sums.h;
    parallel::for_chunks(static_cast<long>(n), threads, [&](long begin, long end) {
      for (long i = begin; i < end; ++i) {
        std::array<double, Dim> s{};
        if (fluid[i] != 0.0) {
          double v2 = 0.0;
          for (int d = 0; d < Dim; ++d) v2 += p.velocity[d][i] * p.velocity[d][i];
          for (int d = 0; d < Dim; ++d) s[d] = scale * std::sqrt(v2) * sums_[Dim + d][i];
          if (zone_[i] != SurfaceZone::inside) remove_normal(s, static_cast<std::size_t>(i));
        }
        // grad C^R is not needed again: the shift takes its place.
        for (int d = 0; d < Dim; ++d) sums_[Dim + d][i] = s[d];
      }
    });
  }

  // x_i += dt s_i for every fluid particle (wall particles have s_i = 0).
  void apply(Particles<Dim>& p, double dt, int threads) const {
    parallel::for_chunks(static_cast<long>(p.size()), threads, [&](long begin, long end) { apply(p, dt, begin, end); });
  }
  // The same for the particles [begin, end).
  void apply(Particles<Dim>& p, double dt, long begin, long end) const {
    for (int d = 0; d < Dim; ++d) {
      double* __restrict x = p.position[d].data();
      const double* __restrict s = sums_[Dim + d].data();
      for (long i = begin; i < end; ++i) x[i] += dt * s[i];
    }
  }

  // After compute(), per particle: the zone, div r, and grad C (the surface normal's opposite).
  [[nodiscard]] const std::vector<SurfaceZone>& zone() const { return zone_; }
  [[nodiscard]] const std::vector<double>& divergence() const { return sums_[2 * Dim]; }
  [[nodiscard]] const std::vector<double>& concentration_gradient(int d) const { return sums_[d]; }
  // The shift velocity s (after compute(), until the next compute()).
  [[nodiscard]] const std::vector<double>& shift_velocity(int d) const { return sums_[Dim + d]; }
  // The same, to change before apply() (the wall-approach stop: geometry/leaks.hpp).
  [[nodiscard]] std::array<double*, Dim> shift_velocity_data() {
    std::array<double*, Dim> s{};
    for (int d = 0; d < Dim; ++d) s[d] = sums_[Dim + d].data();
    return s;
  }

 private:
  // Surface particles (div r below the threshold), then every fluid particle within the support of
  // one is near the surface.
  void classify(const Particles<Dim>& p, const CellGrid<Dim>& grid, double h, double threshold, const double* fluid,
                int threads) {
    const long n = static_cast<long>(p.size());
    zone_.assign(static_cast<std::size_t>(n), SurfaceZone::inside);
    const std::vector<double>& divr = sums_[2 * Dim];
    surface_.clear();
    for (long i = 0; i < n; ++i)
      if (fluid[i] != 0.0 && divr[i] < threshold) {
        zone_[i] = SurfaceZone::surface;
        surface_.push_back(static_cast<std::uint32_t>(i));
      }
    const double support2 = 4.0 * h * h;
    // Threads may mark the same particle; each writes the same value, through an atomic reference.
    parallel::for_each_dynamic(static_cast<long>(surface_.size()), threads, 64, [&](long k) {
      const std::uint32_t s = surface_[static_cast<std::size_t>(k)];
      grid.for_each_neighbor_range(grid.cell_of()[s], [&](std::uint32_t begin, std::uint32_t end) {
        for (std::uint32_t j = begin; j < end; ++j) {
          if (fluid[j] == 0.0) continue;
          double r2 = 0.0;
          for (int d = 0; d < Dim; ++d) {
            const double delta = p.position[d][s] - p.position[d][j];
            r2 += delta * delta;
          }
          if (r2 >= support2) continue;
          std::atomic_ref<SurfaceZone> z(zone_[j]);
          if (z.load(std::memory_order_relaxed) == SurfaceZone::inside) z.store(SurfaceZone::near_surface, std::memory_order_relaxed);
        }
      });
    });
  }

  // s <- (I - n n) s with n along grad C (a particle with grad C = 0 keeps s).
  void remove_normal(std::array<double, Dim>& s, std::size_t i) const {
    double g2 = 0.0, s_dot_g = 0.0;
    for (int d = 0; d < Dim; ++d) {
      g2 += sums_[d][i] * sums_[d][i];
      s_dot_g += s[d] * sums_[d][i];
    }
    if (!(g2 > 0.0)) return;
    for (int d = 0; d < Dim; ++d) s[d] -= s_dot_g / g2 * sums_[d][i];
  }

  // [0, Dim): grad C; [Dim, 2 Dim): grad C^R, then the shift velocity; 2 Dim: div r.
  std::array<std::vector<double>, 2 * Dim + 1> sums_;
  std::vector<SurfaceZone> zone_;
  std::vector<std::uint32_t> surface_;
};

}  // namespace sluice
