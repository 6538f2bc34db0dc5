// The table of compiled pair loops of one instruction set (physics/pair_loop-inl.hpp enters them,
// a dimension and precision at a time; physics/pair_loop.cpp puts each target's table together and
// picks the CPU's best): a function per dimension, kernel, wall pair traits, artificial-pressure
// switch and precision of the pairs, and a Shepard filter, the sums of particle shifting and the fluid
// sums at a point (mDBC's ghost nodes) per dimension and kernel, and the tests for fluid near a point and
// near each wall particle per dimension.
#pragma once

#include <array>
#include <cstdint>
#include <variant>
#include <vector>

#include "sluice/physics/fluid_sums.hpp"
#include "sluice/physics/rates.hpp"

namespace sluice {

inline constexpr std::size_t kKernels = std::variant_size_v<AnyKernel<2>>;
inline constexpr std::size_t kPairWallTraits = std::variant_size_v<PairWallTraits>;

template <int Dim>
using RateLoop = RateSummary (*)(Particles<Dim>&, const CellGrid<Dim>&, const RateSettings<Dim>&,
                                 const ParticleTerms&, int threads);
template <int Dim>
using ShepardLoop = void (*)(Particles<Dim>&, const CellGrid<Dim>&, double h, double mass,
                             const std::vector<std::uint8_t>* selected, std::vector<double>& scratch, int threads);

template <int Dim>
using ShiftingLoop = void (*)(const Particles<Dim>&, const CellGrid<Dim>&, const ShiftingSums&, const double* fluid,
                              const std::array<double*, 2 * Dim + 1>& out, int threads);

template <int Dim>
using DensityGradientLoop = void (*)(const Particles<Dim>&, const CellGrid<Dim>&, double h, double mass,
                                     const double* fluid,
                                     const std::array<double*, Dim*(Dim + 1) / 2 + Dim>& out, int threads);

template <int Dim>
using FluidSumsLoop = FluidSums<Dim> (*)(const Particles<Dim>&, const CellGrid<Dim>&, double h, double mass,
                                         const FluidIndex&, const Vec<Dim>& point);

template <int Dim>
using FluidWithinLoop = bool (*)(const Particles<Dim>&, const CellGrid<Dim>&, const FluidIndex&, const Vec<Dim>& point,
                                 double radius2);

template <int Dim>
using WallsReachedLoop = void (*)(const Particles<Dim>&, const CellGrid<Dim>&, const FluidIndex&, std::uint32_t first_cell,
                                  std::uint32_t last_cell, double radius2, std::uint8_t* reached);

template <int Dim>
struct DimensionLoops {
  // [kernel][wall pair traits][with artificial pressure][single-precision pairs]
  RateLoop<Dim> rates[kKernels][kPairWallTraits][2][2];
  ShepardLoop<Dim> shepard[kKernels];
  ShiftingLoop<Dim> shifting[kKernels];
  DensityGradientLoop<Dim> density_gradient[kKernels];
  FluidSumsLoop<Dim> fluid_sums[kKernels];
  FluidWithinLoop<Dim> fluid_within;
  WallsReachedLoop<Dim> walls_reached;
};

struct RateLoops {
  const char* target;  // Highway's name of the instruction set: AVX2, AVX3 (AVX-512), SSE4, EMU128, ...
  DimensionLoops<2> two;
  DimensionLoops<3> three;

  template <int Dim>
  [[nodiscard]] const DimensionLoops<Dim>& of() const {
    if constexpr (Dim == 2) return two;
    else return three;
  }
};

}  // namespace sluice
