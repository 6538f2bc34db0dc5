// Leak handling: a fluid particle found inside a solid wall is put back on the fluid side, half a
// particle spacing from the wall surface, with the normal component of its velocity relative to the
// wall (Solid::velocity_at: zero unless the wall moves) reversed; its
// density is re-interpolated from its neighbours at the next force evaluation. Never deleted.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "sluice/core/particles.hpp"
#include "sluice/geometry/near_solids.hpp"
#include "sluice/geometry/solid.hpp"

namespace sluice {

// Where no solid is near: a grid of cells over a box, each cell marked clear when every point of it
// is outside every solid and further than `reach` from its surface. A cell is clear when the signed
// distance at its centre, less half the cell's diagonal, exceeds `reach` for every solid: a distance
// changes by at most the distance moved. Built once for the solids (which do not move); the leak and
// wall-approach checks then skip the particles in clear cells, most of the water, instead of asking
// each solid for each particle's distance at every step. A point outside the box, or one that is not
// a number, is never clear. Default-constructed, nothing is clear.
template <int Dim>
class SolidReach {
 public:
  SolidReach() = default;
  // `cell` is enlarged if the box would need more than `max_cells` cells.
  SolidReach(const Solids<Dim>& solids, const Vec<Dim>& lower, const Vec<Dim>& upper, double cell, double reach,
             std::size_t max_cells = std::size_t{1} << 22);

  // The lookup, its numbers in a value of its own that a loop can keep in registers. Without
  // branches: a point outside the box (or not a number) reads cell 0 and is not clear.
  struct Lookup {
    Vec<Dim> lower{};
    std::array<double, Dim> extent{};  // the cell counts, as doubles
    std::array<int, Dim> count{};
    double inv_cell = 0.0;
    const std::uint8_t* clear = nullptr;

    [[nodiscard]] bool operator()(const Vec<Dim>& x) const {
      bool inside = clear != nullptr;
      std::int64_t c = 0;
      for (int d = Dim - 1; d >= 0; --d) {
        const double u = (x[d] - lower[d]) * inv_cell;
        const bool in = u >= 0.0 && u < extent[d];
        inside = inside && in;
        c = c * count[d] + static_cast<int>(in ? u : 0.0);
      }
      return inside && clear[inside ? c : 0] != 0;
    }
  };
  [[nodiscard]] Lookup lookup() const {
    Lookup l;
    l.lower = lower_;
    for (int d = 0; d < Dim; ++d) l.extent[d] = static_cast<double>(count_[d]);
    l.count = count_;
    l.inv_cell = inv_cell_;
    l.clear = clear_.empty() ? nullptr : clear_.data();
    return l;
  }
  [[nodiscard]] bool clear(const Vec<Dim>& x) const { return lookup()(x); }
  // The cells near `moving` (solids that go where the water takes them: floating bodies) where they
  // are now, besides the cells near the solids it was built with; the previous call's marks are
  // undone first. Only the cells around each solid's bounding box are visited.
  void update(const std::vector<const Solid<Dim>*>& moving);
  [[nodiscard]] double reach() const { return reach_; }
  // The fraction of the cells that are clear (for tests and diagnostics).
  [[nodiscard]] double clear_fraction() const;

 private:
  Vec<Dim> lower_{};
  std::array<int, Dim> count_{};
  double inv_cell_ = 0.0;
  double reach_ = 0.0;
  double cell_ = 0.0;
  std::vector<std::uint8_t> clear_;
  std::vector<std::size_t> marked_;  // the cells the last update() marked, clear without it
};

// Returns the number of particles put back. With `near`, only particles outside its clear cells are
// checked (its reach must be at least 0).
template <int Dim>
std::size_t put_back_leaked(Particles<Dim>& p, const Solids<Dim>& solids, double dx, int threads = 1,
                            const SolidReach<Dim>* near = nullptr);

// No penetration (physics.wall_no_penetration; the idea of DualSPHysics 5.4's mDBC penetration
// control, on the walls' geometry): before a drift, a fluid particle closer than dx/4 to a wall surface
// whose drift velocity relative to the wall, u = v + tau a - u_wall, points into it (u.n < 0, n the
// surface's outward normal)
// loses the part f (u.n) n of its velocity, f = 1 - 4 d/dx clamped to [0, 2] at signed distance d:
// nothing at dx/4 (water at rest sits at dx/2), the approach stopped at the surface, reflected a
// quarter spacing inside. tau a is the acceleration the drift adds (the leapfrog's half kick; else
// none). Returns the number of particles changed. With `near` (its reach at least dx/4), only
// particles outside its clear cells are checked.
template <int Dim>
std::size_t stop_wall_approach(Particles<Dim>& p, const Solids<Dim>& solids, double dx,
                               const typename Particles<Dim>::template Vector<double>* acceleration, double tau,
                               int threads = 1, const SolidReach<Dim>* near = nullptr);

// The same stop for particle shifting's displacement dt s (physics/shifting.hpp), applied to the shift
// velocity s before the shift: the shift of a fluid particle closer than dx/4 to a wall surface loses
// its part into the wall, as the drift velocity's does.
template <int Dim>
std::size_t stop_shift_approach(Particles<Dim>& p, const std::array<double*, Dim>& shift_velocity,
                                const Solids<Dim>& solids, double dx, int threads = 1,
                                const SolidReach<Dim>* near = nullptr);

// The put-back and the stops above over a range of particles, for a sweep of the caller's that does
// more with each block of particles while it is in cache (the leapfrog folds them into its kick and
// drift and its final kick: solver/solver_impl.hpp). Each does to the particles [begin, end) what the
// function of the same name does to them, and returns how many it changed. A particle away from every
// solid (most of the water) is passed over by a test of a few operations; with `near_cells` (its
// reach at least dx/4), every particle in one of its clear cells is.
template <int Dim>
class WallChecks {
 public:
  WallChecks(const Solids<Dim>& solids, double dx, const SolidReach<Dim>* near_cells);

  // Less the particles `skip` marks, if given (another process's ghosts, which their owner checks).
  long put_back(Particles<Dim>& p, long begin, long end, const std::uint8_t* skip = nullptr) const;
  long stop_approach(Particles<Dim>& p, long begin, long end,
                     const typename Particles<Dim>::template Vector<double>* acceleration, double tau) const;
  long stop_shift(const Particles<Dim>& p, const std::array<double*, Dim>& shift_velocity, long begin,
                  long end) const;

 private:
  std::vector<near_solids::Bounded<Dim>> solids_;  // their own bounding boxes (the put-back)
  std::vector<near_solids::Bounded<Dim>> banded_;  // grown by the dx/4 band (the stops)
  typename SolidReach<Dim>::Lookup clear_;
  double dx_;
};
}  // namespace sluice
