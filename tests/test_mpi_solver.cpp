// The solver on several processes (run under mpirun -np N, tests/CMakeLists.txt) against the same case
// on one: after a number of steps, every particle where the serial run has it, to round-off. The
// distributed run adds the same pair terms in another order (the particles of a cell are ordered
// differently when ghosts are mixed in), so the two agree to round-off, not bit for bit; the bound
// is far below anything physical (1e-9 m against dx = 4 mm) and far above what a missing pair, a
// stale ghost or a lost particle gives (1e-4 m and more after a few steps).
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <cmath>
#include <filesystem>
#include <memory>
#include <new>
#include <string>

#include "physics_cases.hpp"
#include "sluice/case/builtin_cases.hpp"
#include "sluice/case/overrides.hpp"
#include "sluice/case/params.hpp"
#include "sluice/io/checkpoint.hpp"
#include "sluice/io/run.hpp"
#include "sluice/mpi/mpi_communicator.hpp"
#include "sluice/simulation.hpp"

using namespace sluice;

namespace {

const Communicator* world = nullptr;

struct Agreement {
  std::size_t particles = 0;
  double max_position = 0.0;  // m
  double max_velocity = 0.0;  // m/s
  double max_density = 0.0;   // kg/m^3
  bool same_ids = false;  // the serial run's, in increasing order
  std::int64_t outflow = 0, serial_outflow = 0;
  double time = 0.0;
  double time_difference = 0.0;  // s: the steps' sizes follow the largest acceleration, to round-off
};

// Runs `c` for `steps` steps on all processes and on the root alone; compares on the root.
template <int Dim>
Agreement compare(const Case& c, int steps) {
  Simulation distributed(c, 1, world);
  for (int s = 0; s < steps; ++s) distributed.step();
  Agreement a;
  a.time = distributed.time();
  distributed.solver<Dim>().with_all_particles([&](const Particles<Dim>& all) {
    Simulation serial(c, 1);
    for (int s = 0; s < steps; ++s) serial.step();
    a.time_difference = std::abs(serial.time() - distributed.time());
    const Particles<Dim>& one = serial.particles<Dim>();
    a.particles = all.size();
    a.outflow = distributed.clock().outflow;
    a.serial_outflow = serial.clock().outflow;
    if (all.size() != one.size()) return;
    // The serial run's row of each id (ids are 0..N-1 but for those removed as outflow).
    const std::size_t none = one.size();
    std::vector<std::size_t> row(one.size() + static_cast<std::size_t>(serial.clock().outflow), none);
    for (std::size_t i = 0; i < one.size(); ++i) row[one.id[i]] = i;
    for (std::size_t k = 0; k < all.size(); ++k) {
      if (all.id[k] >= row.size() || row[all.id[k]] == none || (k > 0 && all.id[k] <= all.id[k - 1])) return;
      const std::size_t i = row[all.id[k]];
      for (int d = 0; d < Dim; ++d) {
        a.max_position = std::max(a.max_position, std::abs(all.position[d][k] - one.position[d][i]));
        a.max_velocity = std::max(a.max_velocity, std::abs(all.velocity[d][k] - one.velocity[d][i]));
      }
      a.max_density = std::max(a.max_density, std::abs(all.density[k] - one.density[i]));
    }
    a.same_ids = true;
  });
  return a;
}

// A water column collapsing (Martin & Moyce's, a/dx = 14): its surge runs through the processes'
// boxes, so particles migrate and the boxes are cut anew as the water moves.
Case collapse(const std::vector<std::string>& sets) {
  Case c = *load_builtin_case("martin_moyce");
  apply_override(c, "domain.dx=0.004");
  // Dynamic walls at h = 1.3 dx (the built-in case runs mDBC with the wall function, shifting and
  // h = 2 dx): each variant adds what it tests.
  for (const char* set : {"physics.wall_friction=none", "physics.wall_boundary=dynamic", "physics.shifting=0",
                          "domain.h_over_dx=1.3"})
    apply_override(c, set);
  for (const auto& s : sets) apply_override(c, s);
  return c;
}

// `scale` 1 for double-precision pairs: positions within 1e-9 m, velocities 1e-7 m/s, densities 1e-6
// kg/m^3.
void expect_agreement(const Agreement& a, std::size_t particles, const std::string& what, double scale = 1.0) {
  if (world->rank() != 0) return;
  EXPECT_EQ(a.particles, particles) << what;
  EXPECT_TRUE(a.same_ids) << what << ": the gathered particles are not the serial run's, in id order";
  EXPECT_EQ(a.outflow, a.serial_outflow) << what;
  EXPECT_LT(a.max_position, 1e-9 * scale) << what;
  EXPECT_LT(a.max_velocity, 1e-7 * scale) << what;
  EXPECT_LT(a.max_density, 1e-6 * scale) << what;
  EXPECT_LT(a.time_difference, 1e-12 * scale * scale) << what;
  std::printf("[ agreement ] %s, %d processes, t = %.4f s (%.2g s apart): max |dx| %.3g m, |dv| %.3g m/s, "
              "|drho| %.3g kg/m^3\n", what.c_str(), world->size(), a.time, a.time_difference, a.max_position,
              a.max_velocity, a.max_density);
}

}  // namespace

// Every combination that changes what crosses a process boundary: the integrators (step-start state
// and the leapfrog's carried rates migrate with the particles), the wall treatments (Adami and mDBC
// refresh the wall densities and velocities of the ghosts; mDBC reads further), the Shepard filter
// (refreshes densities) and shifting (refreshes div r).
struct Variant {
  const char* name;
  std::vector<std::string> sets;
  int steps = 1500;
  double scale = 1.0;  // of the tolerances
};

class DistributedCollapse : public ::testing::TestWithParam<Variant> {};

TEST_P(DistributedCollapse, GivesTheSerialParticlesToRoundOff) {
  const Variant& v = GetParam();
  const Case c = collapse(v.sets);
  const std::size_t n = Simulation(c, 1).particle_count();
  expect_agreement(compare<2>(c, v.steps), n, v.name, v.scale);
}

INSTANTIATE_TEST_SUITE_P(
    Variants, DistributedCollapse,
    ::testing::Values(Variant{"predictor_corrector_dynamic", {}},
                      Variant{"leapfrog_adami_shepard", {"time.integrator=leapfrog", "physics.wall_boundary=adami",
                                                         "physics.shepard_every=7"}},
                      Variant{"euler_mdbc_no_slip", {"time.integrator=euler", "time.cfl=0.1", "physics.wall_boundary=mdbc",
                                                     "physics.wall_slip=no_slip"}},
                      // The wall function acts on the owned particles only (a ghost's friction is
                      // skipped); its acceleration enters the time step on each process.
                      Variant{"leapfrog_mdbc_log_law", {"time.integrator=leapfrog", "physics.wall_boundary=mdbc",
                                                        "physics.wall_friction=log_law"}, 300},
                      // The renormalised density gradient: the ghosts take their owners' gradients.
                      Variant{"renormalised_gradient", {"physics.density_diffusion_gradient=renormalised"}, 300},
                      // The shift's surface test is a threshold on div r: once round-off tips one
                      // particle's side, the runs part faster (on 3 processes 7e-18 m at step 401,
                      // 1e-10 m at step 501, 4e-9 m at step 533); 300 steps keep to the round-off.
                      Variant{"leapfrog_shifting", {"time.integrator=leapfrog", "physics.shifting=2.0"}, 300},
                      // Single-precision pairs: float round-off in the sums, 1e-7 of them.
                      Variant{"single_precision", {"domain.pair_precision=single"}, 1500, 100.0}),
    [](const ::testing::TestParamInfo<Variant>& info) { return std::string(info.param.name); });

TEST(Distributed3D, DamBreakFromACornerGivesTheSerialParticles) {
  Case c = *load_builtin_case("dam_break_3d");
  apply_override(c, "domain.dx=0.05");
  const std::size_t n = Simulation(c, 1).particle_count();
  expect_agreement(compare<3>(c, 40), n, "3D dam break");
}

// Water that goes over an open tank's wall leaves the processes that hold it as it leaves one process.
TEST(Distributed, WaterLeavingAnOpenTankIsRemovedAsOnOneProcess) {
  // At dx = 1 cm (150 water particles), light enough to run under AddressSanitizer on 4 processes.
  const Case c = test_cases::spill_over_wall(0.01, false, 1.0);
  Simulation probe(c, 1);
  while (probe.clock().outflow == 0) probe.step();
  const int steps = static_cast<int>(probe.clock().step) + 200;
  const std::size_t left = [&] {
    for (int s = static_cast<int>(probe.clock().step); s < steps; ++s) probe.step();
    return probe.particle_count();
  }();
  const Agreement a = compare<2>(c, steps);
  expect_agreement(a, left, "outflow");
  if (world->rank() == 0) {
    EXPECT_GT(a.outflow, 0);
  }
}

// The particles are spread: each process owns some; the surge moves some across, and the boxes are
// cut anew when one process holds 10 % more than the mean.
TEST(Distributed, EveryProcessOwnsParticlesTheyMigrateAndTheBoxesFollowTheWater) {
  Simulation sim(collapse({}), 1, world);
  const auto& solver = sim.solver<2>();
  EXPECT_GT(solver.particles().size(), 0u);
  EXPECT_LT(solver.particles().size(), sim.particle_count());
  for (int s = 0; s < 3000; ++s) sim.step();
  const double moved = world->reducer().sum(static_cast<double>(solver.distribution()->migrated()));
  EXPECT_GT(moved, 0.0);
  EXPECT_GT(solver.distribution()->repartitions(), 0);
  // The predictor-corrector's second evaluations kept the ghosts of the first (within the skin).
  EXPECT_GT(solver.distribution()->ghosts_reused(), 2000);
  // The boxes balance the cost (a wall particle weighs 0.1 of a fluid one); between two new cuts the
  // imbalance may pass the limit of 1.1 by what one evaluation moves.
  const double load = Distribution<2>::load(solver.particles());
  const double mean = world->reducer().sum(load) / world->size();
  EXPECT_LT(world->reducer().max(load), 1.2 * mean);
  const Diagnostics d = sim.diagnostics();
  EXPECT_EQ(d.fluid_particles + d.wall_particles, sim.particle_count());
}

// The world's communicator, except that on one process the n-th exchange of particles throws
// std::bad_alloc before it starts, as running out of memory while packing a message would: an error
// on one process, between collective calls, in the middle of a step.
class FailingCommunicator final : public Communicator {
 public:
  FailingCommunicator(const Communicator& real, int process, int at) : real_(real), process_(process), at_(at) {}
  [[nodiscard]] int rank() const override { return real_.rank(); }
  [[nodiscard]] int size() const override { return real_.size(); }
  [[nodiscard]] const Reducer& reducer() const override { return real_.reducer(); }
  [[nodiscard]] std::vector<std::string> exchange(const std::vector<std::string>& send) const override {
    if (rank() == process_ && ++exchanges_ == at_) throw std::bad_alloc();
    return real_.exchange(send);
  }
  [[nodiscard]] std::vector<std::string> gather(const std::string& part) const override { return real_.gather(part); }
  [[nodiscard]] std::string broadcast(const std::string& from_root) const override {
    return real_.broadcast(from_root);
  }
  [[nodiscard]] std::vector<DomainBox> partition(int dimension, const std::vector<std::array<double, 3>>& points,
                                                 const std::vector<double>& weights) const override {
    return real_.partition(dimension, points, weights);
  }
  [[nodiscard]] Failure fail(const std::string& message, int kind) const override { return real_.fail(message, kind); }
  [[noreturn]] void abort(const std::string& message, int status) const override {
    real_.abort(message, status);
    std::abort();  // not reached (the compiler does not carry [[noreturn]] through the virtual call)
  }

 private:
  const Communicator& real_;
  int process_;
  int at_;
  mutable int exchanges_ = 0;
};

// A process that fails in the middle of a step: every process stops with one error naming it, and
// the state before that step is saved as the last frame and a checkpoint, which holds every particle
// where one process has them after the same number of steps.
TEST(Distributed, AProcessThatFailsMidStepStopsAllAndTheLastGoodStateIsSaved) {
  Case c = collapse({});
  apply_override(c, "time.end=1");
  apply_override(c, "output.interval=0.01");
  const auto dir = std::filesystem::temp_directory_path() / ("sluice_mpi_failure_np" + std::to_string(world->size()));
  if (world->is_root()) std::filesystem::remove_all(dir);
  const int failing = world->size() - 1;
  const FailingCommunicator comm(*world, failing, 200);  // about step 70 (3 exchanges a step)
  RunOptions options;
  options.output_dir = dir;
  options.progress = RunOptions::Progress::none;
  options.comm = &comm;
  std::string error;
  try {
    (void)run_case(c, options, std::cerr);
  } catch (const RunFailure& e) {
    error = e.what();
  }
  const std::string expected = "process " + std::to_string(failing) + " of " + std::to_string(world->size()) +
                               " failed at t = ";
  EXPECT_EQ(error.rfind(expected, 0), 0u) << error;
  EXPECT_NE(error.find("out of memory"), std::string::npos) << error;
  EXPECT_NE(error.find("--restart"), std::string::npos) << error;
  if (!world->is_root()) return;
  std::fprintf(stderr, "The error as a user sees it:\n%s\n", error.c_str());
  const Checkpoint cp = read_checkpoint(dir / "checkpoint.bin");
  EXPECT_GT(cp.clock.step, 30);
  EXPECT_LT(cp.clock.step, 150);
  const auto& saved = std::get<Particles<2>>(cp.particles);
  Simulation serial(c, 1);
  while (serial.clock().step < cp.clock.step) serial.step();
  const Particles<2>& one = serial.particles<2>();
  ASSERT_EQ(saved.size(), one.size());
  EXPECT_NEAR(cp.clock.time, serial.time(), 1e-12);
  std::vector<std::size_t> row(one.size());
  for (std::size_t i = 0; i < one.size(); ++i) row[one.id[i]] = i;
  double worst = 0.0;
  for (std::size_t k = 0; k < saved.size(); ++k)
    for (int d = 0; d < 2; ++d)
      worst = std::max(worst, std::abs(saved.position[d][k] - one.position[d][row[saved.id[k]]]));
  EXPECT_LT(worst, 1e-9);
  // The last frame is that state too, written after the regular frames before it.
  bool frame_found = false;
  for (const auto& entry : std::filesystem::directory_iterator(dir / "frames"))
    frame_found = frame_found || entry.path().extension() == ".npz";
  EXPECT_TRUE(frame_found);
  std::filesystem::remove_all(dir);
}

int main(int argc, char** argv) {
  auto session = start_mpi_if_launched(argc, argv);
  ::testing::InitGoogleTest(&argc, argv);
  if (!session || session->world() == nullptr) {
    std::fprintf(stderr, "test_mpi_solver: run it with mpirun -np N (N >= 2)\n");
    return 1;
  }
  world = session->world();
  // One report, the root's; a failure on any process fails every process.
  if (world->rank() != 0) delete ::testing::UnitTest::GetInstance()->listeners().Release(
      ::testing::UnitTest::GetInstance()->listeners().default_result_printer());
  const int local = RUN_ALL_TESTS();
  const std::int64_t failed = world->reducer().sum(static_cast<std::int64_t>(local != 0));
  return failed > 0 ? 1 : 0;
}
