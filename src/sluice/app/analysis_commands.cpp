// sluice analyze, sluice convergence, sluice validate: measurements on runs (sluice/analysis/).
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <omp.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>

#include "sluice/analysis/convergence.hpp"
#include "sluice/analysis/validation.hpp"
#include "sluice/analysis/irregular_waves.hpp"
#include "sluice/analysis/wave_flume.hpp"
#include "sluice/analysis/wave_report.hpp"
#include "sluice/app/commands.hpp"
#include "sluice/case/overrides.hpp"
#include "sluice/io/checkpoint.hpp"

namespace fs = std::filesystem;

namespace sluice::app {

namespace {

std::vector<double> parse_dx_list(const std::string& text) {
  std::vector<double> out;
  std::size_t start = 0;
  while (start <= text.size()) {
    const auto comma = text.find(',', start);
    const std::string item = text.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
    double v = 0.0;
    const auto [ptr, ec] = std::from_chars(item.data(), item.data() + item.size(), v);
    if (item.empty() || ec != std::errc() || ptr != item.data() + item.size() || !(v > 0.0) || !std::isfinite(v))
      throw BadInput(fmt::format("--dx {}: '{}' is not a positive number; expected spacings in metres separated by "
                                 "commas, e.g. --dx 0.2,0.1,0.05",
                                 text, item));
    out.push_back(v);
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  if (out.size() < 3)
    throw BadInput(fmt::format("--dx {}: a convergence study needs at least 3 spacings; got {}", text, out.size()));
  std::sort(out.begin(), out.end(), std::greater<>());
  for (std::size_t i = 1; i < out.size(); ++i)
    if (out[i] == out[i - 1]) throw BadInput(fmt::format("--dx {}: {} is given twice", text, out[i]));
  return out;
}

// A positive finite number, with a message that says so (CLI11's PositiveNumber names its range up
// to 1.8e308).
CLI::Validator positive_number() {
  return CLI::Validator(
      [](std::string& text) {
        double v = 0.0;
        const auto [ptr, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
        if (ec != std::errc() || ptr != text.data() + text.size() || !(v > 0.0) || !std::isfinite(v))
          return fmt::format("'{}' is not a positive number", text);
        return std::string();
      },
      "POSITIVE");
}

int threads_or_all(int threads) { return threads > 0 ? threads : omp_get_num_procs(); }

struct AnalyzeArgs {
  std::string dir, output, window;
  double threshold = 0.0;
  int transits = 3;
  double period = 0.0, height = 0.0, depth = 0.0;
  std::optional<double> maker_x;
};

// --window T0,T1: two times, T0 < T1.
analysis::Window parse_window(const std::string& text) {
  const auto comma = text.find(',');
  double v[2] = {0.0, 0.0};
  bool ok = comma != std::string::npos;
  for (int k = 0; ok && k < 2; ++k) {
    const std::string item = k == 0 ? text.substr(0, comma) : text.substr(comma + 1);
    const auto [ptr, ec] = std::from_chars(item.data(), item.data() + item.size(), v[k]);
    ok = !item.empty() && ec == std::errc() && ptr == item.data() + item.size() && std::isfinite(v[k]);
  }
  if (!ok || !(v[1] > v[0]))
    throw BadInput(fmt::format("--window {}: expected two times in seconds, the first before the second, e.g. "
                               "--window 10,20",
                               text));
  return {v[0], v[1]};
}

// A wave flume: the gauges' waves against the wave maker's target.
int analyze_flume(const AnalyzeArgs& a, const Case& c, const fs::path& out) {
  analysis::FlumeOptions o;
  o.period = a.period;
  o.height = a.height;
  o.depth = a.depth;
  o.maker_x = a.maker_x;
  if (!a.window.empty()) o.window = parse_window(a.window);
  analysis::FlumeAnalysis f;
  try {
    f = analysis::analyze_flume(a.dir, c, o);
  } catch (const analysis::AnalysisError& e) {
    throw BadInput(fmt::format("{}: {}", a.dir, e.what()));
  }
  analysis::write_flume_report(f, a.dir, out);
  std::cout << analysis::flume_table(f);
  std::cout << fmt::format("wrote {}/gauges.csv, summary.csv, harmonics.svg, eta_<gauge>.svg and report.html\n",
                           out.string());
  return 0;
}

// A wave flume with irregular waves: each gauge's significant height and peak period.
int analyze_irregular(const AnalyzeArgs& a, const Case& c, const fs::path& out) {
  analysis::IrregularAnalysis f;
  try {
    f = analysis::analyze_irregular_flume(a.dir, c);
  } catch (const analysis::AnalysisError& e) {
    throw BadInput(fmt::format("{}: {}", a.dir, e.what()));
  }
  analysis::write_irregular_report(f, a.dir, out);
  std::cout << analysis::irregular_table(f);
  std::cout << fmt::format("wrote {}/irregular.csv, spectra.svg and report.html\n", out.string());
  return 0;
}

int analyze(const AnalyzeArgs& a) {
  const fs::path dir = a.dir;
  const fs::path checkpoint = dir / "checkpoint.bin";
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) throw BadInput(fmt::format("{}: no such directory; expected a run's output directory", a.dir));
  if (!fs::exists(checkpoint, ec))
    throw BadInput(fmt::format("{}: no checkpoint.bin, which holds the run's case (tank width, gravity); is this a "
                               "sluice run's output directory?",
                               a.dir));
  const Case c = read_checkpoint(checkpoint).config;
  const fs::path out = a.output.empty() ? dir / "analysis" : fs::path(a.output);
  if (analysis::has_irregular_maker(c) && !(a.period > 0.0)) return analyze_irregular(a, c, out);
  if (analysis::has_wave_maker(c) || a.period > 0.0) return analyze_flume(a, c, out);
  analysis::WaveOptions options;
  options.front_threshold = a.threshold;
  options.transits = a.transits;
  analysis::WaveAnalysis w;
  try {
    w = analysis::analyze_run(dir, c, options);
  } catch (const analysis::AnalysisError& e) {
    throw BadInput(e.what());
  }
  analysis::write_wave_report(w, c, dir, out);
  std::cout << analysis::wave_table(w, c, dir);
  std::cout << fmt::format("wrote {}/waves.csv, summary.csv, crest.svg, crest_height.svg, sloshing.svg and report.html\n",
                           out.string());
  return 0;
}

struct ConvergenceArgs {
  std::string case_arg, dx, output;
  std::vector<std::string> sets;
  double end = 0.0, threshold = 0.0, interval = 0.0;
  int threads = 0;
  bool quiet = false;
};

int convergence(const ConvergenceArgs& a) {
  Case c = case_from_argument(a.case_arg);
  apply_overrides(c, a.sets);
  analysis::ConvergenceOptions o;
  o.dx = parse_dx_list(a.dx);
  o.end_time = a.end;
  o.front_threshold = a.threshold;
  o.frame_interval = a.interval;
  o.threads = threads_or_all(a.threads);
  o.output_dir = a.output.empty() ? fs::path("out") / (c.name + "_convergence") : fs::path(a.output);
  o.progress = a.quiet ? RunOptions::Progress::none : RunOptions::Progress::lines;
  o.command_line = fmt::format("sluice convergence {} --dx {}", a.case_arg, a.dx);
  for (const auto& s : a.sets) o.command_line += " --set " + s;
  if (a.end > 0.0) o.command_line += fmt::format(" --end {}", a.end);
  if (a.interval > 0.0) o.command_line += fmt::format(" --interval {}", a.interval);
  if (a.threshold > 0.0) o.command_line += fmt::format(" --threshold {}", a.threshold);
  const analysis::ConvergenceStudy study = analysis::run_convergence(c, o, std::cerr);
  std::cout << analysis::convergence_table(study);
  std::cout << fmt::format("wrote {}/convergence.csv, convergence.svg, fronts.svg and report.html\n",
                           o.output_dir.string());
  return 0;
}

struct ValidateArgs {
  bool quick = false, quiet = false, three_d = false, no_dynamic = false, waves = false, bodies = false;
  std::string output;
  std::vector<std::string> cases, sets, compare;
  int threads = 0;
};

int validate(const ValidateArgs& a) {
  analysis::ValidationOptions o;
  o.quick = a.quick;
  o.cases = a.cases;
  o.three_d = a.three_d;
  o.waves = a.waves;
  o.bodies = a.bodies;
  if (a.waves && a.bodies) throw BadInput("--waves and --bodies: expected one of them (run validate once for each)");
  o.sets = a.sets;
  for (const auto& text : a.compare) {
    try {
      o.variants.push_back(analysis::parse_variant(text));
      analysis::check_variant_labels(o.variants);
    } catch (const analysis::AnalysisError& e) {
      throw BadInput(e.what());
    }
  }
  // Dynamic walls beside the cases' own settings, first among the variants (unless a
  // --compare variant has that label: then it is the user's).
  const auto dynamic = analysis::dynamic_walls_variant();
  if (!a.no_dynamic &&
      std::none_of(o.variants.begin(), o.variants.end(), [&](const auto& v) { return v.label == dynamic.label; }))
    o.variants.insert(o.variants.begin(), dynamic);
  for (const auto& name : o.cases)
    if (std::find(analysis::validation_case_names().begin(), analysis::validation_case_names().end(), name) ==
        analysis::validation_case_names().end())
      throw BadInput(fmt::format("--case {}: no validation case of that name; expected one of: {}", name,
                                 fmt::join(analysis::validation_case_names(), ", ")));
  o.threads = threads_or_all(a.threads);
  o.output_dir = a.output.empty() ? fs::path("out") / fmt::format("validation{}{}", a.waves ? "_waves" : a.bodies ? "_bodies" : "",
                                                                  a.quick ? "_quick" : "")
                                  : fs::path(a.output);
  o.progress = a.quiet ? RunOptions::Progress::none : RunOptions::Progress::lines;
  o.command_line = std::string("sluice validate") + (a.quick ? " --quick" : "") + (a.three_d ? " --3d" : "") +
                   (a.waves ? " --waves" : "") + (a.bodies ? " --bodies" : "") +
                   (a.no_dynamic ? " --no-dynamic" : "");
  for (const auto& name : a.cases) o.command_line += " --case " + name;
  for (const auto& set : a.sets) o.command_line += " --set " + set;
  for (const auto& text : a.compare) o.command_line += " --compare '" + text + "'";
  const analysis::ValidationReport report = analysis::run_validation(o, std::cerr);
  std::cout << analysis::validation_table(report);
  std::cout << fmt::format("wrote {}, validation.csv and checks.csv\n", (o.output_dir / "report.html").string());
  if (!report.passed()) {
    std::cerr << "sluice: validation failed: a requirement above is not met\n";
    return exit_failure;
  }
  return 0;
}

}  // namespace

Command add_analyze_command(CLI::App& app) {
  auto args = std::make_shared<AnalyzeArgs>();
  auto* cmd = app.add_subcommand(
      "analyze",
      "A run's waves: for a wave flume (a wave maker, or --period), each gauge's wave height, period and harmonics, "
      "the decay along the flume and the reflection, against linear theory; otherwise the crest, front, crest speeds "
      "and sloshing period, against shallow-water theory.");
  cmd->add_option("output_dir", args->dir, "A run's output directory (frames/*.npz and checkpoint.bin)")->required();
  cmd->add_option("-o,--output", args->output, "Where to write the CSVs, plots and report (default: OUTPUT_DIR/analysis)");
  cmd->add_option("--threshold", args->threshold,
                  "Height (m) above the initial surface that marks the wave front (default: 10% of the initial step "
                  "between the walls' depths)")
      ->check(positive_number());
  cmd->add_option("--period", args->period,
                  "Wave flume: the waves' period (s), for a paddle without law = \"wave\" (a recorded motion); a run "
                  "with a wave maker or this option is analysed at its gauges")
      ->check(positive_number());
  cmd->add_option("--height", args->height, "Wave flume: the target wave height (m) to compare with")
      ->check(positive_number());
  cmd->add_option("--depth", args->depth, "Wave flume: the still water's depth (m) for the dispersion relation")
      ->check(positive_number());
  cmd->add_option("--maker-x", args->maker_x, "Wave flume: x of the wave maker's face (m), where distances start");
  cmd->add_option("--window", args->window,
                  "Wave flume: T0,T1 (s), one window for every gauge (default: each gauge's steady window, from the "
                  "group velocity, the ramp and the far end)");
  cmd->add_option("--transits", args->transits, "Average the crest speed over this many first transits (default: 3)")
      ->check(CLI::Range(1, 1000));
  return {cmd, [args] { return analyze(*args); }};
}

Command add_convergence_command(CLI::App& app) {
  auto args = std::make_shared<ConvergenceArgs>();
  auto* cmd = app.add_subcommand(
      "convergence", "Run a case at several particle spacings and measure the observed order of convergence.");
  cmd->add_option("case", args->case_arg, "Case file (.toml) or built-in case name")->required();
  cmd->add_option("--dx", args->dx, "Particle spacings in metres, at least 3, e.g. 0.2,0.1,0.05 (h/dx stays fixed)")
      ->required();
  cmd->add_option("--end", args->end,
                  "Simulated time of each run (default: the time a shallow-water wave takes to cross the tank, "
                  "plus 20%, at most the case's end)")
      ->check(positive_number());
  cmd->add_option("--interval", args->interval,
                  "Frame interval in seconds for the front position (default: 1/50 of the shallow-water crossing "
                  "time)")
      ->check(positive_number());
  cmd->add_option("--threshold", args->threshold,
                  "Height (m) above the initial surface that marks the wave front (default: 10% of the initial step)")
      ->check(positive_number());
  cmd->add_option("--set", args->sets, "Override a case key for every run (repeatable)")->allow_extra_args(false);
  cmd->add_option("-o,--output", args->output, "Output directory (default: out/<case>_convergence)");
  cmd->add_option("--threads", args->threads, "Threads per run (default: all cores)")->check(CLI::Range(1, 1024));
  cmd->add_flag("-q,--quiet", args->quiet, "No progress lines");
  return {cmd, [args] { return convergence(*args); }};
}

Command add_validate_command(CLI::App& app) {
  auto args = std::make_shared<ValidateArgs>();
  auto* cmd = app.add_subcommand(
      "validate", "Run the validation cases and compare them with experiments; writes an HTML report.");
  cmd->add_flag("--quick", args->quick, "Coarse resolution, as run by the test suite (about a minute)");
  cmd->add_option("-o,--output", args->output, "Output directory (default: out/validation or out/validation_quick)");
  cmd->add_flag("--3d", args->three_d,
                "Also run the 3D case, spheric2 (SPHERIC test 2 at dx = 0.02 m: about 18 minutes on two cores; with "
                "--quick dx = 0.05 m, a few minutes)");
  cmd->add_flag("--waves", args->waves,
                "Run the wave cases instead: wave_flume against linear theory and the NTNU flume's runs 1021, 1062 and "
                "1102 against the laboratory's probes (about 80 minutes on two cores; with --quick a few minutes)");
  cmd->add_flag("--bodies", args->bodies,
                "Run the floating-body cases instead: the floating box's draft against Archimedes in 2D and 3D, the "
                "NTNU section's heave and roll decay periods, its wave forces held in run 2062 and its motions free "
                "in runs 3061_1 and 3102_1 against the laboratory's, the NTNU cases at dx = 0.01 m and the 3D box at "
                "1/60 m (over an hour a decay or the 3D box, several hours a wave run); with --quick the 2D box and "
                "the decays at dx = 0.02 m, about a quarter of an hour");
  cmd->add_option("--case", args->cases,
                  fmt::format("Run only this validation case (repeatable): {}",
                              fmt::join(analysis::validation_case_names(), ", ")));
  cmd->add_option("--set", args->sets,
                  "Override a case key in every validation case, e.g. --set physics.wall_boundary=adami (repeatable; "
                  "applied after --quick's resolution)")
      ->allow_extra_args(false);
  cmd->add_option("--compare", args->compare,
                  "Also run every case with other settings and report them side by side (repeatable): 'LABEL: "
                  "KEY=VALUE; KEY=VALUE ...', e.g. --compare 'mdbc: physics.wall_boundary=mdbc'; the checks stay the "
                  "main run's")
      ->allow_extra_args(false);
  cmd->add_flag("--no-dynamic", args->no_dynamic,
                "Leave out the column of dynamic walls (h = 1.3 dx, no shifting, no wall function: the default case's) that "
                "the 2D cases are otherwise run again with, beside their own settings");
  cmd->add_option("--threads", args->threads, "Threads per run (default: all cores)")->check(CLI::Range(1, 1024));
  cmd->add_flag("-q,--quiet", args->quiet, "No progress lines");
  return {cmd, [args] { return validate(*args); }};
}

}  // namespace sluice::app
