// Google Benchmark micro-benchmarks: the neighbour search (bin + reorder) and the pair loop, of the
// default dam break (2D) and of SPHERIC test 2 (3D).
#include <benchmark/benchmark.h>

#include "sluice/case/params.hpp"
#include "sluice/geometry/setup.hpp"
#include "sluice/neighbors/cell_grid.hpp"
#include "sluice/physics/kernel.hpp"
#include "sluice/physics/rates.hpp"

using namespace sluice;

namespace {

template <int Dim>
struct Fixture {
  Case c;
  Particles<Dim> particles;
  CellGrid<Dim> grid;
  RateSettings<Dim> settings{};
  ParticleTerms terms;
  std::vector<double> scratch;

  explicit Fixture(double dx, bool single = false)
      : c(*load_builtin_case(Dim == 2 ? "dam_break" : "spheric2")) {
    apply_override(c, "domain.dx=" + std::to_string(dx));
    particles = build_setup<Dim>(c).particles;
    const double h = c.smoothing_length();
    const Vec3 size = c.tank_size();
    Vec<Dim> lower{}, upper{}, middle{};
    for (int d = 0; d < Dim; ++d) {
      lower[d] = -1.0;
      upper[d] = size[d] + 1.0;
      middle[d] = 0.5 * size[d];
    }
    grid = CellGrid<Dim>(lower, upper, 2.0 * h);
    double mass = c.rest_density;
    for (int d = 0; d < Dim; ++d) mass *= c.dx;
    settings = {mass, h, c.viscosity, c.artificial_viscosity, c.density_diffusion, first<Dim>(c.gravity),
                TaitEos{c.rest_density, c.sound_speed, c.gamma}};
    grid.bin(particles.position);
    particles.permute(grid.order(), scratch, false, 1);
    terms.compute(particles, settings.eos, settings.gravity, 1, 0.0, single, middle);
  }
};

template <int Dim>
void NeighbourSearch(benchmark::State& state) {
  Fixture<Dim> f(static_cast<double>(state.range(0)) * 1e-3);
  for (auto _ : state) {
    f.grid.bin(f.particles.position);
    f.particles.permute(f.grid.order(), f.scratch, false, 1);
    benchmark::DoNotOptimize(f.grid.cell_start().data());
  }
  state.counters["particles"] = static_cast<double>(f.particles.size());
  state.SetItemsProcessed(state.iterations() * static_cast<long>(f.particles.size()));
}

// Range arguments: dx in millimetres, and 1 for single-precision pair arithmetic.
template <int Dim>
void PairLoop(benchmark::State& state) {
  Fixture<Dim> f(static_cast<double>(state.range(0)) * 1e-3, state.range(1) != 0);
  const AnyKernel<Dim> kernel = CubicSpline<Dim>(f.settings.h);
  const WallTreatment walls = DynamicWalls{};
  for (auto _ : state)
    benchmark::DoNotOptimize(compute_rates<Dim>(f.particles, f.grid, kernel, walls, f.settings, f.terms, 1));
  state.counters["particles"] = static_cast<double>(f.particles.size());
  state.SetItemsProcessed(state.iterations() * static_cast<long>(f.particles.size()));
}

}  // namespace

// 2D, dx in millimetres: 50 mm ~23k particles, 22 mm ~109k; 3D (SPHERIC test 2): 40 mm ~37k.
BENCHMARK(NeighbourSearch<2>)->Arg(50)->Arg(22)->Unit(benchmark::kMillisecond);
BENCHMARK(PairLoop<2>)->Args({50, 0})->Args({50, 1})->Args({22, 0})->Args({22, 1})->Unit(benchmark::kMillisecond);
BENCHMARK(PairLoop<3>)->Args({40, 0})->Args({40, 1})->Unit(benchmark::kMillisecond);

BENCHMARK_MAIN();
