// The pair loop's table for every instruction set Highway targets here (foreach_target re-includes
// this file once per target), and the dispatch to the best one the CPU runs.
//
// The loops themselves are compiled in four files, 2D and 3D with pairs in double and in single
// precision (physics/pair_loop_{2d,3d}_{double,single}.cpp), so that a parallel build shares them out:
// as one file they were the longest compile of the build, 17-18 minutes under the sanitizers. The
// four take about the same time, in release builds and under the sanitizers (within a fifth of each
// other), the Shepard filter and the shifting sums, in double precision only, going with the double
// parts. Each target's table is put together here from that target's parts, so that one dispatch
// picks all its loops.
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "sluice/physics/pair_loop.cpp"
#include <hwy/foreach_target.h>  // must come before highway.h

#include <hwy/highway.h>

#include "sluice/physics/rate_loops.hpp"

HWY_BEFORE_NAMESPACE();
namespace sluice::HWY_NAMESPACE {

// Enters this target's loops of one dimension with pairs in precision R: defined in
// physics/pair_loop-inl.hpp, instantiated in physics/pair_loop_{2d,3d}_{double,single}.cpp.
template <int Dim, class R>
void add_loops(DimensionLoops<Dim>& loops);

const RateLoops* target_rate_loops() {
  static const RateLoops loops = [] {
    RateLoops table{hwy::TargetName(HWY_TARGET), {}, {}};
    add_loops<2, double>(table.two);
    add_loops<2, float>(table.two);
    add_loops<3, double>(table.three);
    add_loops<3, float>(table.three);
    return table;
  }();
  return &loops;
}

}  // namespace sluice::HWY_NAMESPACE
HWY_AFTER_NAMESPACE();

#if HWY_ONCE

#include <algorithm>
#include <cctype>
#include <stdexcept>

#include <fmt/format.h>

#include "sluice/physics/rates.hpp"
#include "sluice/physics/simd_target.hpp"

namespace sluice {

HWY_EXPORT(target_rate_loops);

namespace {

const RateLoops& loops() { return *HWY_DYNAMIC_DISPATCH(target_rate_loops)(); }

std::string upper(std::string_view s) {
  std::string u(s);
  std::transform(u.begin(), u.end(), u.begin(), [](unsigned char c) { return static_cast<char>(std::toupper(c)); });
  return u;
}

}  // namespace

std::string simd_target() { return loops().target; }

namespace {

// The compiled targets the CPU runs, read once, before use_simd_target narrows what Highway reports.
const std::vector<std::int64_t>& runnable_targets() {
  static const std::vector<std::int64_t> targets = hwy::SupportedAndGeneratedTargets();
  return targets;
}

}  // namespace

std::vector<std::string> available_simd_targets() {
  std::vector<std::string> names;
  for (const std::int64_t t : runnable_targets()) names.emplace_back(hwy::TargetName(t));
  return names;
}

void use_simd_target(std::string_view name) {
  const std::string wanted = upper(name);
  runnable_targets();
  if (wanted == "AUTO") {
    hwy::SetSupportedTargetsForTest(0);
    hwy::GetChosenTarget().Update(hwy::SupportedTargets());
    return;
  }
  for (const std::int64_t t : runnable_targets()) {
    if (upper(hwy::TargetName(t)) != wanted) continue;
    hwy::SetSupportedTargetsForTest(t);
    hwy::GetChosenTarget().Update(hwy::SupportedTargets());
    return;
  }
  std::string list;
  for (const auto& n : available_simd_targets()) list += (list.empty() ? "" : ", ") + n;
  throw std::invalid_argument(
      fmt::format("unknown or unsupported SIMD target '{}': this CPU and build have {} (or auto)", name, list));
}

template <int Dim>
RateSummary compute_rates(Particles<Dim>& p, const CellGrid<Dim>& grid, const AnyKernel<Dim>& kernel,
                          const WallTreatment& walls, const RateSettings<Dim>& settings, const ParticleTerms& terms,
                          int threads) {
  const bool with_artificial_pressure = settings.artificial_pressure > 0.0;
  const RateLoop<Dim> loop = loops().template of<Dim>().rates[kernel.index()][pair_traits_index(walls)]
                                                              [with_artificial_pressure ? 1 : 0][terms.single_precision ? 1 : 0];
  return loop(p, grid, settings, terms, threads);
}

template <int Dim>
void shepard_filter(Particles<Dim>& p, const CellGrid<Dim>& grid, const AnyKernel<Dim>& kernel, double mass,
                    const std::vector<std::uint8_t>* selected, std::vector<double>& scratch, int threads) {
  const double h = std::visit([](const auto& k) { return k.h; }, kernel);
  loops().template of<Dim>().shepard[kernel.index()](p, grid, h, mass, selected, scratch, threads);
}

template <int Dim>
void shifting_sums(const Particles<Dim>& p, const CellGrid<Dim>& grid, const AnyKernel<Dim>& kernel,
                   const ShiftingSums& settings, const double* fluid, const std::array<double*, 2 * Dim + 1>& out,
                   int threads) {
  loops().template of<Dim>().shifting[kernel.index()](p, grid, settings, fluid, out, threads);
}

template <int Dim>
void density_gradient_sums(const Particles<Dim>& p, const CellGrid<Dim>& grid, const AnyKernel<Dim>& kernel,
                           double mass, const double* fluid,
                           const std::array<double*, Dim*(Dim + 1) / 2 + Dim>& out, int threads) {
  const double h = std::visit([](const auto& k) { return k.h; }, kernel);
  loops().template of<Dim>().density_gradient[kernel.index()](p, grid, h, mass, fluid, out, threads);
}

template <int Dim>
FluidSums<Dim> fluid_sums_at(const Particles<Dim>& p, const CellGrid<Dim>& grid, const AnyKernel<Dim>& kernel,
                             double mass, const FluidIndex& fluid, const Vec<Dim>& point) {
  const double h = std::visit([](const auto& k) { return k.h; }, kernel);
  return loops().template of<Dim>().fluid_sums[kernel.index()](p, grid, h, mass, fluid, point);
}

template <int Dim>
bool fluid_within(const Particles<Dim>& p, const CellGrid<Dim>& grid, const FluidIndex& fluid, const Vec<Dim>& point,
                  double radius2) {
  return loops().template of<Dim>().fluid_within(p, grid, fluid, point, radius2);
}

template <int Dim>
void walls_reached(const Particles<Dim>& p, const CellGrid<Dim>& grid, const FluidIndex& fluid, std::uint32_t first_cell,
                   std::uint32_t last_cell, double radius2, std::uint8_t* reached) {
  loops().template of<Dim>().walls_reached(p, grid, fluid, first_cell, last_cell, radius2, reached);
}

template void walls_reached<2>(const Particles<2>&, const CellGrid<2>&, const FluidIndex&, std::uint32_t, std::uint32_t,
                               double, std::uint8_t*);
template void walls_reached<3>(const Particles<3>&, const CellGrid<3>&, const FluidIndex&, std::uint32_t, std::uint32_t,
                               double, std::uint8_t*);
template bool fluid_within<2>(const Particles<2>&, const CellGrid<2>&, const FluidIndex&, const Vec<2>&, double);
template bool fluid_within<3>(const Particles<3>&, const CellGrid<3>&, const FluidIndex&, const Vec<3>&, double);
template FluidSums<2> fluid_sums_at<2>(const Particles<2>&, const CellGrid<2>&, const AnyKernel<2>&, double,
                                       const FluidIndex&, const Vec<2>&);
template FluidSums<3> fluid_sums_at<3>(const Particles<3>&, const CellGrid<3>&, const AnyKernel<3>&, double,
                                       const FluidIndex&, const Vec<3>&);
template RateSummary compute_rates<2>(Particles<2>&, const CellGrid<2>&, const AnyKernel<2>&, const WallTreatment&,
                                      const RateSettings<2>&, const ParticleTerms&, int);
template RateSummary compute_rates<3>(Particles<3>&, const CellGrid<3>&, const AnyKernel<3>&, const WallTreatment&,
                                      const RateSettings<3>&, const ParticleTerms&, int);
template void shifting_sums<2>(const Particles<2>&, const CellGrid<2>&, const AnyKernel<2>&, const ShiftingSums&,
                               const double*, const std::array<double*, 5>&, int);
template void shifting_sums<3>(const Particles<3>&, const CellGrid<3>&, const AnyKernel<3>&, const ShiftingSums&,
                               const double*, const std::array<double*, 7>&, int);
template void density_gradient_sums<2>(const Particles<2>&, const CellGrid<2>&, const AnyKernel<2>&, double,
                                       const double*, const std::array<double*, 5>&, int);
template void density_gradient_sums<3>(const Particles<3>&, const CellGrid<3>&, const AnyKernel<3>&, double,
                                       const double*, const std::array<double*, 9>&, int);
template void shepard_filter<2>(Particles<2>&, const CellGrid<2>&, const AnyKernel<2>&, double,
                                const std::vector<std::uint8_t>*, std::vector<double>&, int);
template void shepard_filter<3>(Particles<3>&, const CellGrid<3>&, const AnyKernel<3>&, double,
                                const std::vector<std::uint8_t>*, std::vector<double>&, int);

}  // namespace sluice

#endif  // HWY_ONCE
