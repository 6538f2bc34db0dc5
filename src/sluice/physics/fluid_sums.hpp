// Sums over the fluid particles around a point, as a first-order fit there needs them: the moments
// of LinearFit (core/linear_fit.hpp) of the density with the weights V_j W(|x_j - x|), V_j = m / rho_j,
// the weighted velocity sum, the number of fluid particles in the support and the densest of them.
// The mDBC walls read their ghost nodes with them (physics/mdbc.hpp).
//
// The sums run in the vector code compiled once per instruction set (physics/pair_loop-inl.hpp,
// fluid_sums_at), the candidates a vector at a time as in the Shepard filter; the dispatch picks the
// same target as the pair loop's.
#pragma once

#include <algorithm>
#include <cstdint>
#include <limits>
#include <vector>

#include "sluice/core/linear_fit.hpp"
#include "sluice/core/parallel.hpp"
#include "sluice/core/particles.hpp"
#include "sluice/core/vec.hpp"
#include "sluice/neighbors/cell_grid.hpp"
#include "sluice/physics/kernel.hpp"

namespace sluice {

template <int Dim>
struct FluidSums {
  LinearFit<Dim> fit;     // of the density, y = (x_j - x) / h
  Vec<Dim> velocity{};    // sum_j V_j W_j v_j
  int neighbours = 0;     // fluid particles within the support
  double densest = 0.0;   // their largest density (0 with none)
};

// Which particles are fluid, as the vector sums read it: 1 or 0 per particle, and the number of
// fluid particles before each index (so that a range of candidates without one is passed over).
struct FluidIndex {
  std::vector<double> fluid;
  std::vector<std::uint32_t> before;  // size n + 1
  // For each cell of the grid it was built on (with `grid`): the box around the cell's fluid particles,
  // its lower corner then its upper one, Dim numbers each; lower +inf and upper -inf without one.
  std::vector<double> box;

  // `grid` binned on the current order; without it, no boxes (fluid_sums_at needs none).
  template <int Dim>
  void build(const Particles<Dim>& p, int threads, const CellGrid<Dim>* grid = nullptr) {
    const long n = static_cast<long>(p.size());
    fluid.resize(static_cast<std::size_t>(n));
    parallel::prefix_count(n, threads, before, [&](long i) {
      const bool is = p.kind[static_cast<std::size_t>(i)] == Kind::fluid;
      fluid[static_cast<std::size_t>(i)] = is ? 1.0 : 0.0;
      return is;
    });
    if (grid == nullptr) return;
    const auto& start = grid->cell_start();
    const long cells = static_cast<long>(grid->cell_count());
    box.resize(static_cast<std::size_t>(cells) * 2 * Dim);
    parallel::for_chunks(cells, threads, [&](long first, long last) {
      for (long c = first; c < last; ++c) {
        double* b = box.data() + c * 2 * Dim;
        std::fill_n(b, Dim, std::numeric_limits<double>::infinity());
        std::fill_n(b + Dim, Dim, -std::numeric_limits<double>::infinity());
        if (before[start[c + 1]] == before[start[c]]) continue;
        for (std::uint32_t i = start[c]; i < start[c + 1]; ++i) {
          if (fluid[i] == 0.0) continue;
          for (int d = 0; d < Dim; ++d) {
            b[d] = std::min(b[d], p.position[d][i]);
            b[Dim + d] = std::max(b[Dim + d], p.position[d][i]);
          }
        }
      }
    });
  }
};

// The sums over the fluid particles within the kernel support of `point` (`grid` binned on the
// current order, with cells at least the support wide, as the solver's are; `fluid` built on it).
template <int Dim>
FluidSums<Dim> fluid_sums_at(const Particles<Dim>& p, const CellGrid<Dim>& grid, const AnyKernel<Dim>& kernel,
                             double mass, const FluidIndex& fluid, const Vec<Dim>& point);

// Whether a fluid particle j lies at |x_j - point|^2 < radius2 (radius2 at most the square of the
// grid's cell size), with the distance computed as the pair loop computes it; with `fluid` built on
// the grid, its boxes pass over the cells whose fluid is all out of reach.
template <int Dim>
bool fluid_within(const Particles<Dim>& p, const CellGrid<Dim>& grid, const FluidIndex& fluid, const Vec<Dim>& point,
                  double radius2);

// For each wall particle i of the grid's cells [first_cell, last_cell): reached[i] = 1 if a fluid
// particle lies at |x_j - x_i|^2 < radius2, else 0, as fluid_within says for x_i (`fluid` built on
// the grid, with its boxes). Fluid particles' entries are left as they are.
template <int Dim>
void walls_reached(const Particles<Dim>& p, const CellGrid<Dim>& grid, const FluidIndex& fluid, std::uint32_t first_cell,
                   std::uint32_t last_cell, double radius2, std::uint8_t* reached);

extern template void walls_reached<2>(const Particles<2>&, const CellGrid<2>&, const FluidIndex&, std::uint32_t,
                                      std::uint32_t, double, std::uint8_t*);
extern template void walls_reached<3>(const Particles<3>&, const CellGrid<3>&, const FluidIndex&, std::uint32_t,
                                      std::uint32_t, double, std::uint8_t*);
extern template bool fluid_within<2>(const Particles<2>&, const CellGrid<2>&, const FluidIndex&, const Vec<2>&, double);
extern template bool fluid_within<3>(const Particles<3>&, const CellGrid<3>&, const FluidIndex&, const Vec<3>&, double);
extern template FluidSums<2> fluid_sums_at<2>(const Particles<2>&, const CellGrid<2>&, const AnyKernel<2>&, double,
                                              const FluidIndex&, const Vec<2>&);
extern template FluidSums<3> fluid_sums_at<3>(const Particles<3>&, const CellGrid<3>&, const AnyKernel<3>&, double,
                                              const FluidIndex&, const Vec<3>&);

}  // namespace sluice
