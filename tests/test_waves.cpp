// Waves made by a moving wall, measured as `sluice analyze` measures them: a short, coarse flume (the
// wave 3.2 particles high, a damping zone after 1.4 wavelengths, wave_flume's physics: no artificial
// viscosity or shifting) driven by a piston and by a flap making the same wave. Physical facts that hold even this coarse: the waves have the maker's period,
// their first harmonic is the target's height to within 15 % (a wrong transfer function, stroke or
// sign is off by far more) and lags linear theory's phase by less than 20 degrees; the damping zone
// reflects little.
#include <gtest/gtest.h>

#include <fmt/format.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <iostream>
#include <numbers>
#include <sstream>
#include <string>

#include "sluice/analysis/wave_flume.hpp"
#include "sluice/case/load.hpp"
#include "sluice/io/run.hpp"

namespace sluice {
namespace {

namespace fs = std::filesystem;

// H = 0.08 m, T = 1.2 s on h = 0.4 m (L = 1.936 m), ramped over one period; gauges at 0.5, 0.75 and
// 1 wavelength from the maker's face (at x = `face`); the zone from 2.9 m.
std::string flume(const std::string& maker, double face) {
  std::string text = fmt::format(R"(
[domain]
dx = 0.025
kernel = "wendland_c2"
[tank]
width = 4.0
height = 0.7
[fluid]
sound_speed = 22.0
[physics]
artificial_viscosity = 0.0
shifting = 0.0
[time]
end = 9.6
[output]
interval = 1.0
[[water]]
min = [{face}, 0.0]
max = [4.0, 0.4]
[damping]
start = [2.9, 0.0]
length = 1.1
)", fmt::arg("face", face));
  text += maker;
  for (const double wavelengths : {0.5, 0.75, 1.0})
    text += fmt::format("[[probe]]\nname = \"g{}\"\ntype = \"gauge\"\npoint = [{}, 0.0]\nmeasure = \"surface\"\n"
                        "interval = 0.02\n",
                        wavelengths, face + wavelengths * 1.9361);
  return text;
}

const std::string piston = R"(
[[wall]]
name = "piston"
min = [0.04, 0.0]
max = [0.12, 0.65]
[wall.translation]
law = "wave"
direction = [1.0, 0.0]
height = 0.08
period = 1.2
depth = 0.4
ramp = 1
)";

// Hinged 0.1 m above the floor on a fixed base, its face at x = 0.22 m: its top swings 0.1 m back.
const std::string flap = R"(
[[wall]]
name = "base"
min = [0.14, 0.0]
max = [0.22, 0.1]
[[wall]]
name = "flap"
min = [0.14, 0.1]
max = [0.22, 0.55]
[wall.rotation]
law = "wave"
centre = [0.22, 0.1]
height = 0.08
period = 1.2
depth = 0.4
ramp = 1
)";

analysis::FlumeAnalysis run_and_analyse(const std::string& maker, double face, const std::string& label,
                                        const std::string& text = "", analysis::Window window = {4.8, 9.6}) {
  const Case c = parse_case(text.empty() ? flume(maker, face) : text, label);
  const fs::path dir = fs::temp_directory_path() / fmt::format("sluice_waves_{}_{}", label, ::getpid());
  fs::remove_all(dir);
  RunOptions options;
  options.output_dir = dir;
  options.progress = RunOptions::Progress::none;
  options.threads = 1;
  std::ostringstream log;
  run_case(c, options, log);
  // The steady window after the one-period ramp and the front's passage (by default), the same at every
  // gauge: four periods, over which the zero crossings' jitter at this coarse spacing averages out.
  analysis::FlumeOptions o;
  o.window = window;
  analysis::FlumeAnalysis a = analysis::analyze_flume(dir, c, o);
  fs::remove_all(dir);
  return a;
}

void expect_the_target_wave(const analysis::FlumeAnalysis& a, const std::string& label) {
  std::cout << label << ":\n" << analysis::flume_table(a);
  ASSERT_EQ(a.gauges.size(), 3u);
  for (const auto& g : a.gauges) {
    ASSERT_TRUE(g.harmonics && g.zero_crossing) << label << " " << g.name << ": " << g.note;
    EXPECT_NEAR(g.zero_crossing->mean_period, 1.2, 0.012) << label << " " << g.name;
    EXPECT_NEAR(2.0 * g.harmonics->amplitude[0] / 0.08, 1.0, 0.15) << label << " " << g.name;
    const double lag = std::remainder(g.harmonics->phase[0] - g.theory_phase, 2.0 * std::numbers::pi);
    EXPECT_LT(std::abs(lag) * 180.0 / std::numbers::pi, 20.0) << label << " " << g.name;
  }
  ASSERT_TRUE(a.reflection) << label;
  EXPECT_LT(a.reflection->coefficient, 0.1) << label;
}

TEST(Waves, APistonMakesTheTargetWave) { expect_the_target_wave(run_and_analyse(piston, 0.12, "piston"), "piston"); }

TEST(Waves, AFlapMakesTheTargetWave) { expect_the_target_wave(run_and_analyse(flap, 0.22, "flap"), "flap"); }

}  // namespace
}  // namespace sluice

namespace sluice {
namespace {

// An absorbing piston at the far end in place of the damping zone (its face 3.68 m from the maker's,
// with room behind it for its default correction, h/4):
// the wave reaches it at 4.7 s and what it sends back passes the gauges from about 7 s; over four
// periods after that the reflection is under 0.2, where a fixed wall would send back all of it (at
// dx = 0.02 m in a 7 m flume it measured 0.11; the shallow-water absorber's own at kh = 1.3 is 0.08).
TEST(Waves, AnAbsorbingPistonAtTheFarEndReflectsLittle) {
  std::string text = flume(piston, 0.12);
  const auto zone = text.find("[damping]");
  text.replace(zone, text.find("[[wall]]") - zone, "");
  text.replace(text.find("max = [4.0, 0.4]"), 16, "max = [3.8, 0.4]");
  text.replace(text.find("end = 9.6"), 9, "end = 12.0");
  text += R"(
[[wall]]
name = "end"
min = [3.8, 0.0]
max = [3.88, 0.65]
[wall.translation]
law = "absorber"
direction = [-1.0, 0.0]
depth = 0.4
)";
  const analysis::FlumeAnalysis a = run_and_analyse("", 0.12, "absorber", text, {7.2, 12.0});
  std::cout << analysis::flume_table(a);
  ASSERT_TRUE(a.reflection);
  EXPECT_LT(a.reflection->coefficient, 0.2);
  EXPECT_GT(a.reflection->incident, 0.03);
}

}  // namespace
}  // namespace sluice
