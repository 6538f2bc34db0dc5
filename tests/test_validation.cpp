// `sluice validate --quick`: the three validation cases at the coarse resolution the test suite can
// afford (column width over dx = 20 for Martin & Moyce and Koshizuka & Oka, column height over dx = 30
// for Buchner), run by the real binary. The bounds below are the ones that hold at that resolution
// (measured when they were set, with a margin: docs/validation.md); the full report's targets are
// checked by `sluice validate` itself. Also: bad input to analyze, convergence and validate.
#include <gtest/gtest.h>

#include <fmt/format.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace fs = std::filesystem;

namespace {

std::string read_text(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> out;
  std::stringstream s(line);
  std::string item;
  while (std::getline(s, item, ',')) out.push_back(item);
  return out;
}

// checks.csv: check -> value.
std::map<std::string, double> read_checks(const fs::path& path) {
  std::map<std::string, double> out;
  std::istringstream in(read_text(path));
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "check,value,bound,passed");
  while (std::getline(in, line)) {
    const auto f = split(line);
    if (f.size() == 4) out[f[0]] = std::stod(f[1]);
  }
  return out;
}

// validation.csv: case.comparison -> (rms, max), of the main run or of the --compare variant `variant`.
std::map<std::string, std::pair<double, double>> read_comparisons(const fs::path& path, const std::string& variant = "") {
  std::map<std::string, std::pair<double, double>> out;
  std::istringstream in(read_text(path));
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "case,comparison,points,rms,max,mean,quantity,reference,window,variant");
  while (std::getline(in, line)) {
    const auto f = split(line);  // the main run's rows end in an empty variant field, which split drops
    if (f.size() >= 6 && (f.size() > 9 ? f[9] : std::string()) == variant)
      out[f[0] + "." + f[1]] = {std::stod(f[3]), std::stod(f[4])};
  }
  return out;
}

}  // namespace

// One test (one run of the three cases, about 30 s on one core): the suite runs each test in its own
// process, so splitting it would run the cases again for each part.
TEST(QuickValidation, AgreesWithExperimentsAtCoarseResolution) {
  const fs::path dir = fs::temp_directory_path() / fmt::format("sluice_validate_quick_{}", ::getpid());
  fs::remove_all(dir);
  fs::create_directories(dir);
  // One thread: the suite runs tests side by side on a shared machine.
  const std::string command =
      fmt::format("'{}' validate --quick --threads 1 -q -o '{}' > '{}' 2> '{}'", SLUICE_BIN, (dir / "out").string(),
                  (dir / "stdout.txt").string(), (dir / "stderr.txt").string());
  const int status = std::system(command.c_str());
  const int exit_status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  EXPECT_EQ(exit_status, 0) << read_text(dir / "stdout.txt") << read_text(dir / "stderr.txt");

  // The report: one page with the four plots (two for Martin & Moyce, Koshizuka & Oka, Buchner), and
  // dynamic walls at h = 1.3 dx in a column beside the cases' own settings (their curves dashed).
  const std::string html = read_text(dir / "out" / "report.html");
  ASSERT_FALSE(html.empty());
  std::size_t figures = 0;
  for (auto pos = html.find("<svg"); pos != std::string::npos; pos = html.find("<svg", pos + 1)) ++figures;
  EXPECT_EQ(figures, 4u);
  EXPECT_NE(html.find("Martin &amp; Moyce"), std::string::npos);
  EXPECT_NE(html.find("Buchner"), std::string::npos);
  EXPECT_NE(html.find("<th>RMS, dynamic</th>"), std::string::npos);
  EXPECT_NE(html.find("Variant dynamic: physics.wall_friction=none physics.wall_boundary=dynamic"), std::string::npos);
  EXPECT_NE(read_text(dir / "stdout.txt").find("PASS martin_moyce"), std::string::npos);
  // Each case's table says what leaked and what left: with either walls, nothing leaks.
  std::size_t no_leaks = 0;
  for (auto pos = html.find("<td>0 put back from inside a wall, "); pos != std::string::npos;
       pos = html.find("<td>0 put back from inside a wall, ", pos + 1))
    ++no_leaks;
  EXPECT_EQ(no_leaks, 6u);

  const auto c = read_checks(dir / "out" / "checks.csv");
  const auto m = read_comparisons(dir / "out" / "validation.csv");
  for (const char* id : {"martin_moyce.front_rms", "martin_moyce.height_rms", "koshizuka_oka.front_rms",
                         "buchner.pressure_rms", "buchner.plateau_rms", "buchner.impact_time"})
    ASSERT_TRUE(c.count(id)) << id;
  ASSERT_TRUE(m.count("martin_moyce.front_window"));
  // Each curve also moved in time by its best constant: never further from the data than as run.
  for (const char* id : {"martin_moyce.front_window", "koshizuka_oka.front_window", "buchner.pressure"}) {
    const std::string moved = std::string(id) + "_moved";
    ASSERT_TRUE(m.count(moved)) << moved;
    EXPECT_LE(m.at(moved).first, m.at(id).first) << moved;
  }
  const auto seed = read_comparisons(dir / "out" / "validation.csv", "dynamic");
  for (const char* id : {"martin_moyce.front_window", "koshizuka_oka.front_window", "buchner.pressure"})
    ASSERT_TRUE(seed.count(id)) << id;
  for (const auto& [id, value] : c) std::cout << "measured " << id << " = " << value << "\n";

  // Surge fronts. Martin & Moyce, T <= 3, a/dx = 20: RMS dZ within the full report's target.
  EXPECT_LE(c.at("martin_moyce.front_rms"), 0.25);
  EXPECT_LE(m.at("martin_moyce.front_window").second, 0.30);
  // Koshizuka & Oka, all points (T <= 3.1), L/dx = 20.
  EXPECT_LE(c.at("koshizuka_oka.front_rms"), 0.30);
  // Martin & Moyce residual column height, all points: mDBC walls without the dynamic walls' gap hold
  // the column's last water at the back wall (0.012; 0.054 with dynamic walls).
  EXPECT_LE(c.at("martin_moyce.height_rms"), 0.03);

  // Buchner wall pressure, H/dx = 30: the whole window 2 <= t* <= 7 (impact spikes and the late-time
  // scatter included), the quasi-steady plateau 3.5 <= t* <= 5.5, and the impact time (t* at which p*
  // first reaches 0.25). Measured 0.223, 0.069 and 0.051 with the cases' settings; dynamic walls
  // (the dynamic column) 0.422, 0.168 and 0.169, over these bounds.
  EXPECT_LE(c.at("buchner.pressure_rms"), 0.35);
  EXPECT_LE(c.at("buchner.plateau_rms"), 0.10);
  EXPECT_LE(c.at("buchner.impact_time"), 0.15);
  EXPECT_GT(seed.at("buchner.pressure").first, c.at("buchner.pressure_rms"));

  std::error_code ec;
  fs::remove_all(dir, ec);
}

// --compare: the Buchner case run again with Adami walls, reported beside the main run (about 20 s on
// one core); --no-dynamic leaves out dynamic walls' column. The variant's numbers are its own
// run's, the checks and the exit status the main run's.
TEST(QuickValidation, ReportsVariantsBesideTheMainRun) {
  const fs::path dir = fs::temp_directory_path() / fmt::format("sluice_validate_compare_{}", ::getpid());
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string command = fmt::format(
      "'{}' validate --quick --case buchner --no-dynamic --compare 'adami: physics.wall_boundary=adami' --threads 1 -q -o '{}' > '{}' "
      "2> '{}'",
      SLUICE_BIN, (dir / "out").string(), (dir / "stdout.txt").string(), (dir / "stderr.txt").string());
  const int status = std::system(command.c_str());
  ASSERT_EQ(WIFEXITED(status) ? WEXITSTATUS(status) : -1, 0) << read_text(dir / "stdout.txt") << read_text(dir / "stderr.txt");

  const auto main_run = read_comparisons(dir / "out" / "validation.csv");
  const auto variant = read_comparisons(dir / "out" / "validation.csv", "adami");
  for (const char* id : {"buchner.pressure", "buchner.pressure_impact", "buchner.pressure_plateau",
                         "buchner.pressure_second_impact"}) {
    ASSERT_TRUE(main_run.count(id)) << id;
    ASSERT_TRUE(variant.count(id)) << id;
    EXPECT_TRUE(std::isfinite(variant.at(id).first)) << id;
  }
  // Another wall treatment, another run: its wall pressure differs from the mDBC walls'.
  EXPECT_NE(variant.at("buchner.pressure").first, main_run.at("buchner.pressure").first);
  EXPECT_TRUE(fs::exists(dir / "out" / "variants" / "adami" / "runs" / "buchner" / "probes" / "wall_pressure.csv"));
  // The checks are the main run's only.
  EXPECT_EQ(read_checks(dir / "out" / "checks.csv").size(), 3u);
  const std::string html = read_text(dir / "out" / "report.html");
  EXPECT_NE(html.find("<th>RMS, adami</th>"), std::string::npos);
  EXPECT_NE(html.find("Variant adami: physics.wall_boundary=adami"), std::string::npos);
  // One plot, the main run's, with the variant's curve drawn dashed on it and named in its legend.
  std::size_t figures = 0;
  for (auto pos = html.find("<svg"); pos != std::string::npos; pos = html.find("<svg", pos + 1)) ++figures;
  EXPECT_EQ(figures, 1u);
  EXPECT_NE(html.find("stroke-dasharray"), std::string::npos);
  EXPECT_NE(html.find(">adami</text>"), std::string::npos);
  const std::string table = read_text(dir / "stdout.txt");
  EXPECT_NE(table.find("adami = physics.wall_boundary=adami"), std::string::npos) << table;
  EXPECT_NE(table.find(fmt::format("{:.3f}", variant.at("buchner.pressure").first)), std::string::npos) << table;
  // Beside the main run's moved row, the variant's RMS moved by its own best constant, and that constant.
  ASSERT_TRUE(variant.count("buchner.pressure_moved"));
  EXPECT_NE(table.find(fmt::format("{:.3f} (", variant.at("buchner.pressure_moved").first)), std::string::npos) << table;

  std::error_code ec;
  fs::remove_all(dir, ec);
}

// SPHERIC test 2 (3D) at the quick resolution, dx = 0.05 m (H/dx = 11), over its first 0.8 s: the
// water released from the reservoir reaches the obstacle, P1 rises at the experiment's impact time
// within the quick bound, and the water levels follow the experiment's. About 40 s on one core.
TEST(QuickValidation, Spheric2ReachesTheObstacleOnTime) {
  const fs::path dir = fs::temp_directory_path() / fmt::format("sluice_validate_spheric2_{}", ::getpid());
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string command =
      fmt::format("'{}' validate --quick --case spheric2 --set time.end=0.8 --threads 1 -q -o '{}' > '{}' 2> '{}'",
                  SLUICE_BIN, (dir / "out").string(), (dir / "stdout.txt").string(), (dir / "stderr.txt").string());
  const int status = std::system(command.c_str());
  EXPECT_EQ(WIFEXITED(status) ? WEXITSTATUS(status) : -1, 0) << read_text(dir / "stdout.txt") << read_text(dir / "stderr.txt");
  const std::string html = read_text(dir / "out" / "report.html");
  std::size_t figures = 0;
  for (auto pos = html.find("<svg"); pos != std::string::npos; pos = html.find("<svg", pos + 1)) ++figures;
  EXPECT_EQ(figures, 6u);  // P1-P4, H2, H4
  EXPECT_NE(html.find("SPHERIC test 2"), std::string::npos);
  // The collapse's timing is in the notes (measured at this resolution: H2 wet at 0.411 s against
  // 0.353 s, H4's fall 0.025 s behind the experiment's).
  EXPECT_NE(html.find("The collapse: the water reaches H2"), std::string::npos);
  EXPECT_NE(html.find("The reservoir&#39;s level at H4 falls"), std::string::npos);
  const auto c = read_checks(dir / "out" / "checks.csv");
  const auto m = read_comparisons(dir / "out" / "validation.csv");
  ASSERT_TRUE(c.count("spheric2.p1_impact_time"));
  for (const char* id : {"spheric2.P1", "spheric2.P4", "spheric2.H2", "spheric2.H4"}) ASSERT_TRUE(m.count(id)) << id;
  for (const auto& [id, value] : m) std::cout << "measured " << id << " RMS = " << value.first << "\n";
  // Measured at this resolution over 0.8 s with the case's mDBC walls: impact 0.041 s late, H2 RMS
  // 0.014 m, H4 RMS 0.006 m (the dynamic walls: 0.087 s, 0.049 m and 0.021 m over 1 s). The bounds
  // leave room for another instruction set's round-off, not for the dynamic walls' numbers.
  EXPECT_LE(c.at("spheric2.p1_impact_time"), 0.07);
  EXPECT_LE(m.at("spheric2.H2").first, 0.03);
  EXPECT_LE(m.at("spheric2.H4").first, 0.015);
  // The reservoir drains: H4's largest difference stays within a few particle spacings.
  EXPECT_LE(m.at("spheric2.H4").second, 0.06);
  std::error_code ec;
  fs::remove_all(dir, ec);
}

// The floating box at --quick's dx = 0.02 m: its draft within the quick bound of the validation's
// (measured 4.2 % short there), the water level and the box's bottom plotted.
TEST(QuickValidation, AFloatingBoxSettlesAtItsDraft) {
  const fs::path dir = fs::temp_directory_path() / fmt::format("sluice_validate_bodies_{}", ::getpid());
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string command =
      fmt::format("'{}' validate --quick --case floating_box --threads 2 -q -o '{}' > '{}' 2> '{}'", SLUICE_BIN,
                  (dir / "out").string(), (dir / "stdout.txt").string(), (dir / "stderr.txt").string());
  const int status = std::system(command.c_str());
  const std::string out = read_text(dir / "stdout.txt");
  EXPECT_EQ(WIFEXITED(status) ? WEXITSTATUS(status) : -1, 0) << out << read_text(dir / "stderr.txt");
  EXPECT_NE(out.find("PASS floating_box: draft error"), std::string::npos) << out;
  const auto c = read_checks(dir / "out" / "checks.csv");
  ASSERT_TRUE(c.count("floating_box.draft"));
  EXPECT_LE(c.at("floating_box.draft"), 6.0);
  const std::string html = read_text(dir / "out" / "report.html");
  EXPECT_NE(html.find("box bottom (sluice)"), std::string::npos);
  // Afloat, the water's vertical force carries the box's weight, 500 x 0.3 x 0.2 x 9.81 N/m, within
  // 1 % on average from 2 s on.
  std::ifstream body(dir / "out" / "runs" / "floating_box" / "bodies" / "box.csv");
  std::string line;
  std::getline(body, line);
  double sum = 0.0;
  int n = 0;
  while (std::getline(body, line)) {
    std::vector<double> v;
    std::stringstream fields(line);
    for (std::string f; std::getline(fields, f, ',');) v.push_back(std::stod(f));
    if (v.size() > 8 && v[0] >= 2.0) sum += v[8], ++n;
  }
  ASSERT_GT(n, 0);
  const double weight = 500.0 * 0.3 * 0.2 * 9.81;
  EXPECT_NEAR(sum / n, weight, 0.01 * weight);
  std::error_code ec;
  fs::remove_all(dir, ec);
}

namespace {

struct Outcome {
  int status = -1;
  std::string err;
};

Outcome run_sluice(const std::string& args) {
  const fs::path err = fs::temp_directory_path() / fmt::format("sluice_analysis_cli_{}.txt", ::getpid());
  const int status = std::system(fmt::format("'{}' {} > /dev/null 2> '{}'", SLUICE_BIN, args, err.string()).c_str());
  Outcome o{WIFEXITED(status) ? WEXITSTATUS(status) : -1, read_text(err)};
  fs::remove(err);
  return o;
}

}  // namespace

// Bad input to analyze, convergence and validate: exit status 2 and a message naming what is wrong,
// before anything runs.
TEST(AnalysisCommands, BadInputIsAClearError) {
  const struct {
    std::string args, expected;
  } cases[] = {
      {"analyze /nonexistent/run", "/nonexistent/run: no such directory"},
      {"analyze " + fs::temp_directory_path().string(), "no checkpoint.bin"},
      {"convergence dam_break --dx 0.2,0.1", "needs at least 3 spacings; got 2"},
      {"convergence dam_break --dx 0.2,abc,0.1", "'abc' is not a positive number"},
      {"convergence dam_break --dx 0.2,0.1,0.1", "0.1 is given twice"},
      {"convergence no_such_case --dx 0.2,0.1,0.05", "no_such_case: no such case file"},
      {"validate --case no_such_case", "--case no_such_case: no validation case of that name"},
      {"validate --quick --set physics.wall_boundary=adamy", "physics.wall_boundary"},
      {"validate --quick --set physics.wall_boundary=adamy", "expected one of \"dynamic\", \"adami\""},
      {"validate --set domain.no_such_key=1", "domain.no_such_key"},
      {"validate --case spheric2 --set 'physics.gravity=[0, -9.81]'", "2 components in a 3D case"},
      // A case changed away from its experiment is refused before it runs, not after.
      {"validate --case spheric2 --set 'water[0].max=[3.22, 1.0, 0.5]'", "the SPHERIC test 2 data are for a 3D tank"},
      {"validate --case buchner --set tank.width=3.5", "the Buchner data are for a column 2H wide"},
      {"validate --case martin_moyce --set 'physics.gravity=[0.1, -9.81]'", "assume gravity straight down"},
      // The wave cases: wave_flume without its damping zone, an NTNU run driven by another run's paddle.
      {"validate --case wave_flume --set damping.length=0", "needs its wave maker (law = \"wave\") and its damping"},
      {"validate --waves --case ntnu_1062 --set wall[1].rotation.file=ntnu_flume2025_1102.csv",
       "the flap (wall[1]) must be driven by the record ntnu_flume2025_1062.csv"},
      // The floating-body cases: the box given by its mass, validate asked for two families at once.
      {"validate --case floating_box --set wall[0].floating.density=0 --set wall[0].floating.mass=30",
       "the buoyancy check needs its floating box 'box' given by its density"},
      {"validate --bodies --waves", "--waves and --bodies: expected one of them"},
      // The NTNU section in waves: held in 2062, free in 3061_1 and 3102_1, run to the window's end.
      {"validate --case ntnu_forces_2062 --set 'wall[2].floating.lock=[\"x\"]'", "run 2062 held the model"},
      {"validate --case ntnu_motions_3061_1 --set 'wall[2].floating.lock=[\"rz\"]'",
       "the model was free in sway, heave and roll; nothing may be locked"},
      {"validate --case ntnu_motions_3102_1 --set time.end=20", "the run must reach t = 26 s"},
      {"validate --case ntnu_motions_3102_1 --set wall[1].rotation.time_offset=-13",
       "must follow the record ntnu_flume2025_3102_1.csv from its time 12.04 s"},
      {"validate --case floating_box_3d --set wall[0].floating.density=0 --set wall[0].floating.mass=9",
       "the buoyancy check needs its floating box 'box' given by its density"},
      // The cases' wall function is refused with dynamic walls: the message says how to switch it off.
      {"validate --case buchner --set physics.wall_boundary=dynamic",
       "put physics.wall_friction=none before the walls"},
      {"validate --case buchner --compare 'd: physics.wall_boundary=dynamic'", "--compare 'd': "},
      // The variants of --compare: their syntax, their labels, and their overrides, before anything runs.
      {"validate --compare physics.wall_boundary=mdbc", "no label"},
      {"validate --compare 'a/b: physics.wall_boundary=mdbc'", "is not a plain name"},
      {"validate --compare 'mdbc:'", "no KEY=VALUE after the label"},
      {"validate --compare 'w: physics.shifting=1' --compare 'w: physics.shifting=2'", "the label 'w' is given twice"},
      {"validate --quick --compare 'w: physics.wall_boundary=adamy'", "expected one of \"dynamic\", \"adami\""},
      {"validate --case buchner --compare 'w: tank.width=3.5'", "the Buchner data are for a column 2H wide"},
  };
  for (const auto& c : cases) {
    const Outcome o = run_sluice(c.args);
    EXPECT_EQ(o.status, 2) << c.args << "\n" << o.err;
    EXPECT_NE(o.err.find("sluice: error: "), std::string::npos) << c.args << "\n" << o.err;
    EXPECT_NE(o.err.find(c.expected), std::string::npos) << c.args << "\n" << o.err;
  }
  // The wall-function hint is given where switching the wall function off would have been enough,
  // and only there: not for a refusal of something else, nor where the user keeps the wall function.
  const struct {
    std::string args;
    bool hint;
  } hints[] = {
      {"validate --case buchner --compare 'd: physics.wall_boundary=dynamic'", true},
      {"validate --case buchner --set physics.wall_boundary=dynamic --set physics.shifting=-1", false},
      {"validate --case buchner --set physics.wall_boundary=adamy", false},
      {"validate --case buchner --set physics.wall_slip=no_slip --set physics.wall_friction=log_law", false},
  };
  for (const auto& c : hints) {
    const Outcome o = run_sluice(c.args);
    EXPECT_EQ(o.status, 2) << c.args << "\n" << o.err;
    EXPECT_EQ(o.err.find("put physics.wall_friction=none before the walls") != std::string::npos, c.hint)
        << c.args << "\n" << o.err;
  }
}
