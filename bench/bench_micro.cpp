// Google Benchmark micro-benchmarks: the neighbour search (bin + reorder) and the pair loop.
#include <benchmark/benchmark.h>

#include "sluice/case/params.hpp"
#include "sluice/geometry/setup.hpp"
#include "sluice/neighbors/cell_grid.hpp"
#include "sluice/physics/kernel.hpp"
#include "sluice/physics/rates.hpp"

using namespace sluice;

namespace {

struct Fixture {
  Case c;
  Particles<2> particles;
  CellGrid<2> grid;
  RateSettings<2> settings{};
  ParticleTerms terms;
  std::vector<double> scratch;

  explicit Fixture(double dx) : c(*load_builtin_case("dam_break")) {
    apply_override(c, "domain.dx=" + std::to_string(dx));
    particles = build_setup<2>(c).particles;
    const double h = c.smoothing_length();
    grid = CellGrid<2>({-1.0, -1.0}, {c.tank_width + 1.0, c.tank_height + 1.0}, 2.0 * h);
    settings = {c.rest_density * c.dx * c.dx, h, c.viscosity, c.artificial_viscosity, c.density_diffusion,
                first<2>(c.gravity), TaitEos{c.rest_density, c.sound_speed, c.gamma}};
    grid.bin(particles.position);
    particles.permute(grid.order(), scratch, false, 1);
    terms.compute(particles, settings.eos, 1);
  }
};

void NeighbourSearch(benchmark::State& state) {
  Fixture f(static_cast<double>(state.range(0)) * 1e-3);
  for (auto _ : state) {
    f.grid.bin(f.particles.position);
    f.particles.permute(f.grid.order(), f.scratch, false, 1);
    benchmark::DoNotOptimize(f.grid.cell_start().data());
  }
  state.counters["particles"] = static_cast<double>(f.particles.size());
  state.SetItemsProcessed(state.iterations() * static_cast<long>(f.particles.size()));
}

void PairLoop(benchmark::State& state) {
  Fixture f(static_cast<double>(state.range(0)) * 1e-3);
  const AnyKernel<2> kernel = CubicSpline<2>(f.settings.h);
  const WallTreatment walls = DynamicWalls{};
  for (auto _ : state)
    benchmark::DoNotOptimize(compute_rates<2>(f.particles, f.grid, kernel, walls, f.settings, f.terms, 1));
  state.counters["particles"] = static_cast<double>(f.particles.size());
  state.SetItemsProcessed(state.iterations() * static_cast<long>(f.particles.size()));
}

}  // namespace

// Range argument: dx in millimetres (50 mm: ~23k particles; 22 mm: ~105k).
BENCHMARK(NeighbourSearch)->Arg(50)->Arg(22)->Unit(benchmark::kMillisecond);
BENCHMARK(PairLoop)->Arg(50)->Arg(22)->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
