// The analysis functions on synthetic data with known answers: interpolation and differences, line
// fits, periods of a sine, transits of a crest moving at a known speed, a wave front moving at a known
// speed through real frames, observed orders, the reference tables, plots and the validation
// evaluations fed with the experiments' own curves.
#include <gtest/gtest.h>

#include <fmt/format.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <functional>
#include <limits>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "sluice/analysis/convergence.hpp"
#include "sluice/analysis/html_report.hpp"
#include "sluice/analysis/reference_data.hpp"
#include "sluice/analysis/series.hpp"
#include "sluice/analysis/svg_plot.hpp"
#include "sluice/analysis/table.hpp"
#include "sluice/analysis/validation.hpp"
#include "sluice/analysis/waves.hpp"
#include "sluice/case/params.hpp"
#include "sluice/io/atomic_file.hpp"

using namespace sluice;
using namespace sluice::analysis;
namespace fs = std::filesystem;

namespace {

Series sampled(double t0, double t1, double step, const std::function<double(double)>& f) {
  Series s;
  for (int k = 0; t0 + k * step <= t1 + 1e-12; ++k) {
    s.t.push_back(t0 + k * step);
    s.y.push_back(f(s.t.back()));
  }
  return s;
}

// A temporary directory, removed at the end of the test.
struct TempDir {
  fs::path path;
  TempDir() {
    path = fs::temp_directory_path() /
           fmt::format("sluice_analysis_{}_{}", ::getpid(), ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
};

}  // namespace

TEST(Series, InterpolatesLinearlyAndOnlyInsideItsRange) {
  const Series s{{0.0, 1.0, 3.0}, {0.0, 2.0, 6.0}};
  EXPECT_DOUBLE_EQ(*interpolate(s, 0.5), 1.0);
  EXPECT_DOUBLE_EQ(*interpolate(s, 2.0), 4.0);
  EXPECT_DOUBLE_EQ(*interpolate(s, 3.0), 6.0);
  EXPECT_FALSE(interpolate(s, -0.1));
  EXPECT_FALSE(interpolate(s, 3.1));
}

TEST(Series, SortedKeepsPairsAndRejectsBadInput) {
  const Series s = sorted({{2.0, 0.5, 1.0}, {20.0, 5.0, 10.0}});
  EXPECT_EQ(s.t, (std::vector<double>{0.5, 1.0, 2.0}));
  EXPECT_EQ(s.y, (std::vector<double>{5.0, 10.0, 20.0}));
  EXPECT_THROW(sorted({{0.0, 1.0}, {1.0}}), AnalysisError);
  EXPECT_THROW(sorted({{0.0, NAN}, {1.0, 2.0}}), AnalysisError);
}

TEST(Series, CompareGivesRmsMaxAndBiasOverTheWindow) {
  // Simulation = reference + 0.1 everywhere, except one point 0.4 off, outside the window.
  const Series reference{{0.0, 1.0, 2.0, 3.0, 4.0}, {1.0, 2.0, 3.0, 4.0, 5.0}};
  const Series simulation = sampled(0.0, 4.0, 0.25, [](double t) { return t + 1.1 + (t == 4.0 ? 0.3 : 0.0); });
  const Difference d = compare(simulation, reference, 0.0, 3.0);
  EXPECT_EQ(d.points, 4u);
  EXPECT_NEAR(d.rms, 0.1, 1e-12);
  EXPECT_NEAR(d.max_abs, 0.1, 1e-12);
  EXPECT_NEAR(d.mean, 0.1, 1e-12);
  const Difference all = compare(simulation, reference, 0.0, 10.0);
  EXPECT_EQ(all.points, 5u);
  EXPECT_NEAR(all.max_abs, 0.4, 1e-12);
  EXPECT_NEAR(all.rms, std::sqrt((4 * 0.01 + 0.16) / 5), 1e-12);
  // Reference points outside the simulated times are not used; none at all is an error.
  EXPECT_EQ(compare(Series{{0.0, 2.0}, {1.0, 3.0}}, reference, 0.0, 10.0).points, 3u);
  EXPECT_THROW(compare(Series{{10.0, 11.0}, {0.0, 0.0}}, reference, 0.0, 10.0), AnalysisError);
}

TEST(Series, FitsAStraightLine) {
  const Series s = sampled(0.0, 5.0, 0.1, [](double t) { return 2.0 + 3.0 * t; });
  const LineFit f = fit_line(s, 1.0, 4.0);
  EXPECT_NEAR(f.slope, 3.0, 1e-12);
  EXPECT_NEAR(f.intercept, 2.0, 1e-12);
  EXPECT_EQ(f.points, 31u);
  EXPECT_THROW(fit_line(s, 1.0, 1.05), AnalysisError);
}

TEST(Series, FindsTheFirstRiseToALevel) {
  const Series s{{0.0, 1.0, 2.0, 3.0}, {0.0, 0.2, 1.2, 0.0}};
  EXPECT_NEAR(*first_rise_to(s, 0.7), 1.5, 1e-12);
  EXPECT_NEAR(*first_rise_to(s, 0.2), 1.0, 1e-12);
  EXPECT_FALSE(first_rise_to(s, 2.0));
  EXPECT_FALSE(first_rise_to(s, 0.7, 2.5));
}

TEST(Series, BestLagRecoversAKnownDelay) {
  // A level falling as a water column's does, sampled every ms, and the same fall 27 ms later sampled
  // every 10 ms (as a gauge's probe file is).
  const auto level = [](double t) { return t <= 0.0 ? 0.55 : 0.55 - 0.5 * t * t - 0.05 * t; };
  const Series reference = sampled(0.0, 0.6, 0.001, level);
  const Series later = sampled(0.0, 0.6, 0.01, [&](double t) { return level(t - 0.027); });
  const Lag lag = best_lag(later, reference, 0.05, 0.4, 0.15, 0.001);
  EXPECT_NEAR(lag.shift, 0.027, 1e-9);
  EXPECT_LT(lag.rms, 1e-4);
  // Earlier is a negative shift; the same series has none.
  EXPECT_NEAR(best_lag(reference, later, 0.05, 0.4, 0.15, 0.001).shift, -0.027, 1e-9);
  EXPECT_NEAR(best_lag(reference, reference, 0.05, 0.4, 0.15, 0.001).shift, 0.0, 1e-12);
  EXPECT_THROW(best_lag(later, reference, 0.05, 0.4, 0.15, 0.0), AnalysisError);
  EXPECT_THROW(best_lag(later, reference, 5.0, 6.0, 0.15, 0.001), AnalysisError);
}

TEST(Series, PeriodOfASineFromZeroCrossingsAndAutocorrelation) {
  const double period = 1.7;
  const Series s = sampled(0.0, 20.0, 0.01, [&](double t) { return 5.0 + 0.3 * std::sin(2 * std::numbers::pi * t / period + 0.4); });
  const PeriodEstimate z = period_from_zero_crossings(s);
  EXPECT_NEAR(z.period, period, 1e-4);
  EXPECT_GE(z.crossings, 22u);
  EXPECT_NEAR(period_from_autocorrelation(s), period, 0.01);
  // A decaying oscillation sampled coarsely (as frames are): still the period within a few percent.
  const Series d = sampled(0.0, 30.0, 0.1, [](double t) { return 10.0 + std::exp(-t / 20.0) * std::cos(2 * std::numbers::pi * t / 8.0); });
  EXPECT_NEAR(period_from_zero_crossings(d).period, 8.0, 0.1);
  EXPECT_NEAR(period_from_autocorrelation(d), 8.0, 0.25);
  // Too short a record for a period.
  EXPECT_THROW(period_from_zero_crossings(sampled(0.0, 1.0, 0.01, [&](double t) { return std::sin(2 * std::numbers::pi * t / period); })),
               AnalysisError);
}

TEST(Series, ObservedOrder) {
  // e = C dx^2 gives p = 2; e = C dx gives 1.
  EXPECT_NEAR(observed_order(3.0 * 0.04, 0.2, 3.0 * 0.01, 0.1), 2.0, 1e-12);
  EXPECT_NEAR(observed_order(0.5 * 0.4, 0.4, 0.5 * 0.1, 0.1), 1.0, 1e-12);
  EXPECT_THROW(observed_order(0.0, 0.2, 0.1, 0.1), AnalysisError);
  EXPECT_THROW(observed_order(0.1, 0.1, 0.1, 0.2), AnalysisError);
}

// A probe file's or data file's text reaches the messages escaped.
TEST(Table, TextFromTheFileIsShownEscaped) {
  std::string message;
  try {
    parse_csv_table("t,\x1b[2Jz\n0.5,\x1b[31m1\n", "bad.csv");
  } catch (const AnalysisError& e) {
    message = e.what();
  }
  EXPECT_NE(message.find(R"(bad.csv:2: column '\u001B[2Jz': '\u001B[31m1' is not a finite number)"), std::string::npos)
      << message;
  try {
    (void)parse_csv_table("t,\x1b[2Jz\n0.5\n", "short.csv");
  } catch (const AnalysisError& e) {
    message = e.what();
  }
  EXPECT_NE(message.find(R"(expected 2 (t,\u001B[2Jz))"), std::string::npos) << message;
  try {
    (void)parse_csv_table("t,\x1b[2Jz\n0.5,1\n", "ok.csv").column("height");
  } catch (const AnalysisError& e) {
    message = e.what();
  }
  EXPECT_NE(message.find(R"(no column 'height'; the columns are t, \u001B[2Jz)"), std::string::npos) << message;
}

TEST(Table, ParsesCommentsHeaderAndRowsAndNamesBadLines) {
  const Table t = parse_csv_table("# source: here\n# scaling: T = t\nT,Z\n0.5, 1.0\n\n1.5,2.5\n", "test.csv");
  EXPECT_EQ(t.comments, (std::vector<std::string>{"source: here", "scaling: T = t"}));
  EXPECT_EQ(t.columns, (std::vector<std::string>{"T", "Z"}));
  ASSERT_EQ(t.rows.size(), 2u);
  EXPECT_EQ(t.values("Z"), (std::vector<double>{1.0, 2.5}));
  EXPECT_EQ(t.series("T", "Z").t, (std::vector<double>{0.5, 1.5}));
  try {
    parse_csv_table("T,Z\n0.5,1.0\n0.7,abc\n", "bad.csv");
    FAIL() << "expected an error";
  } catch (const AnalysisError& e) {
    EXPECT_NE(std::string(e.what()).find("bad.csv:3"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("'abc'"), std::string::npos) << e.what();
  }
  EXPECT_THROW(parse_csv_table("T,Z\n0.5\n", "short.csv"), AnalysisError);
  EXPECT_THROW(parse_csv_table("# only comments\n", "empty.csv"), AnalysisError);
  EXPECT_THROW(t.values("X"), AnalysisError);
  // Written back with its provenance.
  EXPECT_EQ(parse_csv_table(csv_text(t), "again").comments, t.comments);
}

TEST(ReferenceData, EveryFileIsEmbeddedWithItsProvenance) {
  ASSERT_GE(reference_files().size(), 6u);
  for (const auto& f : reference_files()) {
    const Table t = reference_table(f.name);
    EXPECT_FALSE(t.comments.empty()) << f.name;
    EXPECT_FALSE(t.rows.empty()) << f.name;
  }
  EXPECT_EQ(reference_table("mm1952_n2sq2_a2.25in_front_table2.csv").rows.size(), 15u);
  EXPECT_THROW(reference_table("no_such.csv"), AnalysisError);
}

TEST(Waves, StokerAndRitterSpeedsAndTheFirstModePeriod) {
  EXPECT_NEAR(stoker_bore_speed_ratio(0.4), 0.938224, 1e-9);  // a row of the table
  EXPECT_NEAR(stoker_bore_speed_ratio(0.0), 2.0, 1e-12);      // Ritter
  EXPECT_NEAR(stoker_bore_speed_ratio(0.45), 0.5 * (0.938224 + 0.944391), 1e-9);
  EXPECT_THROW(stoker_bore_speed_ratio(0.95), AnalysisError);
  EXPECT_THROW(stoker_bore_speed_ratio(-0.1), AnalysisError);
  // Deep water: 2 pi / sqrt(g k); shallow: 2L / sqrt(g h).
  EXPECT_NEAR(first_mode_period(2.0, 100.0, 9.81), 2 * std::numbers::pi / std::sqrt(9.81 * std::numbers::pi / 2.0), 1e-9);
  EXPECT_NEAR(first_mode_period(100.0, 0.1, 9.81), 200.0 / std::sqrt(9.81 * 0.1), 0.01);
}

TEST(Waves, TransitsOfACrestBouncingAtAKnownSpeed) {
  // A crest going back and forth across a 20 m tank at 5 m/s (a triangle wave), sampled every 0.1 s.
  const double width = 20.0, speed = 5.0;
  const Series x = sampled(0.0, 16.0, 0.1, [&](double t) {
    const double s = std::fmod(speed * t, 2 * width);
    return s < width ? s : 2 * width - s;
  });
  const auto transits = find_transits(x, width);
  ASSERT_EQ(transits.size(), 4u);
  for (std::size_t k = 0; k < transits.size(); ++k) {
    EXPECT_NEAR(transits[k].speed, speed, 1e-9);
    EXPECT_EQ(transits[k].direction, k % 2 == 0 ? 1 : -1);
  }
  EXPECT_NEAR(transits[0].t_start, 1.0, 1e-9);
  EXPECT_NEAR(transits[0].t_end, 3.0, 1e-9);
  // A crest that jumps between two humps is not a transit.
  const Series jumping = sampled(0.0, 4.0, 0.1, [&](double t) { return std::fmod(t, 0.2) < 0.1 ? 6.0 : 14.0; });
  EXPECT_TRUE(find_transits(jumping, width).empty());
}

namespace {

// A frame of fluid particles on a dx lattice under a surface y = surface(x), over [0, width].
Frame lattice_frame(double t, double dx, double width, const std::function<double(double)>& surface) {
  Frame f;
  f.time = t;
  f.dx = dx;
  std::uint32_t id = 0;
  for (double x = 0.5 * dx; x < width; x += dx)
    for (double y = 0.5 * dx; y < surface(x); y += dx) {
      f.position().push_back(x);
      f.position().push_back(y);
      f.velocity().insert(f.velocity().end(), {0.0, 0.0});
      f.density().push_back(1000.0);
      f.pressure().push_back(0.0);
      f.kind().push_back(0);
      f.id().push_back(id++);
      f.body().push_back(0);
    }
  return f;
}

}  // namespace

TEST(Waves, ABoreMovingAtAKnownSpeed) {
  // A wet-bed dam break idealised: depth 2 ahead of a bore, 3.3 behind it, the bore at x = 3 + 6.5 t in a
  // 20 m tank, and the reservoir 5 deep over x < 1. Frames every 0.1 s; dx = 0.05.
  const double width = 20.0, dx = 0.05, speed = 6.5;
  std::vector<Frame> frames;
  for (int k = 0; k <= 30; ++k) {
    const double t = 0.1 * k;
    const double bore = k == 0 ? 3.0 : 3.0 + speed * t;
    frames.push_back(lattice_frame(t, dx, width, [&](double x) {
      if (k == 0) return x < 3.0 ? 5.0 : 2.0;
      return x < 1.0 ? 5.0 : (x < bore ? 3.3 : 2.0);
    }));
  }
  const WaveAnalysis a = analyze_waves(frames, width, 9.81, {});
  EXPECT_NEAR(a.upstream_depth, 5.0, 1e-9);
  EXPECT_NEAR(a.downstream_depth, 2.0, 1e-9);
  EXPECT_TRUE(a.dam_break);
  EXPECT_NEAR(a.front_threshold, 0.3, 1e-9);
  ASSERT_TRUE(a.front_fit);
  EXPECT_NEAR(a.front_fit->slope, speed, 0.02);
  // The bore reaches x = 20 - 2 dx (the band of the far-wall height) at t = (20 - 0.1 - 3) / 6.5.
  ASSERT_TRUE(a.far_wall_arrival);
  EXPECT_NEAR(*a.far_wall_arrival, (width - 2 * dx - 3.0) / speed, 0.1);
  ASSERT_TRUE(a.stoker_speed);
  EXPECT_NEAR(*a.stoker_speed, 0.938224 * std::sqrt(9.81 * 5.0), 1e-6);
  EXPECT_NEAR(a.mean_depth, (5.0 * 3.0 + 2.0 * 17.0) / 20.0, 1e-9);
}

TEST(Waves, ASinusoidalCrestWithAKnownPeriod) {
  // A first-mode standing wave, surface 1 + 0.2 cos(pi x / L) cos(2 pi t / T), T = 3 s, in a 2 m tank:
  // the crest sits at one wall, then the other, and the centre of mass oscillates with period T.
  const double width = 2.0, dx = 0.01, period = 3.0;
  std::vector<Frame> frames;
  for (int k = 0; k <= 200; ++k) {
    const double t = 0.05 * k;
    frames.push_back(lattice_frame(t, dx, width, [&](double x) {
      return 1.0 + 0.2 * std::cos(std::numbers::pi * x / width) * std::cos(2 * std::numbers::pi * t / period);
    }));
  }
  const WaveAnalysis a = analyze_waves(frames, width, 9.81, {});
  ASSERT_TRUE(a.period_zero_crossings);
  EXPECT_NEAR(a.period_zero_crossings->period, period, 0.03);
  ASSERT_TRUE(a.period_autocorrelation);
  EXPECT_NEAR(*a.period_autocorrelation, period, 0.05);
  // The crest: at the left wall at t = 0 and at the right wall half a period later.
  // On the dx lattice the top row under the crest is flat over the last ~0.14 m next to the wall; the
  // crest is the first particle of that row.
  EXPECT_LT(a.crest_x[0], 0.05);
  EXPECT_GT(a.crest_x[30], 1.85);  // t = 1.5 s
  EXPECT_NEAR(a.crest_height[0], 1.2, dx);
  EXPECT_NEAR(a.mean_depth, 1.0, dx);
  // A smooth surface is no dam break: no Stoker speed, the front threshold from the mean depth.
  EXPECT_FALSE(a.dam_break);
  EXPECT_FALSE(a.stoker_speed);
  EXPECT_NEAR(a.front_threshold, 0.1 * a.mean_depth, 1e-12);
}

// analyze reads the run's frames: one whose spacing is not positive, or whose time or a position is
// not finite, is refused naming its file, rather than measured (a NaN time was reported as "frames out
// of order", a zero spacing and a NaN position went into the results).
TEST(Waves, AFrameWithAZeroSpacingOrNonFiniteValuesIsRefused) {
  Case c;
  c.dimension = 2;
  c.tank_width = 2.0;
  c.gravity = {0.0, -9.81, 0.0};
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const std::vector<std::pair<std::string, std::function<void(Frame&)>>> damage = {
      {"dx = 0 is not a positive spacing", [](Frame& f) { f.dx = 0.0; }},
      {"dx = -0.05 is not a positive spacing", [](Frame& f) { f.dx = -0.05; }},
      {"its time t = nan is not finite", [&](Frame& f) { f.time = nan; }},
      {"the position of particle id 4 (row 4 of x) is not finite: [nan, ", [&](Frame& f) { f.position()[8] = nan; }},
  };
  for (const auto& [what, change] : damage) {
    SCOPED_TRACE(what);
    TempDir dir;
    fs::create_directories(dir.path / "frames");
    for (int k = 0; k < 4; ++k) {
      Frame f = lattice_frame(0.1 * k, 0.05, 2.0, [](double x) { return 0.5 + 0.1 * x; });
      if (k == 2) change(f);
      write_file_atomic(dir.path / "frames" / fmt::format("frame_{:06}.npz", k), frame_to_npz(f));
    }
    try {
      analyze_run(dir.path, c, {});
      ADD_FAILURE() << "no error";
    } catch (const AnalysisError& e) {
      EXPECT_NE(std::string(e.what()).find((dir.path / "frames" / "frame_000002.npz").string() +
                                           ": not a sluice frame: " + what),
                std::string::npos)
          << e.what();
    }
  }
}

TEST(Plots, SvgHasAxesSeriesLegendAndEscapedText) {
  Plot p;
  p.title = "a < b & c";
  p.x_label = "t (s)";
  p.y_label = "x (m)";
  p.series = {curve("line", {0.0, 1.0, 2.0}, {0.0, 1.0, 4.0}),
              curve("points", {0.5, 1.5}, {0.2, 2.2}, PlotSeries::Style::markers)};
  p.bands = {{0.0, 1.0, "window"}};
  const std::string svg = svg_plot(p);
  EXPECT_EQ(svg.rfind("<svg", 0), 0u);
  EXPECT_NE(svg.find("</svg>"), std::string::npos);
  EXPECT_NE(svg.find("a &lt; b &amp; c"), std::string::npos);
  EXPECT_EQ(svg.find("a < b"), std::string::npos);
  EXPECT_NE(svg.find("<path d=\"M"), std::string::npos);
  std::size_t circles = 0;
  for (auto pos = svg.find("<circle"); pos != std::string::npos; pos = svg.find("<circle", pos + 1)) ++circles;
  EXPECT_EQ(circles, 3u);  // two markers and the legend's
  EXPECT_NE(svg.find(">window<"), std::string::npos);
  auto expect_ticks = [](const std::vector<double>& got, const std::vector<double>& want) {
    ASSERT_EQ(got.size(), want.size());
    for (std::size_t i = 0; i < got.size(); ++i) EXPECT_NEAR(got[i], want[i], 1e-12);
  };
  expect_ticks(nice_ticks(0.0, 1.0), {0.0, 0.2, 0.4, 0.6, 0.8, 1.0});
  expect_ticks(nice_ticks(-3.0, 7.0, 5), {-2.0, 0.0, 2.0, 4.0, 6.0});
  // A logarithmic axis cannot show zero; an empty plot is an error.
  p.log_y = true;
  EXPECT_THROW(svg_plot(p), AnalysisError);
  EXPECT_THROW(svg_plot(Plot{}), AnalysisError);
}

TEST(Plots, HtmlReportEmbedsFiguresAndEscapesText) {
  HtmlReport r("Report <1>");
  r.paragraph("x < y");
  r.table({"a", "b"}, {{"PASS", "1"}, {"FAIL", "2"}});
  r.figure("<svg></svg>", "caption & more");
  const std::string html = r.html();
  EXPECT_NE(html.find("<title>Report &lt;1&gt;</title>"), std::string::npos);
  EXPECT_NE(html.find("<p>x &lt; y</p>"), std::string::npos);
  EXPECT_NE(html.find("<td class=\"pass\">PASS</td>"), std::string::npos);
  EXPECT_NE(html.find("<td class=\"fail\">FAIL</td>"), std::string::npos);
  EXPECT_NE(html.find("<figure>\n<svg></svg>"), std::string::npos);
  EXPECT_NE(html.find("caption &amp; more"), std::string::npos);
}

TEST(Convergence, ErrorsAndOrdersFromKnownFronts) {
  // Fronts x = 2t + 0.5 dx (first order) and arrivals 3 + 4 dx^2 (second order) against the finest.
  ConvergenceStudy study;
  for (double dx : {0.4, 0.2, 0.1, 0.05}) {
    ConvergenceLevel l;
    l.dx = dx;
    l.front = sampled(0.0, 5.0, 0.1, [&](double t) { return 2.0 * t + 0.5 * dx; });
    l.arrival = 3.0 + 4.0 * dx * dx;
    study.levels.push_back(l);
  }
  compute_convergence_errors(study);
  const auto& L = study.levels;
  EXPECT_NEAR(L[0].front_error, 0.5 * (0.4 - 0.05), 1e-9);
  EXPECT_NEAR(L[0].arrival_error, 4.0 * (0.16 - 0.0025), 1e-9);
  EXPECT_NEAR(L[0].front_order, std::log((0.4 - 0.05) / (0.2 - 0.05)) / std::log(2.0), 1e-9);
  EXPECT_NEAR(L[1].arrival_order, std::log((0.04 - 0.0025) / (0.01 - 0.0025)) / std::log(2.0), 1e-9);
  EXPECT_TRUE(std::isnan(L[2].front_order));  // no finer level with an error
  EXPECT_TRUE(std::isnan(L[3].front_error));  // the reference itself
  // The finest run must reach the far wall.
  study.levels.back().arrival.reset();
  EXPECT_THROW(compute_convergence_errors(study), AnalysisError);
}

namespace {

void write_probe(const fs::path& dir, const std::string& name, const std::string& header, const Series& s) {
  std::string text = header + "\n";
  for (std::size_t i = 0; i < s.size(); ++i) text += fmt::format("{},{}\n", s.t[i], s.y[i]);
  fs::create_directories(dir / "probes");
  write_file_atomic(dir / "probes" / (name + ".csv"), text);
}


// A "run" of the Martin & Moyce case in dir whose probes hold Martin & Moyce's own curves converted to
// metres and seconds: the front `dz` further in Z and `dT` earlier in T (from Z = 1 at T = 0), the
// residual height as measured.
void write_martin_moyce_probes(const fs::path& dir, const Case& c, double dz, double dT) {
  const double a = c.water[0].max[0], g = -c.gravity[1];
  const Series front = reference_table("mm1952_n2sq2_a2.25in_front_table2.csv").series("T", "Z");
  const Series height = reference_table("mm1952_n2sq2_a2.25in_height_table6.csv").series("tau", "H");
  Series x, h;
  if (dT > 0.0) {
    x.t.push_back(0.0);
    x.y.push_back(a - 0.5 * c.dx);
  }
  for (std::size_t i = 0; i < front.size(); ++i) {
    x.t.push_back((front.t[i] - dT) / std::sqrt(2 * g / a));
    x.y.push_back((front.y[i] + dz) * a - 0.5 * c.dx);
  }
  for (std::size_t i = 0; i < height.size(); ++i) {
    h.t.push_back(height.t[i] / std::sqrt(g / a));
    h.y.push_back(height.y[i] * 2 * a);
  }
  write_probe(dir, "front", "time,distance", x);
  write_probe(dir, "column_height", "time,height", h);
}

}  // namespace

TEST(Validation, MartinMoyceScalingRecoversTheDataThatWentIn) {
  // A "run" whose probes hold Martin & Moyce's own curves converted to metres and seconds: the
  // evaluation must convert back (T = t sqrt(2g/a), Z = (x + dx/2)/a; tau = t sqrt(g/a), H = h/2a)
  // and find no difference; shifted by 0.1 in Z it must find 0.1.
  const Case c = *load_builtin_case("martin_moyce");
  for (double shift : {0.0, 0.1}) {
    TempDir dir;
    write_martin_moyce_probes(dir.path, c, shift, 0.0);
    const ValidationResult r = evaluate_martin_moyce(c, dir.path, full_bounds());
    // The window T <= 3, the same moved in time, all points (T <= 3.33), the residual height.
    ASSERT_EQ(r.comparisons.size(), 4u);
    EXPECT_EQ(r.comparisons[0].id, "front_window");
    EXPECT_NEAR(r.comparisons[0].difference.rms, shift, 1e-9);
    EXPECT_EQ(r.comparisons[0].difference.points, 13u);  // T <= 3
    // Moved in time it is never further off (a constant lead in Z, where the front's speed is
    // steady, is the same as a lead in time: the move takes most of it away).
    EXPECT_EQ(r.comparisons[1].id, "front_window_moved");
    EXPECT_LE(r.comparisons[1].difference.rms, r.comparisons[0].difference.rms);
    if (shift == 0.0) {
      EXPECT_NEAR(r.comparisons[1].difference.rms, 0.0, 1e-9);
    }
    EXPECT_EQ(r.comparisons[3].id, "height");
    EXPECT_NEAR(r.comparisons[3].difference.rms, 0.0, 1e-9);
    EXPECT_EQ(r.passed(), shift < 0.25);
    EXPECT_EQ(r.figures.size(), 2u);
  }
}

TEST(Validation, TheMovedComparisonFindsADifferenceInTiming) {
  // Martin & Moyce's front 0.2 in T earlier than theirs (a faster release, say): the window's RMS is
  // large, and the comparison moved in time finds the 0.2 and nothing left.
  const Case c = *load_builtin_case("martin_moyce");
  TempDir dir;
  write_martin_moyce_probes(dir.path, c, 0.0, 0.2);
  const ValidationResult r = evaluate_martin_moyce(c, dir.path, full_bounds());
  ASSERT_EQ(r.comparisons[1].id, "front_window_moved");
  EXPECT_GT(r.comparisons[0].difference.rms, 0.15);
  EXPECT_NEAR(r.comparisons[1].difference.rms, 0.0, 1e-9);
  EXPECT_EQ(r.comparisons[1].quantity, "front Z moved +0.20 in T");

  // The same, directly: a curve late by 0.35 moves earlier, and the id and window carry over.
  const Series reference{{0.0, 1.0, 2.0, 3.0, 4.0}, {0.0, 0.0, 1.0, 1.0, 0.5}};
  Series late = reference;
  for (double& t : late.t) t += 0.35;
  const Comparison base{"p", "p* = p/(rho g H)", "data", "1 <= t <= 4", compare(late, reference, 1.0, 4.0)};
  const Comparison moved = moved_comparison(base, late, reference, 1.0, 4.0, 0.5, 0.01, "t*");
  EXPECT_EQ(moved.id, "p_moved");
  EXPECT_EQ(moved.quantity, "p* moved -0.35 in t*");
  EXPECT_EQ(moved.window, "1 <= t <= 4");
  EXPECT_NEAR(moved.difference.rms, 0.0, 1e-9);
  EXPECT_GT(base.difference.rms, 0.1);
}

// A tracker that logs a harmonic heave tau late (or early) against accelerometers that see it on
// time: tracker_delay finds tau from the two first harmonics, whatever the motion's own phase.
TEST(Validation, TrackerDelayIsFoundFromTheHeaveAcceleration) {
  const double period = 1.158, omega = 2.0 * std::numbers::pi / period, amplitude = 0.018;
  for (const double tau : {-0.34, -0.1, 0.0, 0.024, 0.5}) {
    for (const double phase : {0.3, 2.0, 5.5}) {
      Series tracked, acceleration;
      for (int i = 0; i <= 2000; ++i) {
        const double t = 10.0 + 0.01 * i;
        tracked.t.push_back(t);
        tracked.y.push_back(0.9 + amplitude * std::cos(omega * (t - tau) - phase));
        acceleration.t.push_back(t);
        acceleration.y.push_back(-omega * omega * amplitude * std::cos(omega * t - phase));
      }
      EXPECT_NEAR(tracker_delay(tracked, acceleration, omega, 12.0, 12.0 + 8 * period), tau, 1e-9)
          << "tau " << tau << ", phase " << phase;
    }
  }
  // Less than a whole period to fit: an error, not a number.
  const Series short_series{{0.0, 0.1, 0.2, 0.3, 0.4, 0.5}, {0.0, 1.0, 0.0, -1.0, 0.0, 1.0}};
  EXPECT_THROW(tracker_delay(short_series, short_series, omega, 0.0, 0.5), AnalysisError);
}

TEST(Validation, BuchnerScalingAndImpactTimeRecoverTheDataThatWentIn) {
  const Case c = *load_builtin_case("buchner");
  const double H = c.water[0].max[1], g = -c.gravity[1];
  const Series data = reference_table("buchner2002_p_wall_pysph.csv").series("tstar", "pstar");
  TempDir dir;
  // Strictly increasing times for a probe file: the data's repeated times nudged apart.
  Series p;
  for (std::size_t i = 0; i < data.size(); ++i) {
    double t = data.t[i] / std::sqrt(g / H);
    if (!p.t.empty() && t <= p.t.back()) t = p.t.back() + 1e-9;
    p.t.push_back(t);
    p.y.push_back(data.y[i] * c.rest_density * g * H);
  }
  write_probe(dir.path, "wall_pressure", "time,pressure", p);
  const ValidationResult r = evaluate_buchner(c, dir.path, full_bounds());
  // The plateau, the whole window and the impact time.
  ASSERT_EQ(r.checks.size(), 3u);
  EXPECT_LT(r.checks[0].value, 0.02);  // only the nudged duplicates differ
  EXPECT_LT(r.checks[1].value, 0.02);
  EXPECT_NEAR(r.checks[2].value, 0.0, 1e-6);
  EXPECT_TRUE(r.passed());
}

TEST(Validation, MissingProbeIsAClearError) {
  TempDir dir;
  try {
    evaluate_koshizuka_oka(*load_builtin_case("koshizuka_oka"), dir.path, full_bounds());
    FAIL() << "expected an error";
  } catch (const AnalysisError& e) {
    EXPECT_NE(std::string(e.what()).find("front"), std::string::npos) << e.what();
  }
}

// sluice validate --compare 'LABEL: KEY=VALUE; KEY=VALUE': the label names a column and a directory.
TEST(ValidationVariant, ParsesALabelAndItsOverrides) {
  const ValidationVariant v = parse_variant("  mdbc+shift :physics.wall_boundary=mdbc;  physics.shifting=2 ;; domain.h_over_dx=2 ");
  EXPECT_EQ(v.label, "mdbc+shift");
  ASSERT_EQ(v.sets.size(), 3u);
  EXPECT_EQ(v.sets[0], "physics.wall_boundary=mdbc");
  EXPECT_EQ(v.sets[1], "physics.shifting=2");
  EXPECT_EQ(v.sets[2], "domain.h_over_dx=2");
  // A vector value keeps its commas and spaces.
  EXPECT_EQ(parse_variant("g: physics.gravity=[0, -9.8]").sets.at(0), "physics.gravity=[0, -9.8]");
  const struct {
    const char* text;
    const char* expected;
  } bad[] = {{"physics.shifting=2", "no label"},
             {": physics.shifting=2", "the label is empty"},
             {"a/b: physics.shifting=2", "is not a plain name"},
             {"..: physics.shifting=2", "is not a plain name"},
             {"x:", "no KEY=VALUE"},
             {"x: ; ", "no KEY=VALUE"}};
  for (const auto& b : bad) {
    try {
      (void)parse_variant(b.text);
      ADD_FAILURE() << b.text << ": expected an error";
    } catch (const AnalysisError& e) {
      EXPECT_NE(std::string(e.what()).find(b.expected), std::string::npos) << b.text << ": " << e.what();
    }
  }
}

// The experiment's data the live view draws over a validation case's probes: on the run's clock and in
// its units (Buchner's p* and t* back to pascals and seconds), up to the run's end; none for a case
// without data.
TEST(ReferenceOverlays, BuchnerInPascalsAndSeconds) {
  const Case c = *load_builtin_case("buchner");
  const auto overlays = reference_overlays(c);
  ASSERT_EQ(overlays.size(), 1u);
  const ReferenceOverlay& o = overlays[0];
  EXPECT_EQ(o.series, "wall_pressure");
  EXPECT_EQ(o.column, "pressure");
  const Table data = reference_table("buchner2002_p_wall_pysph.csv");
  const Series star = data.series("tstar", "pstar");
  const double height = c.water[0].max[1], g = -c.gravity[1];
  ASSERT_GT(o.data.size(), 10u);
  EXPECT_NEAR(o.data.t[5], star.t[5] / std::sqrt(g / height), 1e-12);
  EXPECT_NEAR(o.data.y[5], star.y[5] * c.rest_density * g * height, 1e-9);
  EXPECT_LE(o.data.t.back(), c.end_time);
  EXPECT_TRUE(reference_overlays(*load_builtin_case("dam_break")).empty());
}

TEST(ReferenceOverlays, NtnuGaugesFromTheRecordOnTheRunsClock) {
  const Case c = *load_builtin_case("ntnu_flume");
  const auto overlays = reference_overlays(c);
  std::size_t gauges = 0;
  for (const Probe& p : c.probes) gauges += p.type == ProbeType::gauge;
  EXPECT_EQ(overlays.size(), gauges);
  for (const ReferenceOverlay& o : overlays) {
    EXPECT_TRUE(o.from_first_value);
    ASSERT_GT(o.data.size(), 100u);
    // Departures from the still level: near zero before the flap moves, waves of centimetres after.
    EXPECT_LT(std::abs(o.data.y[0]), 0.005) << o.series;
    double most = 0.0;
    for (double y : o.data.y) most = std::max(most, std::abs(y));
    EXPECT_GT(most, 0.005) << o.series;
    EXPECT_LT(most, 0.2) << o.series;
  }
}
