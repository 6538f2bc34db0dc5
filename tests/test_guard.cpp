// The instability guard: a run made unstable on purpose (a fixed time step far above the acoustic
// limit) stops with a message naming the time, the step and the offending particles, saves the last
// good state as a frame and a checkpoint, and the CLI exits non-zero.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <sstream>
#include <type_traits>
#include <sys/wait.h>
#include <unistd.h>

#include "sluice/case/params.hpp"
#include "sluice/io/checkpoint.hpp"
#include "sluice/io/frames.hpp"
#include "sluice/io/run.hpp"
#include "sluice/simulation.hpp"

using namespace sluice;
namespace fs = std::filesystem;

namespace {

fs::path fresh_dir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / ("sluice_guard_" + name + "_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  return dir;
}

Case unstable_case() {
  Case c = *load_builtin_case("dam_break");
  apply_override(c, "domain.dx=0.4");
  apply_override(c, "time.dt=0.05");  // the acoustic limit is about 0.2 * 0.52 m / 20 m/s = 0.005 s
  apply_override(c, "time.end=5.0");
  return c;
}

}  // namespace

TEST(InstabilityGuard, StopsWithTheOffendersAndKeepsTheLastGoodState) {
  const fs::path dir = fresh_dir("run");
  RunOptions options;
  options.output_dir = dir;
  options.progress = RunOptions::Progress::none;
  std::ostringstream log;
  std::string message;
  try {
    run_case(unstable_case(), options, log);
    FAIL() << "the run did not stop";
  } catch (const InstabilityError& e) {
    message = e.what();
  }
  EXPECT_NE(message.find("became unstable at t = "), std::string::npos) << message;
  EXPECT_NE(message.find("(step "), std::string::npos) << message;
  EXPECT_NE(message.find("  id "), std::string::npos) << message;
  EXPECT_NE(message.find("neighbours"), std::string::npos) << message;
  EXPECT_NE(message.find("time.dt"), std::string::npos) << message;

  // The checkpoint holds the last good state: every particle finite and in the tank.
  const Checkpoint cp = read_checkpoint(dir / "checkpoint.bin");
  EXPECT_GT(cp.clock.step, 0);
  Simulation good(cp.config, cp.particles, cp.clock, 1);
  EXPECT_TRUE(good.check_health().ok());
  // ... and so does the frame written with it.
  bool found = false;
  for (const auto& entry : fs::directory_iterator(dir / "frames")) {
    if (entry.path().extension() != ".npz") continue;
    const Frame f = read_npz_frame(entry.path());
    if (f.time != cp.clock.time) continue;
    found = true;
    for (double x : f.position()) EXPECT_TRUE(std::isfinite(x));
  }
  EXPECT_TRUE(found) << "no frame at the checkpoint's time " << cp.clock.time;
  fs::remove_all(dir);
}

TEST(InstabilityGuard, TheCommandLineExitsNonZeroWithTheMessage) {
  const fs::path dir = fresh_dir("cli");
  const std::string command = std::string(SLUICE_BIN) + " run dam_break --set domain.dx=0.4 --set time.dt=0.05 -q -o " +
                              dir.string() + " > " + dir.string() + ".out 2>&1";
  const int status = std::system(command.c_str());
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 1);
  std::ifstream out(dir.string() + ".out");
  std::stringstream text;
  text << out.rdbuf();
  EXPECT_NE(text.str().find("sluice: error: the run became unstable"), std::string::npos) << text.str();
  EXPECT_TRUE(fs::exists(dir / "checkpoint.bin"));
  fs::remove_all(dir);
  fs::remove(dir.string() + ".out");
}

// Each kind of bad particle, alone, is counted and named: a density, position or velocity that is
// not finite, a particle far above an open tank or beside it, a density outside (0.5, 2) rho0. The
// guard's test runs on every particle at every step (branch-free); a healthy state passes it.
TEST(InstabilityGuard, NamesEachKindOfBadParticle) {
  Case c = *load_builtin_case("dam_break");
  apply_override(c, "domain.dx=0.2");
  const Simulation start(c, 1);
  const Particles<2> healthy = start.visit([](const auto& s) -> Particles<2> {
    if constexpr (std::is_same_v<std::decay_t<decltype(s.particles())>, Particles<2>>) return s.particles();
    else return {};
  });
  ASSERT_GT(healthy.size(), 10u);
  EXPECT_TRUE(start.check_health().ok());
  const double nan = std::numeric_limits<double>::quiet_NaN(), inf = std::numeric_limits<double>::infinity();
  const double rho0 = c.rest_density, width = c.tank_width, height = c.tank_height;
  using Spoil = std::function<void(Particles<2>&, std::size_t)>;
  const struct {
    const char* what;
    Spoil spoil;
    const char* reason;
  } bad[] = {
      {"density NaN", [&](Particles<2>& p, std::size_t i) { p.density[i] = nan; }, "not finite"},
      {"x infinite", [&](Particles<2>& p, std::size_t i) { p.position[0][i] = inf; }, "not finite"},
      {"vy NaN", [&](Particles<2>& p, std::size_t i) { p.velocity[1][i] = nan; }, "not finite"},
      {"vx -inf", [&](Particles<2>& p, std::size_t i) { p.velocity[0][i] = -inf; }, "not finite"},
      {"far above the tank", [&](Particles<2>& p, std::size_t i) { p.position[1][i] = 12.0 * height; },
       "far outside the tank"},
      {"beside the tank", [&](Particles<2>& p, std::size_t i) { p.position[0][i] = width + 5.0; }, "far outside the tank"},
      {"density 2.5 rho0", [&](Particles<2>& p, std::size_t i) { p.density[i] = 2.5 * rho0; },
       "density outside (0.5, 2) rho0"},
      {"density 0.4 rho0", [&](Particles<2>& p, std::size_t i) { p.density[i] = 0.4 * rho0; },
       "density outside (0.5, 2) rho0"},
  };
  for (const auto& b : bad) {
    Particles<2> p = healthy;
    const std::size_t i = p.size() / 2;
    b.spoil(p, i);
    const Simulation spoiled(c, AnyParticles(std::move(p)), start.clock(), 1);
    const Health h = spoiled.check_health();
    EXPECT_EQ(h.offending, 1u) << b.what;
    ASSERT_EQ(h.first.size(), 1u) << b.what;
    EXPECT_EQ(h.first[0].reason, std::string(b.reason)) << b.what;
  }
}
