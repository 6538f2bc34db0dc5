// The sluice command line, run as a real subprocess: help and version, `cases`, `init` and its
// round trip through `run`, built-in case names, and every kind of bad input: each must print
// "sluice: error: ..." naming what is wrong, exit with status 2 and create no output directory.
#include <gtest/gtest.h>

#include <fcntl.h>
#include <sys/wait.h>
#include <unistd.h>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <atomic>
#include <chrono>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <limits>
#include <regex>
#include <sstream>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace fs = std::filesystem;

namespace {

struct Result {
  int status = -1;  // exit status; -1 if the process did not exit normally
  std::string out, err;
};

std::string read_file(const fs::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

// Each test gets an empty temporary directory as the working directory of the binary, so the
// default output folder out/<name> lands there and "no output directory" can be checked exactly.
class Cli : public ::testing::Test {
 protected:
  void SetUp() override {
    static std::atomic<int> counter{0};
    dir_ = fs::temp_directory_path() /
           fmt::format("sluice_cli_{}_{}_{}_{}", ::testing::UnitTest::GetInstance()->current_test_info()->name(),
                       ::getpid(), counter++, std::chrono::steady_clock::now().time_since_epoch().count());
    fs::create_directories(dir_ / "work");
    work_ = dir_ / "work";
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }

  // Runs the sluice binary with `args` in the work directory.
  Result sluice(const std::vector<std::string>& args) {
    std::vector<std::string> argv_strings = {SLUICE_BIN};
    argv_strings.insert(argv_strings.end(), args.begin(), args.end());
    return command(std::move(argv_strings));
  }

  // Runs argv_strings[0] (a path) with the other arguments, in the work directory.
  Result command(std::vector<std::string> argv_strings) {
    const fs::path out_file = dir_ / "stdout.txt", err_file = dir_ / "stderr.txt";
    std::vector<char*> argv;
    for (auto& a : argv_strings) argv.push_back(a.data());
    argv.push_back(nullptr);
    const pid_t pid = ::fork();
    if (pid < 0) {
      ADD_FAILURE() << "fork failed";
      return {};
    }
    if (pid == 0) {
      const int out = ::open(out_file.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      const int err = ::open(err_file.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
      if (out < 0 || err < 0 || ::dup2(out, 1) < 0 || ::dup2(err, 2) < 0 || ::chdir(work_.c_str()) != 0) ::_exit(127);
      ::execv(argv[0], argv.data());
      ::_exit(127);
    }
    int wstatus = 0;
    while (::waitpid(pid, &wstatus, 0) < 0) {
    }
    Result r;
    r.status = WIFEXITED(wstatus) ? WEXITSTATUS(wstatus) : -1;
    r.out = read_file(out_file);
    r.err = read_file(err_file);
    return r;
  }

  fs::path write(const std::string& name, const std::string& text) {
    std::ofstream(work_ / name, std::ios::binary) << text;
    return work_ / name;
  }

  // The work directory holds nothing but `expected` (file names).
  void expect_only(std::initializer_list<std::string> expected) {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(work_)) names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    std::vector<std::string> want(expected);
    std::sort(want.begin(), want.end());
    EXPECT_EQ(names, want) << "the work directory should hold only the given files (no output directory)";
  }

  fs::path dir_, work_;
};

// Keeps runs tiny: a coarse lattice and a few steps.
const std::vector<std::string> tiny = {"--set", "time.end=0.02", "--set", "domain.dx=0.4", "-q"};

std::vector<std::string> with_tiny(std::vector<std::string> args) {
  args.insert(args.end(), tiny.begin(), tiny.end());
  return args;
}

void expect_contains(const std::string& text, std::initializer_list<std::string> parts) {
  for (const auto& part : parts)
    EXPECT_NE(text.find(part), std::string::npos) << "text:  " << text << "\nlacks: " << part;
}

// A bad-input failure: status 2, nothing on stdout, one "sluice: error:" message on stderr that
// contains `parts`.
void expect_bad_input(const Result& r, std::initializer_list<std::string> parts) {
  EXPECT_EQ(r.status, 2) << "stderr: " << r.err;
  EXPECT_EQ(r.out, "");
  EXPECT_EQ(r.err.rfind("sluice: error: ", 0), 0u) << r.err;
  expect_contains(r.err, parts);
}

const std::string minimal_water = "[[water]]\nmin = [0.0, 0.0]\nmax = [2.0, 1.0]\n";

}  // namespace

// ---------------------------------------------------------------------------------------------
// Help and version

TEST_F(Cli, Help) {
  for (const char* flag : {"--help", "-h"}) {
    const Result r = sluice({flag});
    EXPECT_EQ(r.status, 0) << r.err;
    expect_contains(r.out, {"Usage:", "run", "cases", "init", "--version", "sluice <command> --help"});
    EXPECT_EQ(r.err, "");
  }
}

TEST_F(Cli, Version) {
  const Result r = sluice({"--version"});
  EXPECT_EQ(r.status, 0);
  EXPECT_TRUE(std::regex_match(r.out, std::regex(R"(sluice \d+\.\d+\.\d+\npair loop: \w+ \(this CPU runs [\w, ]+\)\n)")))
      << r.out;
}

// sluice restarts itself to choose the OpenMP wait policy, except under valgrind, whose tool refuses
// to be restarted directly (callgrind is how the pair loop's instruction counts are profiled).
TEST_F(Cli, RunsUnderValgrind) {
#if defined(__SANITIZE_ADDRESS__) || defined(__SANITIZE_THREAD__)
  GTEST_SKIP() << "a sanitizer build cannot run under valgrind";
#endif
  if (!fs::exists("/usr/bin/valgrind")) GTEST_SKIP() << "valgrind is not installed";
  const Result r = command({"/usr/bin/valgrind", "--tool=none", "-q", SLUICE_BIN, "--version"});
  // Valgrind 3.19 (Debian 12) on AMD EPYC stops at an instruction of libhwy's own start-up timer
  // (hwy::platform::TimerResolution), before sluice's code runs: not this test's subject.
  if (r.status != 0 && r.err.find("SIGILL") != std::string::npos && r.err.find("libhwy") != std::string::npos)
    GTEST_SKIP() << "valgrind cannot run libhwy's start-up on this CPU:\n" << r.err;
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(r.out.rfind("sluice ", 0) == 0) << r.out;
}

TEST_F(Cli, RunHelp) {
  const Result r = sluice({"run", "--help"});
  EXPECT_EQ(r.status, 0) << r.err;
  expect_contains(r.out, {"case", "-o,--output", "--set", "domain.dx=0.1", "--threads", "--restart", "-q,--quiet"});
  expect_only({});
}

TEST_F(Cli, CasesHelp) {
  const Result r = sluice({"cases", "--help"});
  EXPECT_EQ(r.status, 0) << r.err;
  expect_contains(r.out, {"List the built-in cases"});
}

TEST_F(Cli, InitHelp) {
  const Result r = sluice({"init", "--help"});
  EXPECT_EQ(r.status, 0) << r.err;
  expect_contains(r.out, {"file", "--from", "--force", "commented case file"});
  expect_only({});  // --help writes no case.toml
}

// ---------------------------------------------------------------------------------------------
// Command-line mistakes

TEST_F(Cli, NoCommand) { expect_bad_input(sluice({}), {"no command given", "run, cases, init", "sluice --help"}); }

TEST_F(Cli, UnknownCommand) {
  expect_bad_input(sluice({"rn"}), {"unknown command 'rn'", "did you mean 'run'?"});
  expect_bad_input(sluice({"simulate"}), {"unknown command 'simulate'", "expected one of: run, cases, init"});
}

TEST_F(Cli, UnknownOption) {
  expect_bad_input(sluice({"run", "--bogus"}), {"--bogus", "sluice run --help"});
  expect_bad_input(sluice({"--bogus"}), {"unknown option '--bogus'", "--help"});
  expect_bad_input(sluice({"cases", "extra"}), {"extra"});
  expect_only({});
}

TEST_F(Cli, ThreadsMustBePositive) {
  expect_bad_input(sluice(with_tiny({"run", "--threads", "0", "-o", "o"})), {"--threads", "0", "1"});
  expect_bad_input(sluice(with_tiny({"run", "--threads", "-3", "-o", "o"})), {"--threads"});
  expect_bad_input(sluice(with_tiny({"run", "--threads", "many", "-o", "o"})), {"--threads", "many"});
  expect_only({});
}

// --simd runs the pair loop on another instruction set this CPU runs (the last `sluice --version`
// lists, the portable one), and the run summary says which; an unknown one is refused, naming those.
TEST_F(Cli, SimdChoosesThePairLoopsInstructionSet) {
  const Result version = sluice({"--version"});
  std::smatch m;
  ASSERT_TRUE(std::regex_search(version.out, m, std::regex(R"(this CPU runs ([\w, ]+)\))"))) << version.out;
  const std::string list = m[1];
  const std::string last = list.substr(list.rfind(' ') + 1);
  const Result r = sluice(with_tiny({"run", "--simd", last, "-o", "o"}));
  EXPECT_EQ(r.status, 0) << r.err;
  expect_contains(r.out, {"pair loop   " + last + " "});
  expect_bad_input(sluice(with_tiny({"run", "--simd", "avx9000", "-o", "p"})),
                   {"--simd", "unknown or unsupported SIMD target 'avx9000'", list});
}

// --fixed-threads steps on --threads threads throughout; the summary says how many.
TEST_F(Cli, FixedThreadsKeepsTheCount) {
  const Result r = sluice(with_tiny({"run", "--threads", "2", "--fixed-threads", "-o", "o"}));
  EXPECT_EQ(r.status, 0) << r.err;
  expect_contains(r.out, {"threads     2\n"});
}

TEST_F(Cli, RestartTakesNoCase) {
  expect_bad_input(sluice({"run", "dam_break", "--restart", "x.bin", "-o", "o"}), {"--restart"});
  expect_only({});
}

// ---------------------------------------------------------------------------------------------
// Invalid case files: status 2, file:line:column, key, value, expectation, and no output directory

TEST_F(Cli, UnknownKeyInCaseFile) {
  write("bad.toml", "[domain]\nddx = 0.1\n" + minimal_water);
  const Result r = sluice(with_tiny({"run", "bad.toml", "-o", "o"}));
  expect_bad_input(r, {"bad.toml:2:7", "unknown key 'domain.ddx'", "did you mean 'domain.dx'?"});
  expect_only({"bad.toml"});
}

TEST_F(Cli, UnknownSectionInCaseFile) {
  write("bad.toml", "[domian]\ndx = 0.1\n" + minimal_water);
  expect_bad_input(sluice(with_tiny({"run", "bad.toml"})), {"bad.toml:1:1", "unknown section 'domian'", "'domain'"});
  expect_only({"bad.toml"});
}

TEST_F(Cli, BadValueInCaseFile) {
  write("bad.toml", "[case]\nname = \"bad\"\n[domain]\ndx = -0.5\n" + minimal_water);
  expect_bad_input(sluice({"run", "bad.toml", "-q"}),
                   {"bad.toml:4:6", "domain.dx = -0.5", "out of range", "expected a number from 0.0001 to 100 (m)"});
  expect_only({"bad.toml"});  // neither out/ nor out/bad
}

TEST_F(Cli, UnknownValueInCaseFile) {
  write("bad.toml", "[time]\nintegrator = \"rk4\"\n" + minimal_water);
  expect_bad_input(sluice(with_tiny({"run", "bad.toml", "-o", "o"})),
                   {"bad.toml:2:14", "time.integrator", "rk4", "one of \"predictor_corrector\", \"euler\", \"leapfrog\""});
  expect_only({"bad.toml"});
}

TEST_F(Cli, BadSyntaxInCaseFile) {
  write("bad.toml", "[domain]\ndx = = 0.1\n");
  expect_bad_input(sluice(with_tiny({"run", "bad.toml", "-o", "o"})), {"bad.toml:2:", "not valid TOML"});
  expect_only({"bad.toml"});
}

TEST_F(Cli, MissingRequiredKeyInCaseFile) {
  write("bad.toml", "[[water]]\nmin = [0.0, 0.0]\n");
  expect_bad_input(sluice(with_tiny({"run", "bad.toml", "-o", "o"})), {"bad.toml:1:1", "[[water]] number 1 has no 'max'"});
  expect_only({"bad.toml"});
}

TEST_F(Cli, InconsistentCaseFile) {
  write("bad.toml", "[tank]\nwidth = 1.0\n" + minimal_water);
  expect_bad_input(sluice(with_tiny({"run", "bad.toml", "-o", "o"})), {"bad.toml", "reaches outside the tank"});
  write("bad2.toml", "[case]\nname = \"../escape\"\n" + minimal_water);
  expect_bad_input(sluice({"run", "bad2.toml", "-q"}), {"bad2.toml", "case.name", "not a usable name"});
  expect_only({"bad.toml", "bad2.toml"});
  EXPECT_FALSE(fs::exists(dir_ / "escape"));
}

// A floating body's bad input: each a message naming what was wrong, exit status 2, nothing written;
// one denser than the water is a warning, and runs.
TEST_F(Cli, FloatingBodiesBadInput) {
  const auto run = [&](const std::string& set) {
    return sluice({"run", "floating_box", "-q", "-o", "o", "--set", "domain.dx=0.05", "--set", set});
  };
  expect_bad_input(run("wall[0].min=[-0.1, 0.45]"),
                   {"wall 1 (box) leaves the tank through the wall at the low end of x at the start",
                    "a floating body must start inside the tank"});
  expect_bad_input(run("wall[0].floating.inertia=[0]"), {"wall[0].floating.inertia = [0]", "is not positive"});
  expect_bad_input(run("wall[0].floating.lock=[\"rx\"]"), {"\"rx\" is not a degree of freedom of a 2D body"});
  expect_bad_input(run("wall[0].floating.stiffness=[0, 10, 0]"), {"the spring on y (stiffness 10) has no anchor"});
  expect_bad_input(run("wall[0].floating.mass=2.0"), {"expected one of them"});
  expect_only({});
  const Result heavy = sluice({"run", "floating_box", "-o", "o", "--set", "domain.dx=0.05", "--set", "time.end=0.01",
                               "--set", "wall[0].floating.density=1200"});
  EXPECT_EQ(heavy.status, 0) << heavy.err;
  expect_contains(heavy.err, {"warning: wall[0] (box) floats with a mean density of 1200 kg/m^3, above the water's "
                              "1000: it will sink"});
}

// A probe outside the tank would record zeros for the whole run.
TEST_F(Cli, ProbeOutsideTheTank) {
  write("bad.toml", "[tank]\nwidth = 2.0\nheight = 1.5\n" + minimal_water +
                        "[[probe]]\nname = \"far\"\ntype = \"pressure\"\npoint = [5.0, 0.1]\n");
  expect_bad_input(sluice(with_tiny({"run", "bad.toml"})),
                   {"bad.toml: [[probe]] \"far\" (a pressure probe at [5.0, 0.1]) lies outside the tank [0, 2] x [0, 1.5]"});
  expect_bad_input(sluice({"run", "sloshing", "--set", "probe[1].point=[2.5, 0]", "-q"}),
                   {"--set probe[1].point=[2.5, 0]", "[[probe]] \"gauge_right\" (a gauge on the vertical line through "
                    "[2.5, 0.0]) lies outside the tank [0, 2] x [0, 1.5]"});
  expect_only({"bad.toml"});
}

// A polygon whose edges cross has no single inside; the set-up would build a broken solid.
TEST_F(Cli, SelfIntersectingPolygon) {
  write("bad.toml", "[tank]\nwidth = 2.0\nheight = 1.5\n" + minimal_water +
                        "[[wall]]\nshape = \"polygon\"\npoints = [[1.0, 0.0], [1.6, 0.0], [1.0, 0.5], [1.3, 0.5]]\n");
  expect_bad_input(sluice(with_tiny({"run", "bad.toml"})),
                   {"bad.toml: [[wall]] number 1: the polygon crosses itself: edge 2 (from (1.6, 0) to (1, 0.5)) "
                    "crosses edge 4 (from (1.3, 0.5) to (1, 0))"});
  expect_only({"bad.toml"});
}

// A name too long for a file name was found only when the .pvd file was written, after frame 0.
TEST_F(Cli, CaseNameTooLongForAFileName) {
  for (const std::size_t length : {241, 300}) {
    SCOPED_TRACE(length);
    const std::string name(length, 'n');
    expect_bad_input(sluice(with_tiny({"run", "--set", "case.name=" + name})),
                     {"--set case.name=", "too long, " + std::to_string(length) + " bytes; expected at most 240 bytes"});
  }
  expect_only({});
  const Result r = sluice(with_tiny({"run", "--set", "case.name=" + std::string(240, 'n')}));
  EXPECT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(fs::is_regular_file(work_ / "out" / std::string(240, 'n') / (std::string(240, 'n') + ".pvd")));
}

TEST_F(Cli, MissingCaseFile) {
  expect_bad_input(sluice(with_tiny({"run", "nope.toml", "-o", "o"})), {"nope.toml", "no such case file", "sluice cases"});
  expect_only({});
}

TEST_F(Cli, CaseIsADirectory) {
  fs::create_directory(work_ / "adir");
  expect_bad_input(sluice(with_tiny({"run", "adir", "-o", "o"})), {"adir", "is a directory"});
  expect_only({"adir"});
}

// A mesh that is not closed (a cube without its top), from a case file; a missing mesh, from --set.
TEST_F(Cli, BadMeshFile) {
  std::string open = "solid open\n";
  const char* corners[10][3] = {{"0.1 0.1 0.1", "0.1 0.3 0.1", "0.3 0.3 0.1"}, {"0.1 0.1 0.1", "0.3 0.3 0.1", "0.3 0.1 0.1"},
                                {"0.1 0.1 0.1", "0.3 0.1 0.1", "0.3 0.1 0.3"}, {"0.1 0.1 0.1", "0.3 0.1 0.3", "0.1 0.1 0.3"},
                                {"0.1 0.3 0.1", "0.1 0.3 0.3", "0.3 0.3 0.3"}, {"0.1 0.3 0.1", "0.3 0.3 0.3", "0.3 0.3 0.1"},
                                {"0.1 0.1 0.1", "0.1 0.1 0.3", "0.1 0.3 0.3"}, {"0.1 0.1 0.1", "0.1 0.3 0.3", "0.1 0.3 0.1"},
                                {"0.3 0.1 0.1", "0.3 0.3 0.1", "0.3 0.3 0.3"}, {"0.3 0.1 0.1", "0.3 0.3 0.3", "0.3 0.1 0.3"}};
  for (const auto& t : corners)
    open += fmt::format("facet normal 0 0 0\nouter loop\nvertex {}\nvertex {}\nvertex {}\nendloop\nendfacet\n", t[0],
                        t[1], t[2]);
  write("open.stl", open + "endsolid open\n");
  write("bad.toml",
        "[domain]\ndimension = 3\n[tank]\nwidth = 1.0\ndepth = 1.0\nheight = 1.0\n"
        "[[water]]\nmin = [0.0, 0.0, 0.0]\nmax = [1.0, 1.0, 0.2]\n[[wall]]\nshape = \"mesh\"\nfile = \"open.stl\"\n");
  expect_bad_input(sluice(with_tiny({"run", "bad.toml"})),
                   {"bad.toml: [[wall]] number 1: mesh file \"open.stl\"", "it is not closed", "expected a closed surface"});
  expect_bad_input(sluice({"run", "dam_break_3d", "--set", "wall[0].file=nowhere.stl", "-q"}),
                   {"--set wall[0].file=nowhere.stl", "mesh file \"nowhere.stl\"", "no such file"});
  expect_only({"bad.toml", "open.stl"});
}

// The CRC-32 of zip and zlib (reflected, polynomial 0xEDB88320), as a checkpoint ends with.
std::uint32_t crc32_of(std::string_view bytes) {
  std::uint32_t crc = 0xFFFFFFFFu;
  for (const char ch : bytes) {
    crc ^= static_cast<unsigned char>(ch);
    for (int k = 0; k < 8; ++k) crc = (crc >> 1) ^ (0xEDB88320u & (0u - (crc & 1u)));
  }
  return ~crc;
}

// A checkpoint whose field name holds a terminal escape sequence: the message shows it escaped, and
// no control character reaches the terminal, from `run --restart` and from `analyze`.
TEST_F(Cli, TextFromAFileIsShownEscaped) {
  ASSERT_EQ(sluice(with_tiny({"run", "-o", "o"})).status, 0);
  std::string bytes = read_file(work_ / "o" / "checkpoint.bin");
  const auto at = bytes.rfind("velocity");
  ASSERT_NE(at, std::string::npos);
  bytes.replace(at, 8, "\x1b[31mred");
  const std::uint32_t crc = crc32_of(std::string_view(bytes).substr(0, bytes.size() - 4));
  std::memcpy(bytes.data() + bytes.size() - 4, &crc, 4);
  write("o/checkpoint.bin", bytes);
  for (const auto& args : {std::vector<std::string>{"run", "--restart", "o/checkpoint.bin", "-q"},
                           std::vector<std::string>{"analyze", "o"}}) {
    SCOPED_TRACE(args[0]);
    const Result r = sluice(args);
    EXPECT_NE(r.status, 0);
    expect_contains(r.err, {R"(not a usable checkpoint: field '\u001B[31mred' where 'velocity' was expected)"});
    for (const char c : r.err) EXPECT_TRUE(c == '\n' || (c >= 0x20 && c < 0x7f)) << r.err;
  }
}

// The .npz bytes with the first value of array `name` (a float64 array) set to `value`, and the zip
// CRC-32s of its entry (local header and central directory) made to match.
std::string with_first_value(std::string npz, const std::string& name, double value) {
  const std::string file = name + ".npy";
  const auto local = npz.find(std::string("PK\x03\x04", 4));
  auto u16 = [&](std::size_t at) { return static_cast<std::size_t>(static_cast<unsigned char>(npz[at])) |
                                          static_cast<std::size_t>(static_cast<unsigned char>(npz[at + 1])) << 8; };
  auto u32 = [&](std::size_t at) { return static_cast<std::uint32_t>(u16(at) | u16(at + 2) << 16); };
  for (std::size_t at = local; at != std::string::npos; at = npz.find(std::string("PK\x03\x04", 4), at + 4)) {
    if (npz.compare(at + 30, u16(at + 26), file) != 0) continue;
    const std::size_t data = at + 30 + u16(at + 26) + u16(at + 28), size = u32(at + 18);
    std::memcpy(npz.data() + data + 10 + u16(data + 8), &value, sizeof value);  // after the .npy header
    const std::uint32_t crc = crc32_of(std::string_view(npz).substr(data, size));
    std::memcpy(npz.data() + at + 14, &crc, 4);
    for (std::size_t c = npz.find(std::string("PK\x01\x02", 4)); c != std::string::npos;
         c = npz.find(std::string("PK\x01\x02", 4), c + 4))
      if (npz.compare(c + 46, u16(c + 28), file) == 0) std::memcpy(npz.data() + c + 16, &crc, 4);
    return npz;
  }
  ADD_FAILURE() << "no array " << name;
  return npz;
}

// Frames whose positions, time or spacing are not usable were drawn and measured: render refuses them
// as it does a damaged frame (exit status 1), analyze as bad input (2), both naming the frame's file.
TEST_F(Cli, RenderAndAnalyzeRefuseFramesThatAreNotFinite) {
  ASSERT_EQ(sluice(with_tiny({"run", "-o", "o"})).status, 0);
  const std::string frame = "o/frames/frame_000001.npz";
  const std::string good = read_file(work_ / frame);
  write(frame, with_first_value(good, "x", std::numeric_limits<double>::quiet_NaN()));
  const Result render = sluice({"render", "o", "-o", "o/speed.gif"});
  EXPECT_EQ(render.status, 1) << render.err;
  expect_contains(render.err, {"sluice: error: " + frame + ": not a sluice frame: the position of particle id 0 (row 0 "
                               "of x) is not finite: [nan, "});
  EXPECT_FALSE(fs::exists(work_ / "o" / "speed.gif"));
  expect_bad_input(sluice({"analyze", "o"}), {frame + ": not a sluice frame: the position of particle id 0"});
  write(frame, with_first_value(good, "t", std::numeric_limits<double>::quiet_NaN()));
  expect_bad_input(sluice({"analyze", "o"}), {frame + ": not a sluice frame: its time t = nan is not finite"});
  write(frame, with_first_value(good, "dx", 0.0));
  expect_bad_input(sluice({"analyze", "o"}), {frame + ": not a sluice frame: dx = 0 is not a positive spacing"});
  EXPECT_FALSE(fs::exists(work_ / "o" / "analysis"));
}

// ---------------------------------------------------------------------------------------------
// --set mistakes

TEST_F(Cli, SetUnknownKey) {
  expect_bad_input(sluice({"run", "--set", "domain.ddx=0.1", "-o", "o", "-q"}),
                   {"--set domain.ddx=0.1: unknown key 'domain.ddx'; did you mean 'domain.dx'?"});
  expect_bad_input(sluice({"run", "--set", "water[0].mx=[1, 1]", "-o", "o", "-q"}),
                   {"unknown key 'mx' in [[water]]", "did you mean 'water[0].max'?"});
  expect_only({});
}

TEST_F(Cli, SetBadValue) {
  expect_bad_input(sluice({"run", "--set", "domain.dx=0", "-o", "o", "-q"}),
                   {"--set domain.dx=0", "domain.dx = 0", "out of range", "a number from 0.0001 to 100 (m)"});
  expect_bad_input(sluice({"run", "--set", "time.integrator=eulr", "-o", "o", "-q"}),
                   {"time.integrator", "eulr", "did you mean \"euler\"?"});
  expect_bad_input(sluice({"run", "--set", "tank.lid=maybe", "-o", "o", "-q"}), {"tank.lid", "maybe", "true or false"});
  expect_only({});
}

TEST_F(Cli, SetMalformed) {
  expect_bad_input(sluice({"run", "--set", "domain.dx", "-o", "o", "-q"}), {"--set domain.dx: expected key=value"});
  expect_bad_input(sluice({"run", "--set", "domain.dx=", "-o", "o", "-q"}), {"no value after '='"});
  expect_bad_input(sluice({"run", "--set"}), {"--set", "missing"});
  expect_only({});
}

TEST_F(Cli, SetIndexOutOfRange) {
  expect_bad_input(sluice({"run", "--set", "water[2].max=[1.0, 1.0]", "-o", "o", "-q"}),
                   {"the case has 2 [[water]] entries (numbered from 0); there is no water[2]"});
  expect_only({});
}

TEST_F(Cli, SetMakesCaseInconsistent) {
  expect_bad_input(sluice({"run", "--set", "tank.width=2", "-q"}), {"--set tank.width=2", "reaches outside the tank"});
  expect_bad_input(sluice({"run", "--set", "case.name=..", "-q"}), {"case.name", "not a usable name"});
  expect_only({});
}

// ---------------------------------------------------------------------------------------------
// cases, run with a built-in name or none, init

TEST_F(Cli, CasesListsEachBuiltInCaseOnOneLine) {
  const Result r = sluice({"cases"});
  EXPECT_EQ(r.status, 0) << r.err;
  std::vector<std::string> expected;
  for (const auto& e : fs::directory_iterator(fs::path(SLUICE_SOURCE_DIR) / "cases"))
    if (e.path().extension() == ".toml") expected.push_back(e.path().stem().string());
  std::sort(expected.begin(), expected.end());
  ASSERT_FALSE(expected.empty());
  std::vector<std::string> listed;
  std::istringstream in(r.out);
  for (std::string line; std::getline(in, line);) {
    const auto space = line.find(' ');
    ASSERT_NE(space, std::string::npos) << "no description: " << line;
    EXPECT_NE(line.find_first_not_of(' ', space), std::string::npos) << "no description: " << line;
    listed.push_back(line.substr(0, space));
  }
  EXPECT_EQ(listed, expected);
  expect_contains(r.out, {"dam_break "});
}

TEST_F(Cli, RunBuiltInCaseByName) {
  const Result r = sluice(with_tiny({"run", "dam_break"}));
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(fs::is_regular_file(work_ / "out" / "dam_break" / "summary.txt"));
  expect_contains(r.out, {"dam_break"});
}

TEST_F(Cli, BuiltInNameNotHiddenByADirectory) {
  // The output of `sluice run dam_break -o dam_break` must not stop the next `sluice run dam_break`.
  fs::create_directory(work_ / "dam_break");
  const Result r = sluice(with_tiny({"run", "dam_break", "-o", "dam_break"}));
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(fs::is_regular_file(work_ / "dam_break" / "summary.txt"));
}

TEST_F(Cli, RunWithoutCaseRunsTheDefault) {
  const Result r = sluice(with_tiny({"run", "--threads", "1", "-o", "default_out"}));
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(fs::is_regular_file(work_ / "default_out" / "summary.txt"));
  expect_contains(read_file(work_ / "default_out" / "summary.txt"), {"dam_break"});
  expect_only({"default_out"});
}

TEST_F(Cli, SetOverridesReachTheRun) {
  // Several --set forms at once, including item keys and bare words; the summary shows they took.
  const Result r = sluice(with_tiny({"run", "-o", "o", "--set", "case.name=renamed", "--set", "tank.width=4", "--set",
                           "water.0.max=[4.0, 2.0]", "--set", "water[1].max=[1.0, 3.0]", "--set",
                           "time.integrator=euler", "--set", "time.cfl=0.1", "--set", "output.formats=npz"}));
  ASSERT_EQ(r.status, 0) << r.err;
  expect_contains(r.out, {"case 'renamed'"});
  EXPECT_TRUE(fs::is_regular_file(work_ / "o" / "summary.txt"));
  EXPECT_FALSE(fs::exists(work_ / "o" / "renamed.pvd"));  // only npz frames asked for
}

TEST_F(Cli, SinglePrecisionPairsRunAndTheSummarySaysSo) {
  const Result r = sluice(with_tiny({"run", "-o", "o", "--set", "domain.pair_precision=single"}));
  ASSERT_EQ(r.status, 0) << r.err;
  expect_contains(r.out, {"single precision"});
  const Result d = sluice(with_tiny({"run", "-o", "d"}));
  ASSERT_EQ(d.status, 0) << d.err;
  expect_contains(d.out, {"double precision"});
  const Result bad = sluice(with_tiny({"run", "-o", "b", "--set", "domain.pair_precision=half"}));
  EXPECT_EQ(bad.status, 2);
  expect_contains(bad.err, {"domain.pair_precision", "\"half\"", "\"double\", \"single\""});
}

TEST_F(Cli, InitThenRunUnchanged) {
  const Result init = sluice({"init", "x.toml"});
  ASSERT_EQ(init.status, 0) << init.err;
  expect_contains(init.out, {"x.toml", "sluice run x.toml"});
  const std::string text = read_file(work_ / "x.toml");
  expect_contains(text, {"# ", "[case]", "[domain]", "dx = ", "unit: m", "default: ", "allowed: ", "[[water]]"});
  // The template, exactly as written (only the end time shortened on the command line).
  const Result run = sluice({"run", "x.toml", "--set", "time.end=0.02", "-o", "DIR", "-q"});
  ASSERT_EQ(run.status, 0) << run.err;
  EXPECT_TRUE(fs::is_regular_file(work_ / "DIR" / "summary.txt"));
  EXPECT_EQ(read_file(work_ / "x.toml"), text);
}

// A user's new case gets the walls validation chose for wall pressures (docs/validation.md,
// "Defaults"); the built-in dam break keeps dynamic walls by saying so in its own file.
TEST_F(Cli, InitWritesTheValidatedSettings) {
  ASSERT_EQ(sluice({"init", "new.toml"}).status, 0);
  expect_contains(read_file(work_ / "new.toml"),
                  {"name = \"water_column\"", "h_over_dx = 2.0", "wall_boundary = \"mdbc\"", "wall_slip = \"free_slip\"",
                   "wall_friction = \"auto\"", "shifting = 2.0"});
  ASSERT_EQ(sluice({"init", "dam.toml", "--from", "dam_break"}).status, 0);
  expect_contains(read_file(work_ / "dam.toml"),
                  {"h_over_dx = 1.3", "wall_boundary = \"dynamic\"", "wall_friction = \"none\"", "shifting = 0.0"});
}

TEST_F(Cli, InitDefaultFileName) {
  const Result r = sluice({"init"});
  ASSERT_EQ(r.status, 0) << r.err;
  EXPECT_TRUE(fs::is_regular_file(work_ / "case.toml"));
}

TEST_F(Cli, InitRefusesToOverwrite) {
  write("x.toml", "# mine\n");
  const Result r = sluice({"init", "x.toml"});
  expect_bad_input(r, {"x.toml", "already exists", "--force"});
  EXPECT_EQ(read_file(work_ / "x.toml"), "# mine\n");
  const Result forced = sluice({"init", "x.toml", "--force"});
  ASSERT_EQ(forced.status, 0) << forced.err;
  expect_contains(read_file(work_ / "x.toml"), {"[domain]"});
}

TEST_F(Cli, InitIntoADirectory) {
  fs::create_directory(work_ / "adir");
  for (const bool force : {false, true}) {
    expect_bad_input(sluice(force ? std::vector<std::string>{"init", "adir", "--force"} : std::vector<std::string>{"init", "adir"}),
                     {"adir: is a directory", "adir/case.toml"});
  }
  expect_only({"adir"});
  EXPECT_TRUE(fs::is_empty(work_ / "adir"));
}

TEST_F(Cli, InitFromUnknownCase) {
  expect_bad_input(sluice({"init", "x.toml", "--from", "nope"}), {"--from nope", "no built-in case", "sluice cases"});
  expect_only({});
}

TEST_F(Cli, InitFromEveryBuiltInCaseIsAccepted) {
  // `sluice run` accepts each template unchanged: run to t = 0 (set-up and the first frame only), since
  // a coarse --set domain.dx might not fit a small built-in tank.
  for (const auto& e : fs::directory_iterator(fs::path(SLUICE_SOURCE_DIR) / "cases")) {
    if (e.path().extension() != ".toml") continue;
    const std::string name = e.path().stem().string();
    SCOPED_TRACE(name);
    const std::string file = name + "_template.toml";
    ASSERT_EQ(sluice({"init", file, "--from", name}).status, 0);
    const Result run = sluice({"run", file, "-o", "o_" + name, "--set", "time.end=0", "-q"});
    EXPECT_EQ(run.status, 0) << run.err;
  }
}

TEST_F(Cli, ReadmeErrorExamplesAreExact) {
  // The README's "Case files" section shows `$ sluice run --set ...` commands followed by their
  // error: each must be what the binary prints.
  const std::string readme = read_file(fs::path(SLUICE_SOURCE_DIR) / "README.md");
  std::istringstream in(readme);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  int checked = 0;
  for (std::size_t i = 0; i + 1 < lines.size(); ++i) {
    if (lines[i].rfind("$ sluice run --set ", 0) != 0) continue;
    if (lines[i + 1].rfind("sluice: error: ", 0) != 0) continue;
    SCOPED_TRACE(lines[i]);
    std::istringstream words(lines[i].substr(2));
    std::vector<std::string> args;
    for (std::string w; words >> w;) args.push_back(w);
    args.erase(args.begin());  // "sluice"
    args.push_back("-q");
    const Result r = sluice(args);
    EXPECT_EQ(r.status, 2);
    EXPECT_EQ(r.err, lines[i + 1] + "\n");
    ++checked;
  }
  EXPECT_GE(checked, 2) << "the README's examples of --set errors were not found";
  expect_only({});
}

// ---------------------------------------------------------------------------------------------
// Settings within their documented ranges that once ended in a segmentation fault: each run either
// finishes or stops with the instability guard's message (status 1), never with a signal.

TEST_F(Cli, ValidSettingsThatOnceCrashedRunToTheirEnd) {
  const std::vector<std::vector<std::string>> runs = {
      // gamma = 1 with the hydrostatic squeeze (the still water case has it): its closed form was 0/0.
      {"run", "still_water_3d", "--set", "fluid.gamma=1", "--set", "time.end=0.02"},
      {"run", "dam_break", "--set", "fluid.gamma=1.0", "--set", "physics.hydrostatic_squeeze=true", "--set",
       "time.end=0.02"},
      // mDBC under a strong sideways gravity: a ghost's hydrostatic correction past the Tait equation's
      // tension limit gave a NaN density, and the NaN position that followed a cell index out of bounds.
      {"run", "dam_break", "--set", "physics.wall_boundary=mdbc", "--set", "physics.gravity=[100.0,-9.81]", "--set",
       "time.end=0.05"},
  };
  int k = 0;
  for (std::vector<std::string> args : runs) {
    args.insert(args.end(), {"-q", "--threads", "1", "-o", fmt::format("o{}", k++)});
    const Result r = sluice(args);
    EXPECT_EQ(r.status, 0) << fmt::format("{}", fmt::join(args, " ")) << "\n" << r.err;
    expect_contains(r.out, {"all finite  yes"});
  }
}

// A set-up whose state the instability guard refuses (a 5 m column at c0 = 1 m/s is 2.3 times denser at
// the bottom under the hydrostatic start) is bad input: refused before anything is written.
TEST_F(Cli, AnUnusableInitialStateIsRefusedBeforeAnyOutput) {
  const Result r = sluice({"run", "dam_break", "--set", "fluid.sound_speed=1", "-q"});
  expect_bad_input(r, {"the case's initial state is unusable: ", "particles are bad; the first:",
                       "density outside (0.5, 2) rho0", "fluid.sound_speed"});
  expect_only({});
}

// Runaway outputs: an interval shorter than the time step (which would cut every step to it) or more
// frames than output.max_frames is refused before anything is written.
TEST_F(Cli, RunawayOutputsAreRefusedBeforeTheRun) {
  expect_bad_input(sluice({"run", "dam_break", "--set", "output.interval=1e-9", "-q"}),
                   {"output.interval = 1e-09 s is shorter than the time step (up to time.cfl h / c0 = 0.0026 s)",
                    "expected output.interval >= 0.0026 s"});
  expect_bad_input(sluice({"run", "dam_break", "--set", "time.dt=0.001", "--set", "output.checkpoint_interval=0.0005",
                           "-q"}),
                   {"output.checkpoint_interval = 0.0005 s is shorter than the time step (time.dt = 0.001 s)"});
  expect_bad_input(sluice({"run", "dam_break", "--set", "output.interval=0.003", "-q"}),
                   {"the run would write 10001 frames (time.end = 30 s every output.interval = 0.003 s), more than "
                    "output.max_frames = 10000"});
  expect_only({});
  const Result r = sluice({"run", "dam_break", "--set", "output.interval=0.003", "--set", "time.end=0.006", "-q", "-o",
                           "o"});
  EXPECT_EQ(r.status, 0) << r.err;
}

// A case whose particles cannot fit in memory is refused before the set-up allocates them (the tank
// filled at dx = 0.7 mm: up to 4.3e8 particles, about 171 GB), instead of the out-of-memory killer.
TEST_F(Cli, ACaseTooLargeForTheMemoryIsRefusedBeforeTheSetUp) {
  const Result r = sluice({"run", "dam_break", "--set", "water[0].max=[20.0, 10.0]", "--set", "domain.dx=0.0007", "-q"});
  expect_bad_input(r, {"domain.dx = 0.0007 m makes up to 4.", "particles, which need about 171 GB of memory",
                       "GB available; expected a larger domain.dx (memory goes as dx^-2)"});
  expect_only({});
}
