// Whole-run benchmark: the default dam break at several resolutions, each measured in a child
// process (so that its peak memory is its own), reporting particle-steps and force evaluations per
// second, wall time, threads and peak memory per particle. Writes a CSV.
//
//   sluice-bench-run [--dx 0.07,0.022,0.01,0.007] [--threads 1,2] [--steps N] [--csv FILE]
#include <fmt/format.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "sluice/case/params.hpp"
#include "sluice/simulation.hpp"

using namespace sluice;

namespace {

struct Result {
  double dx = 0;
  int threads = 0;
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
Result measure(double dx, int threads, long steps) {
  Case c = *load_builtin_case("dam_break");
  apply_override(c, fmt::format("domain.dx={}", dx));
  Simulation sim(c, threads);
  for (int i = 0; i < 3; ++i) sim.step();
  Result r;
  r.dx = dx;
  r.threads = threads;
  r.particles = static_cast<long>(sim.particles<2>().size());
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

bool measure_in_child(double dx, int threads, long steps, Result& out) {
  int fd[2];
  if (pipe(fd) != 0) return false;
  const pid_t pid = fork();
  if (pid == 0) {
    close(fd[0]);
    const Result r = measure(dx, threads, steps);
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

}  // namespace

int main(int argc, char** argv) {
  std::vector<double> dxs = {0.07, 0.022, 0.01, 0.007};
  std::vector<double> thread_counts = {1, 2};
  long steps = 20;
  std::string csv = "bench/results.csv";
  for (int a = 1; a < argc; ++a) {
    const std::string arg = argv[a];
    auto value = [&]() -> std::string {
      if (a + 1 >= argc) {
        std::cerr << "sluice-bench-run: " << arg << " needs a value\n";
        std::exit(2);
      }
      return argv[++a];
    };
    if (arg == "--dx") dxs = parse_list(value());
    else if (arg == "--threads") thread_counts = parse_list(value());
    else if (arg == "--steps") steps = std::stol(value());
    else if (arg == "--csv") csv = value();
    else {
      std::cerr << "usage: sluice-bench-run [--dx a,b,...] [--threads 1,2] [--steps N] [--csv FILE]\n";
      return 2;
    }
  }
  std::string table = "dx_m,threads,particles,steps,evaluations_per_step,wall_s,particle_steps_per_s,"
                      "evaluations_per_s,peak_bytes_per_particle\n";
  fmt::print("{:>8} {:>7} {:>10} {:>6} {:>9} {:>14} {:>14} {:>10}\n", "dx [m]", "threads", "particles", "steps",
             "wall [s]", "M p-steps/s", "M p-evals/s", "B/particle");
  for (double dx : dxs)
    for (double t : thread_counts) {
      Result r;
      if (!measure_in_child(dx, static_cast<int>(t), steps, r)) {
        std::cerr << fmt::format("sluice-bench-run: the run at dx = {} with {} threads failed\n", dx, t);
        return 1;
      }
      const double psteps = static_cast<double>(r.particles) * static_cast<double>(r.steps) / r.wall;
      const double evals = psteps * r.evaluations_per_step;
      const double bytes = r.peak_bytes / static_cast<double>(r.particles);
      fmt::print("{:>8} {:>7} {:>10} {:>6} {:>9.2f} {:>14.2f} {:>14.2f} {:>10.0f}\n", dx, r.threads, r.particles,
                 r.steps, r.wall, psteps * 1e-6, evals * 1e-6, bytes);
      std::fflush(stdout);
      table += fmt::format("{},{},{},{},{},{:.4f},{:.0f},{:.0f},{:.1f}\n", dx, r.threads, r.particles, r.steps,
                           r.evaluations_per_step, r.wall, psteps, evals, bytes);
    }
  std::ofstream out(csv);
  out << table;
  if (!out) {
    std::cerr << "sluice-bench-run: cannot write " << csv << "\n";
    return 1;
  }
  fmt::print("wrote {}\n", csv);
  return 0;
}
