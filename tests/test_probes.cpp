// Probes and gauges declared in a case file, run through the whole run loop and read back from their
// CSV files: in still water a pressure probe reads rho0 g depth and a gauge reads the water depth.
#include <gtest/gtest.h>
#include <unistd.h>

#include <fmt/format.h>

#include <cmath>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "sluice/case/builtin_cases.hpp"
#include "sluice/case/params.hpp"
#include "sluice/io/atomic_file.hpp"
#include "sluice/io/probes.hpp"
#include "sluice/io/run.hpp"

using namespace sluice;
namespace fs = std::filesystem;

namespace {

constexpr double depth = 1.0, dx = 0.05, rho0 = 1000.0, g = 9.81, end_time = 1.0;

// Still water 1 m deep in a 1 m wide tank, with the probes as a user declares them. c0 = 30 m/s as in
// the hydrostatic physics test: at the default 20 m/s the settled pressure of this coarse column sits
// 1.5-3% above rho0 g d (a property of the solver at that compressibility, not of the probes; the
// t = 0 sample below checks the probe's interpolation itself).
Case still_water_with_probes() {
  return parse_case(fmt::format(R"(
[case]
name = "still_water_probes"
[domain]
dx = {dx}
h_over_dx = 1.3            # the distances below are in h = 1.3 dx
[tank]
width = 1.0
height = 1.2
[fluid]
density = {rho0}
sound_speed = 30.0
[physics]
wall_boundary = "dynamic"  # whose particles the pressure probe leaves out (mdbc walls' it reads)
shifting = 0.0
[time]
end = {end}
[output]
interval = 0.25
formats = ["npz"]

[[water]]
min = [0.0, 0.0]
max = [1.0, {depth}]

[[probe]]
name = "p_half"            # half-way down: rho0 g (depth/2)
type = "pressure"
point = [0.5, 0.5]

[[probe]]
name = "p_deep"            # a quarter of the depth above the floor
type = "pressure"
point = [0.5, 0.25]
interval = 0.1

[[probe]]
name = "gauge_mid"
type = "gauge"
point = [0.5, 0.0]

[[probe]]
name = "front"
type = "front"
point = [0.0, 0.0]
direction = [1.0, 0.0]
)",
                                fmt::arg("dx", dx), fmt::arg("rho0", rho0), fmt::arg("end", end_time),
                                fmt::arg("depth", depth)),
                    "still water probe case");
}

std::vector<std::vector<double>> read_csv(const fs::path& path, const std::string& expected_header) {
  std::istringstream in(read_file(path));
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, expected_header) << path;
  std::vector<std::vector<double>> rows;
  while (std::getline(in, line)) {
    std::vector<double> row;
    std::istringstream cells(line);
    std::string cell;
    while (std::getline(cells, cell, ',')) row.push_back(std::stod(cell));
    rows.push_back(row);
  }
  return rows;
}

// Mean of column `col` over rows with time >= t0.
double mean_after(const std::vector<std::vector<double>>& rows, double t0, std::size_t col) {
  double sum = 0.0;
  int n = 0;
  for (const auto& r : rows)
    if (r[0] >= t0) {
      sum += r[col];
      ++n;
    }
  EXPECT_GT(n, 0);
  return sum / n;
}

struct ProbeRun {
  fs::path dir;
  RunResult result;
};

ProbeRun run_still_water() {
  ProbeRun r;
  r.dir = fs::temp_directory_path() / fmt::format("sluice_test_probes_{}", ::getpid());
  fs::remove_all(r.dir);
  RunOptions options;
  options.output_dir = r.dir;
  options.threads = 1;
  options.progress = RunOptions::Progress::none;
  std::ostringstream log;
  r.result = run_case(still_water_with_probes(), options, log);
  return r;
}

void pressure_probes_read_hydrostatic_pressure(const ProbeRun& run) {
  for (const auto& [name, y] : {std::pair<std::string, double>{"p_half", 0.5}, {"p_deep", 0.25}}) {
    const auto rows = read_csv(run.dir / "probes" / (name + ".csv"), "time,pressure,neighbours");
    ASSERT_FALSE(rows.empty());
    const double expected = rho0 * g * (depth - y);
    // At t = 0 (hydrostatic start) the interpolated pressure is the exact hydrostatic one.
    EXPECT_NEAR(rows.front()[1], expected, 1e-3 * expected) << name;
    const double measured = mean_after(rows, 0.5 * end_time, 1);
    std::cout << name << ": mean pressure over t >= " << 0.5 * end_time << " s = " << measured
              << " Pa, rho0 g d = " << expected << " Pa (" << 100.0 * (measured / expected - 1.0) << "%)\n";
    EXPECT_NEAR(measured, expected, 0.03 * expected) << name;
    // The kernel support around the probe is full of fluid particles.
    EXPECT_GE(mean_after(rows, 0.0, 2), 10.0) << name;
  }
}

void gauge_reads_the_depth(const ProbeRun& run) {
  const auto rows = read_csv(run.dir / "probes" / "gauge_mid.csv", "time,height");
  ASSERT_FALSE(rows.empty());
  EXPECT_NEAR(rows.front()[1], depth, 1e-9);  // at t = 0: top particle centre + dx/2
  const double measured = mean_after(rows, 0.5 * end_time, 1);
  std::cout << "gauge: mean height over t >= " << 0.5 * end_time << " s = " << measured << " m, depth = " << depth
            << " m\n";
  EXPECT_NEAR(measured, depth, 0.5 * dx);
  for (const auto& r : rows) EXPECT_NEAR(r[1], depth, 0.5 * dx) << "t = " << r[0];
}

void front_probe_finds_the_furthest_particle(const ProbeRun& run) {
  const auto rows = read_csv(run.dir / "probes" / "front.csv", "time,distance,x,y");
  ASSERT_FALSE(rows.empty());
  for (const auto& r : rows) {
    EXPECT_NEAR(r[1], 1.0 - 0.5 * dx, 0.25 * dx) << "t = " << r[0];
    EXPECT_EQ(r[1], r[2]);  // from the origin along +x the distance is the x coordinate
  }
}

void sampled_every_step_or_at_their_interval(const ProbeRun& run) {
  const auto every = read_csv(run.dir / "probes" / "p_half.csv", "time,pressure,neighbours");
  ASSERT_FALSE(every.empty());
  // One sample at t = 0 and one after every step.
  EXPECT_EQ(static_cast<std::int64_t>(every.size()), run.result.final.step + 1);
  EXPECT_EQ(every.front()[0], 0.0);
  EXPECT_EQ(every.back()[0], end_time);
  for (std::size_t i = 1; i < every.size(); ++i) EXPECT_GT(every[i][0], every[i - 1][0]);

  // interval = 0.1: the first step at or after each multiple of 0.1 s.
  const auto sparse = read_csv(run.dir / "probes" / "p_deep.csv", "time,pressure,neighbours");
  ASSERT_EQ(sparse.size(), 11u);
  const double max_dt = 0.2 * 1.3 * dx / 30.0;  // cfl * h / c0 bounds the step
  for (std::size_t k = 0; k < sparse.size(); ++k) {
    EXPECT_GE(sparse[k][0], 0.1 * static_cast<double>(k) - 1e-12) << k;
    EXPECT_LT(sparse[k][0], 0.1 * static_cast<double>(k) + max_dt) << k;
  }
}

}  // namespace

// One run for all the checks: under ctest each TEST runs in a process of its own.
TEST(StillWaterProbes, ReadHydrostaticPressureAndTheDepthAtTheirIntervals) {
  const ProbeRun run = run_still_water();
  {
    SCOPED_TRACE("pressure probes");
    pressure_probes_read_hydrostatic_pressure(run);
  }
  {
    SCOPED_TRACE("gauge");
    gauge_reads_the_depth(run);
  }
  {
    SCOPED_TRACE("front");
    front_probe_finds_the_furthest_particle(run);
  }
  {
    SCOPED_TRACE("sampling");
    sampled_every_step_or_at_their_interval(run);
  }
  std::error_code ec;
  fs::remove_all(run.dir, ec);
}

// The interpolation of a pressure probe, at t = 0 (hydrostatic densities: the pressure is exactly
// rho0 g (depth - y) on every fluid particle). On the floor the fluid lies on one side only: the
// Shepard average reads the pressure of the fluid above the floor, the first-order (linear) fit the
// floor's own, rho0 g depth, to round-off. A sensor across the floor reads the same, since the
// pressure does not change along it.
TEST(PressureProbe, OnTheFloorTheLinearFitReadsTheFloorPressureAndShepardTheFluidAbove) {
  const Case c = still_water_with_probes();
  const Simulation sim(c, 1);
  const double floor_pressure = rho0 * g * depth;
  Probe probe;
  probe.type = ProbeType::pressure;
  probe.point = {0.5, 0.0, 0.0};
  const double shepard = sample_probe(probe, sim)[0];
  probe.correction = ProbeCorrection::linear;
  const double linear = sample_probe(probe, sim)[0];
  EXPECT_NEAR(linear, floor_pressure, 1e-9 * floor_pressure);
  // The fluid within 2h = 2.6 dx of the floor has its centres 0.5 dx to 2.5 dx up.
  EXPECT_LT(shepard, floor_pressure - rho0 * g * 0.5 * dx);
  EXPECT_GT(shepard, floor_pressure - rho0 * g * 2.5 * dx);
  probe.size = 0.2;
  const std::vector<double> sensor = sample_probe(probe, sim);
  EXPECT_NEAR(sensor[0], floor_pressure, 1e-9 * floor_pressure);
  EXPECT_GT(sensor[1], 0.0);  // the neighbours of the sensor's centre
  // In the water, away from walls and the surface, both read the pressure at the point: the linear fit
  // to round-off, the Shepard average to 1e-4 (its weights m/rho_j W_ij are not quite symmetric about
  // the point: the density grows with depth).
  probe.size = 0.0;
  probe.point = {0.5, 0.4, 0.0};
  const double expected = rho0 * g * (depth - 0.4);
  EXPECT_NEAR(sample_probe(probe, sim)[0], expected, 1e-9 * expected);
  probe.correction = ProbeCorrection::shepard;
  EXPECT_NEAR(sample_probe(probe, sim)[0], expected, 1e-4 * expected);
}

// A sensor on the side wall reaching above the water: its points in the air read 0, so it reads less
// than its wet half does; a sensor wholly in the air reads 0.
TEST(PressureProbe, ASensorReadsZeroWhereThereIsNoWater) {
  const Case c = still_water_with_probes();
  const Simulation sim(c, 1);
  Probe probe;
  probe.type = ProbeType::pressure;
  probe.size = 0.1;
  probe.point = {0.0, depth - 0.05, 0.0};  // on the wall x = 0, from 0.05 below the surface to it
  const double wet = sample_probe(probe, sim)[0];
  probe.point = {0.0, depth + 0.05, 0.0};  // from the surface to 0.1 above it
  const double half = sample_probe(probe, sim)[0];
  probe.point = {0.0, depth + 0.17, 0.0};  // 0.16 to 0.18 above the surface: beyond 2h = 0.13
  probe.size = 0.02;
  const double dry = sample_probe(probe, sim)[0];
  EXPECT_GT(wet, 0.0);
  EXPECT_LT(half, wet);
  EXPECT_EQ(dry, 0.0);
}

// A gauge over still water 1 m deep with a detached sheet of water 0.1 m thick higher up (spray): the
// highest fluid reads the sheet's top, the column reads the still water's surface; without the sheet
// both read the surface; in 3D too.
TEST(Gauge, TheColumnMeasureReadsTheStandingWaterNotTheSprayAbove) {
  Case c = still_water_with_probes();
  c.tank_height = 2.0;
  Region sheet;
  sheet.min = {0.0, 1.5, 0.0};
  sheet.max = {1.0, 1.6, 0.0};
  c.water.push_back(sheet);
  const Simulation sim(c, 1);
  Probe gauge;
  gauge.type = ProbeType::gauge;
  gauge.point = {0.5, 0.0, 0.0};
  EXPECT_NEAR(sample_probe(gauge, sim)[0], 1.6, 1e-9);
  gauge.measure = GaugeMeasure::column;
  EXPECT_NEAR(sample_probe(gauge, sim)[0], depth, 1e-9);
  // A gauge standing on the sheet's level reads the sheet; one whose foot is in the air above the
  // water reads nothing.
  gauge.point = {0.5, 1.45, 0.0};
  EXPECT_NEAR(sample_probe(gauge, sim)[0], 1.6, 1e-9);
  gauge.point = {0.5, 1.7, 0.0};
  EXPECT_EQ(sample_probe(gauge, sim)[0], 0.0);

  Case c3 = *load_builtin_case("still_water_3d");
  c3.hydrostatic_squeeze = false;  // the water on the lattice: its top at 0.5 m exactly
  Region sheet3;
  sheet3.min = {0.0, 0.0, 0.65};
  sheet3.max = {0.6, 0.4, 0.75};
  c3.water.push_back(sheet3);
  const Simulation sim3(c3, 1);
  Probe gauge3;
  gauge3.type = ProbeType::gauge;
  gauge3.point = {0.3, 0.2, 0.0};
  EXPECT_NEAR(sample_probe(gauge3, sim3)[0], 0.75, 1e-9);
  gauge3.measure = GaugeMeasure::column;
  EXPECT_NEAR(sample_probe(gauge3, sim3)[0], 0.5, 1e-9);
}

// The surface measure reads where the kernel's water fraction falls to 1/2: over still water (on the
// lattice, its top particles dx/2 below the surface) that is the surface to a small fraction of dx,
// with either kernel, in 2D and 3D; a lone particle above the water (a drop of spray) is not water
// level, but a sheet of water thicker than the kernel's reach is.
TEST(Gauge, TheSurfaceMeasureReadsTheKernelsFreeSurface) {
  for (const KernelType kernel : {KernelType::cubic_spline, KernelType::wendland_c2}) {
    Case c = still_water_with_probes();
    c.kernel = kernel;
    c.tank_height = 2.0;
    Probe gauge;
    gauge.type = ProbeType::gauge;
    gauge.measure = GaugeMeasure::surface;
    gauge.point = {0.5, 0.0, 0.0};
    {
      const Simulation sim(c, 1);
      EXPECT_NEAR(sample_probe(gauge, sim)[0], depth, 0.05 * dx) << name_of(kernel, kernel_type_names);
    }
    Region drop;
    drop.min = {0.5, 1.3, 0.0};
    drop.max = {0.5 + dx, 1.3 + dx, 0.0};
    c.water.push_back(drop);
    {
      const Simulation sim(c, 1);
      EXPECT_NEAR(sample_probe(gauge, sim)[0], depth, 0.05 * dx) << "with a drop";
    }
    Region sheet;
    sheet.min = {0.0, 1.5, 0.0};
    sheet.max = {1.0, 1.7, 0.0};
    c.water.push_back(sheet);
    const Simulation sim(c, 1);
    EXPECT_NEAR(sample_probe(gauge, sim)[0], 1.7, 0.05 * dx) << "with a sheet";
  }
  Case c3 = *load_builtin_case("still_water_3d");
  c3.hydrostatic_squeeze = false;
  const Simulation sim3(c3, 1);
  Probe gauge3;
  gauge3.type = ProbeType::gauge;
  gauge3.measure = GaugeMeasure::surface;
  gauge3.point = {0.3, 0.2, 0.0};
  EXPECT_NEAR(sample_probe(gauge3, sim3)[0], 0.5, 0.05 * c3.dx);
}
