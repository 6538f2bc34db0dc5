// Whole-run benchmark: the default dam break at several resolutions, each measured in a child
// process (so that its peak memory is its own), reporting particle-steps and force evaluations per
// second, wall time, threads and peak memory per particle. Writes a CSV.
//
//   sluice-bench-run [--case dam_break] [--dx 0.07,0.022,0.01,0.007] [--threads 1,2]
//                    [--precision double,single] [--simd TARGET] [--steps N] [--csv FILE]
//
// --precision measures each resolution and thread count in each pair precision
// (domain.pair_precision), one after the other: a side-by-side ratio. --simd runs the pair loop
// compiled for another instruction set the CPU has (AVX2 on an AVX-512 machine, say).
#include <fmt/format.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iostream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "sluice/case/params.hpp"
#include "sluice/core/thread_waiting.hpp"
#include "sluice/physics/simd_target.hpp"
#include "sluice/simulation.hpp"

using namespace sluice;

namespace {

struct Result {
  double dx = 0;
  int threads = 0;
  bool single = false;
  long particles = 0;
  long steps = 0;
  int evaluations_per_step = 0;
  double wall = 0;
  double peak_bytes = 0;
};

double peak_rss_bytes() {
  std::ifstream status("/proc/self/status");
  std::string line;
  while (std::getline(status, line))
    if (line.rfind("VmHWM:", 0) == 0) return std::stod(line.substr(6)) * 1024.0;
  return 0.0;
}

std::vector<double> parse_list(const std::string& s) {
  std::vector<double> v;
  std::stringstream in(s);
  std::string item;
  while (std::getline(in, item, ',')) v.push_back(std::stod(item));
  return v;
}

// Runs in the child: set-up, a few warm-up steps, then timed steps (at least `steps`, and at
// least one second of wall time).
Result measure(const std::string& name, double dx, int threads, bool single, long steps) {
  Case c = *load_builtin_case(name);
  apply_override(c, fmt::format("domain.dx={}", dx));
  apply_override(c, single ? "domain.pair_precision=single" : "domain.pair_precision=double");
  Simulation sim(c, threads);
  for (int i = 0; i < 3; ++i) sim.step();
  Result r;
  r.dx = dx;
  r.threads = threads;
  r.single = single;
  r.particles = static_cast<long>(c.dimension == 3 ? sim.particles<3>().size() : sim.particles<2>().size());
  r.evaluations_per_step = sim.force_evaluations_per_step();
  const auto start = std::chrono::steady_clock::now();
  do {
    sim.step();
    ++r.steps;
    r.wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  } while (r.steps < steps || r.wall < 1.0);
  r.peak_bytes = peak_rss_bytes();
  return r;
}

bool measure_in_child(const std::string& name, double dx, int threads, bool single, long steps, Result& out) {
  int fd[2];
  if (pipe(fd) != 0) return false;
  const pid_t pid = fork();
  if (pid == 0) {
    close(fd[0]);
    const Result r = measure(name, dx, threads, single, steps);
    const bool ok = write(fd[1], &r, sizeof r) == static_cast<ssize_t>(sizeof r);
    _exit(ok ? 0 : 1);
  }
  close(fd[1]);
  const bool ok = read(fd[0], &out, sizeof out) == static_cast<ssize_t>(sizeof out);
  close(fd[0]);
  int status = 0;
  waitpid(pid, &status, 0);
  return ok && WIFEXITED(status) && WEXITSTATUS(status) == 0;
}

// Each thread count's speed over one thread's, at one dx and precision (runs of the same thread
// count averaged; the two are measured one after the other, so read them as a ratio of one run).
void print_speedups(double dx, const std::vector<std::tuple<int, bool, double>>& runs) {
  for (const bool single : {false, true}) {
    std::map<int, std::pair<double, int>> mean;  // threads -> (sum, count)
    for (const auto& [threads, s, evals] : runs)
      if (s == single) {
        mean[threads].first += evals;
        ++mean[threads].second;
      }
    const auto one = mean.find(1);
    if (one == mean.end()) continue;
    for (const auto& [threads, sum] : mean)
      if (threads > 1)
        fmt::print("{:>8} {} threads over one, {}: {:.2f}x\n", dx, threads, single ? "single" : "double",
                   (sum.first / sum.second) / (one->second.first / one->second.second));
  }
}

// Speed per particle of each size larger than the one nearest 100,000 particles, over that size's (one
// line per thread count and precision): the O(N) check, issue figures "1M within 15 % of 100k".
struct SizeRun {
  double dx;
  long particles;
  int threads;
  bool single;
  double evals;
};

void print_scaling(const std::vector<SizeRun>& runs) {
  if (runs.empty()) return;
  const auto distance = [](long n) { return std::abs(std::log(static_cast<double>(n) / 1e5)); };
  const SizeRun* reference = &runs.front();
  for (const SizeRun& r : runs)
    if (distance(r.particles) < distance(reference->particles)) reference = &r;
  const auto mean = [&](double dx, int threads, bool single) {
    double sum = 0.0;
    int count = 0;
    for (const SizeRun& r : runs)
      if (r.dx == dx && r.threads == threads && r.single == single) sum += r.evals, ++count;
    return count > 0 ? sum / count : 0.0;
  };
  std::set<std::tuple<double, int, bool>> done;
  for (const SizeRun& r : runs) {
    if (r.particles <= reference->particles || !done.insert({r.dx, r.threads, r.single}).second) continue;
    const double base = mean(reference->dx, r.threads, r.single);
    if (base <= 0.0) continue;
    fmt::print("{:>8} per particle over {} ({} particles), {} threads, {}: {:.2f}\n", r.dx, reference->dx,
               reference->particles, r.threads, r.single ? "single" : "double", mean(r.dx, r.threads, r.single) / base);
  }
}

}  // namespace

int main(int argc, char** argv) {
  restart_with_brief_spinning(argv);  // the threads wait as they do in `sluice run`
  std::vector<double> dxs = {0.07, 0.022, 0.01, 0.007};
  std::vector<double> thread_counts = {1, 2};
  long steps = 20;
  std::string csv = "bench/results.csv", name = "dam_break", precisions = "double";
  for (int a = 1; a < argc; ++a) {
    const std::string arg = argv[a];
    auto value = [&]() -> std::string {
      if (a + 1 >= argc) {
        std::cerr << "sluice-bench-run: " << arg << " needs a value\n";
        std::exit(2);
      }
      return argv[++a];
    };
    // A number that does not parse is an error naming the flag, not an uncaught exception.
    auto numbers = [&](auto parse) {
      const std::string text = value();
      try {
        return parse(text);
      } catch (const std::exception&) {
        std::cerr << "sluice-bench-run: " << arg << " takes a number or a comma-separated list of them, not '" << text << "'\n";
        std::exit(2);
      }
    };
    if (arg == "--dx") dxs = numbers(parse_list);
    else if (arg == "--threads") thread_counts = numbers(parse_list);
    else if (arg == "--steps") steps = numbers([](const std::string& t) { return std::stol(t); });
    else if (arg == "--csv") csv = value();
    else if (arg == "--case") name = value();
    else if (arg == "--precision") precisions = value();
    else if (arg == "--simd") {
      try {
        use_simd_target(value());
      } catch (const std::exception& e) {
        std::cerr << "sluice-bench-run: " << e.what() << "\n";
        return 2;
      }
    }
    else {
      std::cerr << "usage: sluice-bench-run [--case NAME] [--dx a,b,...] [--threads 1,2] [--precision double,single]"
                   " [--simd TARGET] [--steps N] [--csv FILE]\n";
      return 2;
    }
  }
  std::vector<bool> singles;
  {
    std::stringstream in(precisions);
    std::string item;
    while (std::getline(in, item, ',')) {
      if (item != "double" && item != "single") {
        std::cerr << "sluice-bench-run: --precision takes double, single or both (double,single), not '" << item
                  << "'\n";
        return 2;
      }
      singles.push_back(item == "single");
    }
  }
  std::string table = "case,dx_m,threads,precision,particles,steps,evaluations_per_step,wall_s,"
                      "particle_steps_per_s,evaluations_per_s,peak_bytes_per_particle\n";
  fmt::print("{}: {}\n", name, simd_target());
  fmt::print("{:>8} {:>7} {:>9} {:>10} {:>6} {:>9} {:>14} {:>14} {:>10}\n", "dx [m]", "threads", "precision",
             "particles", "steps", "wall [s]", "M p-steps/s", "M p-evals/s", "B/particle");
  std::vector<SizeRun> all_runs;
  for (double dx : dxs) {
    // Particle-evaluations per second of each run at this dx, for the speed-up line below.
    std::vector<std::tuple<int, bool, double>> runs;
    for (double t : thread_counts)
      for (const bool single : singles) {
      Result r;
      if (!measure_in_child(name, dx, static_cast<int>(t), single, steps, r)) {
        std::cerr << fmt::format("sluice-bench-run: the run of {} at dx = {} with {} threads failed\n", name, dx, t);
        return 1;
      }
      const double psteps = static_cast<double>(r.particles) * static_cast<double>(r.steps) / r.wall;
      const double evals = psteps * r.evaluations_per_step;
      const double bytes = r.peak_bytes / static_cast<double>(r.particles);
      const char* precision = r.single ? "single" : "double";
      fmt::print("{:>8} {:>7} {:>9} {:>10} {:>6} {:>9.2f} {:>14.2f} {:>14.2f} {:>10.0f}\n", dx, r.threads, precision,
                 r.particles, r.steps, r.wall, psteps * 1e-6, evals * 1e-6, bytes);
      std::fflush(stdout);
      table += fmt::format("{},{},{},{},{},{},{},{:.4f},{:.0f},{:.0f},{:.1f}\n", name, dx, r.threads, precision,
                           r.particles, r.steps, r.evaluations_per_step, r.wall, psteps, evals, bytes);
      runs.emplace_back(r.threads, r.single, evals);
      all_runs.push_back({dx, r.particles, r.threads, r.single, evals});
    }
    print_speedups(dx, runs);
  }
  print_scaling(all_runs);
  std::ofstream out(csv);
  out << table;
  if (!out) {
    std::cerr << "sluice-bench-run: cannot write " << csv << "\n";
    return 1;
  }
  fmt::print("wrote {}\n", csv);
  return 0;
}
