// The case loader: defaults, every key type, ranges, unknown keys and values with suggestions, TOML
// syntax errors, --set overrides, cross-field validation and the `sluice init` template round trip.
#include <gtest/gtest.h>

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <sstream>
#include <string>
#include <type_traits>
#include <variant>
#include <vector>

#include "sluice/case/params.hpp"
#include "sluice/case/release_gate.hpp"
#include "sluice/case/value_text.hpp"

namespace fs = std::filesystem;
using namespace sluice;

namespace {

// A case needs one [[water]] region; everything else takes its default (tank 20 m x 10 m).
const std::string minimal_water = "[[water]]\nmin = [0.0, 0.0]\nmax = [1.0, 1.0]\n";

Case parse(const std::string& text) { return parse_case(text, "test.toml"); }

// The CaseError message of `f`, or a test failure if it does not throw one.
template <class F>
std::string error_of(F&& f) {
  try {
    f();
  } catch (const CaseError& e) {
    return e.what();
  }
  ADD_FAILURE() << "expected a CaseError";
  return "";
}

std::string parse_error(const std::string& text) {
  return error_of([&] { parse(text); });
}

std::string override_error(Case c, const std::string& assignment) {
  return error_of([&] { apply_override(c, assignment); });
}

// Checks that `message` contains each of `parts`.
void expect_contains(const std::string& message, std::initializer_list<std::string> parts) {
  for (const auto& part : parts)
    EXPECT_NE(message.find(part), std::string::npos) << "message:  " << message << "\nlacks:    " << part;
}

template <class Owner>
ParamValue value_of(const Owner& o, const Param<Owner>& p) {
  return std::visit(
      [&](auto member) -> ParamValue {
        if constexpr (std::is_same_v<decltype(member), ChoiceField<Owner>>)
          return p.choices.at(static_cast<std::size_t>(member.get(o)));
        else
          return o.*member;
      },
      p.field);
}

std::string show(const ParamValue& v) {
  return std::visit(
      [](const auto& x) -> std::string {
        using T = std::decay_t<decltype(x)>;
        if constexpr (std::is_same_v<T, std::monostate>) return "(none)";
        else if constexpr (std::is_same_v<T, std::string>) return '"' + x + '"';
        else if constexpr (std::is_same_v<T, Vec3>) return fmt::format("[{}, {}, {}]", x[0], x[1], x[2]);
        else if constexpr (std::is_same_v<T, std::vector<std::string>>) return fmt::format("{} strings", x.size());
        else if constexpr (std::is_same_v<T, std::vector<Vec2>>) return fmt::format("{} points", x.size());
        else if constexpr (std::is_same_v<T, std::vector<double>>) return fmt::format("{} numbers", x.size());
        else return fmt::format("{}", x);
      },
      v);
}

// Field-by-field equality of two cases, written out so that a field missing from the declarations
// (and so from the template) shows up too.
void expect_regions_equal(const std::vector<Region>& a, const std::vector<Region>& b, const std::string& what) {
  ASSERT_EQ(a.size(), b.size()) << what;
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].shape, b[i].shape) << what << " " << i;
    EXPECT_EQ(a[i].min, b[i].min) << what << " " << i;
    EXPECT_EQ(a[i].max, b[i].max) << what << " " << i;
  }
}

void expect_cases_equal(const Case& a, const Case& b) {
  EXPECT_EQ(a.name, b.name);
  EXPECT_EQ(a.description, b.description);
  EXPECT_EQ(a.dimension, b.dimension);
  EXPECT_EQ(a.dx, b.dx);
  EXPECT_EQ(a.h_over_dx, b.h_over_dx);
  EXPECT_EQ(a.kernel, b.kernel);
  EXPECT_EQ(a.tank_width, b.tank_width);
  EXPECT_EQ(a.tank_depth, b.tank_depth);
  EXPECT_EQ(a.tank_height, b.tank_height);
  EXPECT_EQ(a.tank_lid, b.tank_lid);
  EXPECT_EQ(a.rest_density, b.rest_density);
  EXPECT_EQ(a.sound_speed, b.sound_speed);
  EXPECT_EQ(a.gamma, b.gamma);
  EXPECT_EQ(a.viscosity, b.viscosity);
  EXPECT_EQ(a.gravity, b.gravity);
  EXPECT_EQ(a.artificial_viscosity, b.artificial_viscosity);
  EXPECT_EQ(a.density_diffusion, b.density_diffusion);
  EXPECT_EQ(a.shepard_every, b.shepard_every);
  EXPECT_EQ(a.hydrostatic_start, b.hydrostatic_start);
  EXPECT_EQ(a.end_time, b.end_time);
  EXPECT_EQ(a.integrator, b.integrator);
  EXPECT_EQ(a.wall_boundary, b.wall_boundary);
  EXPECT_EQ(a.cfl, b.cfl);
  EXPECT_EQ(a.fixed_dt, b.fixed_dt);
  EXPECT_EQ(a.output_interval, b.output_interval);
  EXPECT_EQ(a.output_formats, b.output_formats);
  EXPECT_EQ(a.checkpoint_interval, b.checkpoint_interval);
  expect_regions_equal(a.water, b.water, "water");
  expect_regions_equal(a.walls, b.walls, "wall");
  ASSERT_EQ(a.probes.size(), b.probes.size());
  for (std::size_t i = 0; i < a.probes.size(); ++i) {
    EXPECT_EQ(a.probes[i].name, b.probes[i].name);
    EXPECT_EQ(a.probes[i].type, b.probes[i].type);
    EXPECT_EQ(a.probes[i].point, b.probes[i].point);
    EXPECT_EQ(a.probes[i].direction, b.probes[i].direction);
    EXPECT_EQ(a.probes[i].band, b.probes[i].band);
    EXPECT_EQ(a.probes[i].interval, b.probes[i].interval);
  }
}

// A case using every section and odd values: walls, probes of each type, strings with quotes,
// backslashes, a newline, a tab and non-ASCII text, numbers that need all 17 digits.
Case unusual_case() {
  Case c = parse(R"(
[case]
name = "odd_case-1"
description = "a \"quoted\" word, a back\\slash,\na newline,\ta tab and \u00e9t\u00e9"
[domain]
dx = 0.1
h_over_dx = 2
kernel = "wendland_c2"
[tank]
width = 3.3
height = 1.1
lid = false
[fluid]
density = 998.2
sound_speed = 31.4
gamma = 1
viscosity = 0
[physics]
gravity = [0.1, -9.80665]
artificial_viscosity = 0.0
density_diffusion = 1
shepard_every = 0
hydrostatic_start = false
wall_boundary = "adami"
[time]
end = 1e-3
integrator = "euler"
cfl = 0.1
dt = 1.2345678901234567e-5
[output]
interval = 0.30000000000000004
formats = ["npz"]
checkpoint_interval = 0.5
[[water]]
min = [0, 0]
max = [1.7, 0.6]
[[water]]
shape = "box"
min = [1.7, 0.0]
max = [3.3, 0.2]
[[wall]]
min = [2.0, 0.0]
max = [2.1, 0.5]
[[probe]]
name = "p1"
type = "pressure"
point = [3.2, 0.05]
[[probe]]
name = "gauge_a"
type = "gauge"
point = [1.5, 0]
band = 0.05
interval = 0.01
[[probe]]
name = "front"
type = "front"
point = [0, 0.01]
direction = [1, 0.5]
)");
  return c;
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Defaults

TEST(CaseDefaults, EveryKeyTakesItsDeclaredDefault) {
  const Case c = parse(minimal_water);
  ASSERT_FALSE(case_params().empty());
  for (const auto& p : case_params()) {
    ASSERT_FALSE(std::holds_alternative<std::monostate>(p.default_value)) << p.key << " has no default";
    EXPECT_EQ(value_of(c, p), p.default_value)
        << p.key << ": got " << show(value_of(c, p)) << ", declared " << show(p.default_value);
  }
  ASSERT_EQ(c.water.size(), 1u);
  EXPECT_TRUE(c.walls.empty());
  EXPECT_TRUE(c.probes.empty());
}

TEST(CaseDefaults, ItemKeysTakeTheirDeclaredDefaults) {
  const Case c = parse(minimal_water + "[[probe]]\nname = \"p\"\ntype = \"pressure\"\npoint = [1.0, 1.0]\n");
  for (const auto& p : region_params()) {
    // Keys that the item's shape uses are required (min, max of a box), not defaulted.
    if (!std::holds_alternative<std::monostate>(p.default_value) && !(p.applies && p.applies(c.water[0]))) {
      EXPECT_EQ(value_of(c.water[0], p), p.default_value) << p.key;
    }
  }
  for (const auto& p : probe_params()) {
    if (!std::holds_alternative<std::monostate>(p.default_value)) {
      EXPECT_EQ(value_of(c.probes[0], p), p.default_value) << p.key;
    }
  }
}

TEST(CaseDefaults, DefaultsMatchTheDocumentedValues) {
  // The values the documentation and the template promise: a change here must be a deliberate one.
  const Case c = parse(minimal_water);
  EXPECT_EQ(c.name, "unnamed");
  EXPECT_EQ(c.dx, 0.2);
  EXPECT_EQ(c.h_over_dx, 2.0);
  EXPECT_EQ(c.kernel, KernelType::cubic_spline);
  EXPECT_EQ(c.tank_width, 20.0);
  EXPECT_EQ(c.tank_height, 10.0);
  EXPECT_TRUE(c.tank_lid);
  EXPECT_EQ(c.rest_density, 1000.0);
  EXPECT_EQ(c.gravity, (Vec3{0.0, -9.81, 0.0}));
  EXPECT_EQ(c.artificial_viscosity, 0.1);
  EXPECT_EQ(c.density_diffusion, 0.1);
  EXPECT_EQ(c.shepard_every, 20);
  EXPECT_EQ(c.integrator, Integrator::predictor_corrector);
  // The walls validation chose for wall pressures (docs/validation.md, "Defaults").
  EXPECT_EQ(c.wall_boundary, WallBoundary::mdbc);
  EXPECT_EQ(c.wall_slip, WallSlip::free_slip);
  EXPECT_EQ(c.wall_friction, WallFriction::automatic);
  EXPECT_EQ(wall_friction_in_effect(c), WallFriction::log_law);
  EXPECT_EQ(c.shifting, 2.0);
  EXPECT_EQ(c.output_formats, (std::vector<std::string>{"vtk", "npz"}));
  EXPECT_EQ(c.water[0].shape, Shape::box);
}

TEST(CaseDefaults, ThreeDimensionalDefaultsAreTheValidatedOnes) {
  // In 3D, what SPHERIC test 2 was validated with: mdbc walls at h = 1.3 dx, without shifting or the
  // wall function (h = 2 dx would cost 3.6 times the pairs).
  const Case c = parse("[domain]\ndimension = 3\n[[water]]\nmin = [0.0, 0.0, 0.0]\nmax = [1.0, 1.0, 1.0]\n");
  EXPECT_EQ(c.h_over_dx, 1.3);
  EXPECT_EQ(c.wall_boundary, WallBoundary::mdbc);
  EXPECT_EQ(wall_friction_in_effect(c), WallFriction::none);
  EXPECT_EQ(c.shifting, 0.0);
  EXPECT_EQ(c.gravity, (Vec3{0.0, 0.0, -9.81}));
}

TEST(CaseDefaults, DeclarationsAreConsistent) {
  std::vector<std::string> section_names;
  for (const auto& s : case_sections()) section_names.push_back(s.name);
  std::vector<std::string> seen;
  for (const auto& p : case_params()) {
    EXPECT_FALSE(p.description.empty()) << p.key;
    const auto dot = p.key.find('.');
    ASSERT_NE(dot, std::string::npos) << p.key;
    EXPECT_NE(std::find(section_names.begin(), section_names.end(), p.key.substr(0, dot)), section_names.end())
        << p.key << " is in no declared section";
    EXPECT_EQ(std::find(seen.begin(), seen.end(), p.key), seen.end()) << p.key << " declared twice";
    seen.push_back(p.key);
    // A default must itself be allowed.
    if (const double* d = std::get_if<double>(&p.default_value); d && p.lower <= p.upper) {
      EXPECT_GE(*d, p.lower) << p.key;
      EXPECT_LE(*d, p.upper) << p.key;
    }
    if (const auto* s = std::get_if<std::string>(&p.default_value); s && !p.choices.empty()) {
      EXPECT_NE(std::find(p.choices.begin(), p.choices.end(), *s), p.choices.end()) << p.key;
    }
  }
}

// ---------------------------------------------------------------------------------------------
// Each type of key

TEST(CaseTypes, RealAcceptsFloatsAndIntegers) {
  EXPECT_EQ(parse("[domain]\ndx = 0.25\n" + minimal_water).dx, 0.25);
  EXPECT_EQ(parse("[domain]\ndx = 1\n" + minimal_water).dx, 1.0);
  EXPECT_EQ(parse("[time]\nend = 2.5e1\n" + minimal_water).end_time, 25.0);
}

TEST(CaseTypes, RealRejectsOtherTypes) {
  expect_contains(parse_error("[domain]\ndx = \"0.1\"\n" + minimal_water),
                  {"test.toml:2:6", "domain.dx", "0.1", "wrong type", "expected a number from 0.0001 to 100 (m)"});
  expect_contains(parse_error("[domain]\ndx = true\n" + minimal_water), {"domain.dx = true", "wrong type"});
  expect_contains(parse_error("[domain]\ndx = [0.1]\n" + minimal_water), {"domain.dx", "wrong type"});
}

TEST(CaseTypes, RealRejectsNonFinite) {
  expect_contains(parse_error("[time]\nend = inf\n" + minimal_water), {"time.end = inf", "not a finite number"});
  expect_contains(parse_error("[domain]\ndx = nan\n" + minimal_water), {"domain.dx = nan", "not a finite number"});
}

TEST(CaseTypes, Integer) {
  EXPECT_EQ(parse("[physics]\nshepard_every = 7\n" + minimal_water).shepard_every, 7);
  expect_contains(parse_error("[physics]\nshepard_every = 2.5\n" + minimal_water),
                  {"test.toml:2:17", "physics.shepard_every = 2.5", "wrong type", "expected an integer >= 0 (steps)"});
  expect_contains(parse_error("[physics]\nshepard_every = 3000000000\n" + minimal_water),
                  {"physics.shepard_every = 3000000000", "out of range"});
  expect_contains(parse_error("[physics]\nshepard_every = -1\n" + minimal_water),
                  {"physics.shepard_every = -1", "out of range", "an integer >= 0"});
}

TEST(CaseTypes, Bool) {
  EXPECT_FALSE(parse("[tank]\nlid = false\n" + minimal_water).tank_lid);
  EXPECT_TRUE(parse("[tank]\nlid = true\n" + minimal_water).tank_lid);
  expect_contains(parse_error("[tank]\nlid = \"no\"\n" + minimal_water),
                  {"test.toml:2:7", "tank.lid", "no", "wrong type", "expected true or false"});
  expect_contains(parse_error("[tank]\nlid = 1\n" + minimal_water), {"tank.lid = 1", "true or false"});
}

TEST(CaseTypes, StringChoices) {
  EXPECT_EQ(parse("[domain]\nkernel = \"wendland_c2\"\n" + minimal_water).kernel, KernelType::wendland_c2);
  EXPECT_EQ(parse("[time]\nintegrator = \"euler\"\n" + minimal_water).integrator, Integrator::euler);
  EXPECT_EQ(parse("[time]\nintegrator = \"leapfrog\"\n" + minimal_water).integrator, Integrator::leapfrog);
  expect_contains(parse_error("[time]\nintegrator = \"eulr\"\n" + minimal_water),
                  {"test.toml:2:14", "time.integrator = \"eulr\"", "unknown value", "did you mean \"euler\"?",
                   "expected one of \"predictor_corrector\", \"euler\", \"leapfrog\""});
  // An abbreviation finds its choice too.
  expect_contains(parse_error("[domain]\nkernel = \"wendland\"\n" + minimal_water),
                  {"domain.kernel", "did you mean \"wendland_c2\"?"});
  // Nothing close: no suggestion, but the choices.
  const std::string far = parse_error("[domain]\nkernel = \"gaussian\"\n" + minimal_water);
  expect_contains(far, {"unknown value", "\"cubic_spline\", \"wendland_c2\""});
  EXPECT_EQ(far.find("did you mean"), std::string::npos) << far;
  expect_contains(parse_error("[domain]\nkernel = 3\n" + minimal_water), {"domain.kernel = 3", "wrong type"});
}

TEST(CaseTypes, WallBoundaryChoices) {
  EXPECT_EQ(parse("[physics]\nwall_boundary = \"adami\"\n" + minimal_water).wall_boundary, WallBoundary::adami);
  EXPECT_EQ(parse("[physics]\nwall_boundary = \"dynamic\"\n" + minimal_water).wall_boundary, WallBoundary::dynamic);
  expect_contains(parse_error("[physics]\nwall_boundary = \"adamy\"\n" + minimal_water),
                  {"test.toml:2", "physics.wall_boundary = \"adamy\"", "unknown value", "did you mean \"adami\"?",
                   "expected one of \"dynamic\", \"adami\""});
  Case c = parse(minimal_water);
  apply_override(c, "physics.wall_boundary=adami");
  EXPECT_EQ(c.wall_boundary, WallBoundary::adami);
  expect_contains(override_error(c, "physics.wall_boundary=ghost"),
                  {"physics.wall_boundary", "ghost", "expected one of \"dynamic\", \"adami\""});
}

TEST(CaseTypes, FreeString) {
  const Case c = parse("[case]\nname = \"tank 2\"\ndescription = \"x\"\n" + minimal_water);
  EXPECT_EQ(c.name, "tank 2");
  EXPECT_EQ(c.description, "x");
  expect_contains(parse_error("[case]\nname = 5\n" + minimal_water), {"case.name = 5", "wrong type", "a string"});
}

TEST(CaseTypes, Vec2) {
  EXPECT_EQ(parse("[physics]\ngravity = [0.5, -1]\n" + minimal_water).gravity, (Vec3{0.5, -1.0, 0.0}));
  for (const char* bad : {"[1.0]", "[1.0, 2.0, 3.0]", "[1.0, \"a\"]", "\"down\"", "-9.81", "[inf, 0.0]"})
    expect_contains(parse_error(fmt::format("[physics]\ngravity = {}\n", bad) + minimal_water),
                    {"test.toml:2:11", "physics.gravity", "wrong type", "an array of two numbers [x, y] (m/s^2)"});
}

TEST(CaseTypes, StringList) {
  EXPECT_EQ(parse("[output]\nformats = [\"npz\"]\n" + minimal_water).output_formats,
            (std::vector<std::string>{"npz"}));
  EXPECT_EQ(parse("[output]\nformats = [\"npz\", \"vtk\"]\n" + minimal_water).output_formats,
            (std::vector<std::string>{"npz", "vtk"}));
  expect_contains(parse_error("[output]\nformats = [\"npz\", \"csv\"]\n" + minimal_water),
                  {"test.toml:2:11", "output.formats", "unknown entry \"csv\"", "each one of \"vtk\", \"npz\""});
  expect_contains(parse_error("[output]\nformats = [\"npz\", \"npz\"]\n" + minimal_water),
                  {"\"npz\" listed twice"});
  expect_contains(parse_error("[output]\nformats = \"npz\"\n" + minimal_water), {"output.formats", "wrong type"});
  expect_contains(parse_error("[output]\nformats = [1]\n" + minimal_water), {"output.formats", "wrong type"});
}

// ---------------------------------------------------------------------------------------------
// Ranges

TEST(CaseRanges, BoundsAreInclusive) {
  EXPECT_EQ(parse("[domain]\nh_over_dx = 1.0\n" + minimal_water).h_over_dx, 1.0);
  EXPECT_EQ(parse("[domain]\nh_over_dx = 3.0\n" + minimal_water).h_over_dx, 3.0);
  EXPECT_EQ(parse("[time]\ncfl = 0.3\n" + minimal_water).cfl, 0.3);
  EXPECT_EQ(parse("[time]\nend = 0\n" + minimal_water).end_time, 0.0);
}

TEST(CaseRanges, OutOfRangeNamesKeyValueAndRange) {
  expect_contains(parse_error("[domain]\ndx = -0.1\n" + minimal_water),
                  {"test.toml:2:6", "domain.dx = -0.1", "out of range", "expected a number from 0.0001 to 100 (m)"});
  expect_contains(parse_error("[domain]\nh_over_dx = 3.5\n" + minimal_water),
                  {"domain.h_over_dx = 3.5", "out of range", "from 1 to 3"});
  expect_contains(parse_error("[time]\ncfl = 0.5\n" + minimal_water), {"time.cfl = 0.5", "from 0.1 to 0.3"});
  expect_contains(parse_error("[time]\nend = -1\n" + minimal_water),
                  {"time.end = -1", "out of range", "a number >= 0 (s)"});
  expect_contains(parse_error("[physics]\nartificial_viscosity = 1.5\n" + minimal_water),
                  {"physics.artificial_viscosity = 1.5", "from 0 to 1"});
  expect_contains(parse_error(minimal_water + "[[probe]]\nname = \"p\"\ntype = \"gauge\"\npoint = [1, 1]\nband = -1\n"),
                  {"probe[0].band = -1", "out of range", ">= 0 (m)"});
}

// ---------------------------------------------------------------------------------------------
// Unknown keys and sections

TEST(CaseUnknown, KeyWithSuggestion) {
  expect_contains(parse_error("[domain]\nddx = 0.1\n" + minimal_water),
                  {"test.toml:2:7", "unknown key 'domain.ddx'", "did you mean 'domain.dx'?"});
  expect_contains(parse_error("[time]\nintegator = \"euler\"\n" + minimal_water),
                  {"unknown key 'time.integator'", "did you mean 'time.integrator'?"});
}

TEST(CaseUnknown, KeyWithoutCloseMatchPointsToInit) {
  const std::string m = parse_error("[domain]\nresolution_of_everything = 0.1\n" + minimal_water);
  expect_contains(m, {"unknown key 'domain.resolution_of_everything'", "sluice init"});
  EXPECT_EQ(m.find("did you mean"), std::string::npos) << m;
}

TEST(CaseUnknown, SectionWithSuggestion) {
  expect_contains(parse_error("[domian]\ndx = 0.1\n" + minimal_water),
                  {"test.toml:1:1", "unknown section 'domian'", "did you mean 'domain'?"});
  expect_contains(parse_error("domian.dx = 0.1\n" + minimal_water), {"unknown section 'domian'", "'domain'"});
  expect_contains(parse_error("[[watr]]\nmin = [0, 0]\nmax = [1, 1]\n" + minimal_water),
                  {"unknown section 'watr'", "did you mean 'water'?"});
  expect_contains(parse_error("[zzzzzzzz]\nx = 1\n" + minimal_water), {"unknown section 'zzzzzzzz'", "expected one of: case, domain"});
}

TEST(CaseUnknown, KeyOutsideAnySection) {
  expect_contains(parse_error("dx = 0.1\n" + minimal_water),
                  {"test.toml:1:6", "'dx' is outside any section", "did you mean 'domain.dx'", "under [domain]"});
}

TEST(CaseUnknown, KeyInsideArrayItem) {
  expect_contains(parse_error("[[water]]\nmin = [0.0, 0.0]\nmx = [1.0, 1.0]\n"),
                  {"test.toml:3:6", "unknown key 'mx' in [[water]]", "did you mean 'max'?"});
  expect_contains(parse_error(minimal_water + "[[probe]]\nname = \"p\"\ntype = \"gauge\"\npoint = [1, 1]\nbandd = 1\n"),
                  {"unknown key 'bandd' in [[probe]]", "did you mean 'band'?"});
  expect_contains(parse_error(minimal_water + "[[wall]]\nmin = [0, 0]\nmax = [1, 1]\ncolour = \"red\"\n"),
                  {"unknown key 'colour' in [[wall]]", "expected one of: name, shape, min, max"});
}

TEST(CaseUnknown, SectionsOfTheWrongKind) {
  expect_contains(parse_error("[water]\nmin = [0.0, 0.0]\nmax = [1.0, 1.0]\n"), {"'water' must be written as [[water]]"});
  expect_contains(parse_error("domain = 3\n" + minimal_water), {"'domain' must be a section [domain]"});
  expect_contains(parse_error("[[domain]]\ndx = 0.1\n" + minimal_water), {"'domain' must be a section [domain]"});
  expect_contains(parse_error("[domain.dx]\nx = 1\n" + minimal_water), {"domain.dx = a table", "wrong type"});
}

TEST(CaseUnknown, MissingRequiredItemKey) {
  expect_contains(parse_error("[[water]]\nmin = [0.0, 0.0]\n"),
                  {"test.toml:1:1", "[[water]] number 1 has no 'max'", "expected an array of two numbers"});
  expect_contains(parse_error(minimal_water + "[[probe]]\nname = \"p\"\npoint = [1, 1]\n"),
                  {"test.toml:4:1", "[[probe]] number 1 has no 'type'", "\"pressure\", \"gauge\", \"front\""});
  expect_contains(parse_error(minimal_water + "[[wall]]\nmax = [1, 1]\n"), {"[[wall]] number 1 has no 'min'"});
}

TEST(CaseSyntax, InvalidTomlHasLineAndColumn) {
  expect_contains(parse_error("[domain\ndx = 0.1\n"), {"test.toml:1:8: not valid TOML"});
  expect_contains(parse_error("[domain]\ndx = 0.1\ndx = 0.2\n"), {"test.toml:3:", "not valid TOML"});
  expect_contains(parse_error("[domain]\ndx = 0..1\n"), {"test.toml:2:", "not valid TOML"});
  expect_contains(parse_error("[case]\nname = \"unterminated\n"), {"test.toml:2:", "not valid TOML"});
}

// ---------------------------------------------------------------------------------------------
// Files

class CaseFiles : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           fmt::format("sluice_case_loader_{}_{}", ::testing::UnitTest::GetInstance()->current_test_info()->name(),
                       std::chrono::steady_clock::now().time_since_epoch().count());
    fs::create_directories(dir_);
  }
  void TearDown() override {
    std::error_code ec;
    fs::remove_all(dir_, ec);
  }
  fs::path write(const std::string& name, const std::string& text) {
    std::ofstream(dir_ / name) << text;
    return dir_ / name;
  }
  fs::path dir_;
};

TEST_F(CaseFiles, LoadsAFile) {
  const fs::path p = write("ok.toml", "[domain]\ndx = 0.5\n" + minimal_water);
  EXPECT_EQ(load_case_file(p).dx, 0.5);
}

TEST_F(CaseFiles, ErrorsNameTheFile) {
  const fs::path p = write("bad.toml", "[domain]\ndx = 500\n" + minimal_water);
  const std::string m = error_of([&] { load_case_file(p); });
  expect_contains(m, {p.string() + ":2:6: domain.dx = 500: out of range"});
}

TEST_F(CaseFiles, MissingFileAndDirectory) {
  expect_contains(error_of([&] { load_case_file(dir_ / "nope.toml"); }),
                  {(dir_ / "nope.toml").string(), "no such case file"});
  expect_contains(error_of([&] { load_case_file(dir_); }), {dir_.string(), "is a directory"});
}

// ---------------------------------------------------------------------------------------------
// --set overrides

TEST(CaseOverrides, EveryScalarKeyType) {
  Case c = parse(minimal_water);
  apply_override(c, "domain.dx=0.1");
  EXPECT_EQ(c.dx, 0.1);
  apply_override(c, "domain.dx=1");  // an integer for a real
  EXPECT_EQ(c.dx, 1.0);
  apply_override(c, "physics.shepard_every=5");
  EXPECT_EQ(c.shepard_every, 5);
  apply_override(c, "tank.lid=false");
  EXPECT_FALSE(c.tank_lid);
  apply_override(c, "time.integrator=\"euler\"");
  EXPECT_EQ(c.integrator, Integrator::euler);
  apply_override(c, "physics.gravity=[0.0, -1.62]");
  EXPECT_EQ(c.gravity, (Vec3{0.0, -1.62, 0.0}));
  apply_override(c, "output.formats=[\"npz\"]");
  EXPECT_EQ(c.output_formats, (std::vector<std::string>{"npz"}));
  apply_override(c, " time.end = 2.5 ");  // spaces around the key and value
  EXPECT_EQ(c.end_time, 2.5);
}

TEST(CaseOverrides, EveryDeclaredKeyCanBeSetToItsDefault) {
  Case c = parse(minimal_water);
  apply_override(c, "domain.dx=0.1");
  for (const auto& p : case_params()) {
    // The dimension is the case file's to say (tested in CaseDimension), and 3D keys are refused in 2D.
    if (p.key == "domain.dimension" || p.only_3d) continue;
    // Render the default the way a user would type it.
    const std::string text = std::visit(
        [](const auto& x) -> std::string {
          using T = std::decay_t<decltype(x)>;
          if constexpr (std::is_same_v<T, std::string>) return '"' + x + '"';
          else if constexpr (std::is_same_v<T, Vec3>) return fmt::format("[{}, {}]", x[0], x[1]);
          else if constexpr (std::is_same_v<T, bool>) return x ? "true" : "false";
          else if constexpr (std::is_same_v<T, std::vector<std::string>>) {
            std::string s;
            for (const auto& i : x) s += (s.empty() ? "\"" : ", \"") + i + "\"";
            return "[" + s + "]";
          } else if constexpr (std::is_same_v<T, std::vector<Vec2>>) {
            std::string s;
            for (const auto& q : x) s += fmt::format("{}[{}, {}]", s.empty() ? "" : ", ", q[0], q[1]);
            return "[" + s + "]";
          } else if constexpr (std::is_same_v<T, std::vector<double>>) {
            std::string s;
            for (const double q : x) s += fmt::format("{}{}", s.empty() ? "" : ", ", q);
            return "[" + s + "]";
          } else if constexpr (std::is_same_v<T, std::monostate>) return "";
          else return fmt::format("{}", x);
        },
        p.default_value);
    SCOPED_TRACE(p.key + "=" + text);
    EXPECT_NO_THROW(apply_override(c, p.key + "=" + text));
    EXPECT_EQ(value_of(c, p), p.default_value);
  }
}

TEST(CaseOverrides, BareWordsAreStrings) {
  Case c = parse(minimal_water);
  apply_override(c, "time.integrator=euler");
  EXPECT_EQ(c.integrator, Integrator::euler);
  apply_override(c, "case.name=my_run");
  EXPECT_EQ(c.name, "my_run");
  // A bare word that happens to be TOML of another type is still the string for a string key.
  apply_override(c, "case.name=2024");
  EXPECT_EQ(c.name, "2024");
  apply_override(c, "case.description=a \"quoted\" word");
  EXPECT_EQ(c.description, "a \"quoted\" word");
  // String lists may be given bare, since shells strip the quotes from ["npz", "vtk"].
  apply_override(c, "output.formats=npz");
  EXPECT_EQ(c.output_formats, (std::vector<std::string>{"npz"}));
  apply_override(c, "output.formats=[npz, vtk]");
  EXPECT_EQ(c.output_formats, (std::vector<std::string>{"npz", "vtk"}));
  apply_override(c, "output.formats=vtk,npz");
  EXPECT_EQ(c.output_formats, (std::vector<std::string>{"vtk", "npz"}));
}

TEST(CaseOverrides, ItemKeys) {
  Case c = parse(minimal_water + "[[water]]\nmin = [2.0, 0.0]\nmax = [3.0, 1.0]\n");
  apply_override(c, "water[1].max=[3.0, 4.0]");
  EXPECT_EQ(c.water[1].max, (Vec3{3.0, 4.0, 0.0}));
  apply_override(c, "water.1.max=[5.0, 6.0]");
  EXPECT_EQ(c.water[1].max, (Vec3{5.0, 6.0, 0.0}));
  EXPECT_EQ(c.water[0].max, (Vec3{1.0, 1.0, 0.0}));  // the other entry untouched

  Case d = parse(minimal_water + "[[probe]]\nname = \"p\"\ntype = \"pressure\"\npoint = [1, 1]\n");
  apply_override(d, "probe[0].type=gauge");
  EXPECT_EQ(d.probes[0].type, ProbeType::gauge);
  apply_override(d, "probe[0].band=0.5");
  EXPECT_EQ(d.probes[0].band, 0.5);
}

TEST(CaseOverrides, IndexOutOfRange) {
  const Case c = parse(minimal_water);
  expect_contains(override_error(c, "water[1].max=[3.0, 4.0]"),
                  {"--set water[1].max=[3.0, 4.0]", "the case has 1 [[water]] entry", "there is no water[1]"});
  expect_contains(override_error(c, "wall[0].min=[0, 0]"), {"the case has 0 [[wall]] entries"});
  expect_contains(override_error(c, "water[99999999999999999999].max=[1, 1]"), {"there is no water[99999999999999999999]"});
}

TEST(CaseOverrides, UnknownKeys) {
  const Case c = parse(minimal_water);
  expect_contains(override_error(c, "domain.ddx=0.1"),
                  {"--set domain.ddx=0.1: unknown key 'domain.ddx'; did you mean 'domain.dx'?"});
  expect_contains(override_error(c, "domian.dx=0.1"), {"unknown key 'domian.dx'", "did you mean 'domain.dx'?"});
  expect_contains(override_error(c, "water[0].mx=[1, 1]"),
                  {"unknown key 'mx' in [[water]]", "did you mean 'water[0].max'?"});
  expect_contains(override_error(c, "nothing_like_a_key=1"), {"unknown key 'nothing_like_a_key'", "sluice init"});
}

TEST(CaseOverrides, BadValues) {
  const Case c = parse(minimal_water);
  expect_contains(override_error(c, "domain.dx=-1"),
                  {"--set domain.dx=-1: domain.dx = -1: out of range; expected a number from 0.0001 to 100 (m)"});
  expect_contains(override_error(c, "domain.dx=abc"), {"domain.dx", "abc", "wrong type", "expected a number"});
  expect_contains(override_error(c, "time.integrator=eulr"), {"unknown value (did you mean \"euler\"?)"});
  expect_contains(override_error(c, "tank.lid=yes"), {"tank.lid", "yes", "expected true or false"});
  expect_contains(override_error(c, "physics.gravity=[1]"), {"physics.gravity", "an array of two numbers"});
  expect_contains(override_error(c, "output.formats=csv"), {"unknown entry \"csv\""});
  expect_contains(override_error(c, "domain.dx=0.1\nfluid.density=3"), {"domain.dx", "wrong type"});
}

TEST(CaseOverrides, Malformed) {
  const Case c = parse(minimal_water);
  expect_contains(override_error(c, "domain.dx"), {"--set domain.dx: expected key=value"});
  expect_contains(override_error(c, "domain.dx="), {"no value after '='", "expected a number from 0.0001 to 100"});
  expect_contains(override_error(c, "=0.1"), {"no key before '='"});
}

// A case's strings go into its checkpoint as TOML, which is UTF-8: a --set of other bytes made a run
// whose checkpoint could not be read back ("invalid utf-8 sequence") when restarting.
TEST(CaseOverrides, ValuesMustBeUtf8) {
  Case c = parse(minimal_water);
  expect_contains(override_error(c, "case.name=caf\xe9"), {R"(--set case.name=caf\xE9: not UTF-8 text)"});
  expect_contains(override_error(c, "case.description=\xff"), {"not UTF-8 text"});
  apply_override(c, "case.name=caf\u00e9");
  EXPECT_EQ(parse_case(case_template(c), "template").name, "caf\u00e9");
}

TEST(CaseOverrides, ValidatedAfterwards) {
  const Case c = parse(minimal_water);
  expect_contains(override_error(c, "tank.width=0.5"), {"--set tank.width=0.5", "reaches outside the tank"});
  expect_contains(override_error(c, "case.name=a/b"), {"case.name = \"a/b\"", "not a usable name"});
}

TEST(CaseOverrides, SeveralAreValidatedTogether) {
  // Shrinking the tank first would leave the water outside it for a moment: the order of --set must
  // not matter.
  Case c = parse("[[water]]\nmin = [0.0, 0.0]\nmax = [10.0, 1.0]\n");
  apply_overrides(c, {"tank.width=5", "water[0].max=[5.0, 1.0]"});
  EXPECT_EQ(c.tank_width, 5.0);
  EXPECT_EQ(c.water[0].max, (Vec3{5.0, 1.0, 0.0}));
  // ... but the result is still validated.
  Case d = parse("[[water]]\nmin = [0.0, 0.0]\nmax = [10.0, 1.0]\n");
  expect_contains(error_of([&] { apply_overrides(d, {"tank.width=5"}); }),
                  {"with --set tank.width=5", "reaches outside the tank"});
  // The first bad override stops at once with its own message.
  expect_contains(error_of([&] { apply_overrides(d, {"domain.dx=1", "domain.ddx=1"}); }),
                  {"--set domain.ddx=1: unknown key"});
}

// ---------------------------------------------------------------------------------------------
// Cross-field validation

TEST(CaseValidation, WaterOutsideTank) {
  expect_contains(parse_error("[tank]\nwidth = 2.0\nheight = 1.0\n[[water]]\nmin = [0, 0]\nmax = [3.0, 0.5]\n"),
                  {"test.toml: [[water]] number 1", "reaches outside the tank [0, 2] x [0, 1]"});
  expect_contains(parse_error("[[water]]\nmin = [-1, 0]\nmax = [1, 1]\n"), {"reaches outside the tank"});
  // Exactly filling the tank is fine.
  EXPECT_NO_THROW(parse("[tank]\nwidth = 2.0\nheight = 1.0\n[[water]]\nmin = [0, 0]\nmax = [2.0, 1.0]\n"));
}

// Water fills the points (i + 1/2) dx inside a region: a box between two of them along an axis would
// hold none, and the run would start without that water.
TEST(CaseValidation, WaterBoxThinnerThanTheLattice) {
  expect_contains(parse_error("[domain]\ndx = 0.1\n[[water]]\nmin = [0.5, 0]\nmax = [0.52, 1]\n"),
                  {"test.toml: [[water]] number 1 (box from [0.5, 0.0] to [0.52, 1.0])", "holds no water particle",
                   "domain.dx = 0.1 m", "0.02 m across along x", "expected a region at least dx across"});
  expect_contains(
      parse_error("[domain]\ndimension = 3\ndx = 0.1\n[tank]\nwidth = 2.0\ndepth = 1.0\nheight = 1.0\n"
                  "[[water]]\nmin = [0, 0, 0]\nmax = [1, 1, 1]\n[[water]]\nmin = [0, 0, 0.51]\nmax = [1, 1, 0.54]\n"),
      {"[[water]] number 2", "along z"});
  // As thin, but holding a row of points (0.55 is (5 + 1/2) dx), or exactly dx across: accepted.
  EXPECT_NO_THROW(parse("[domain]\ndx = 0.1\n[[water]]\nmin = [0.54, 0]\nmax = [0.56, 1]\n"));
  EXPECT_NO_THROW(parse("[domain]\ndx = 0.1\n[[water]]\nmin = [0.5, 0]\nmax = [0.6, 1]\n"));
}

TEST(CaseValidation, MinNotBelowMax) {
  expect_contains(parse_error("[[water]]\nmin = [1, 0]\nmax = [0.5, 1]\n"),
                  {"[[water]] number 1", "min [1.0, 0.0] must be below max [0.5, 1.0]"});
  expect_contains(parse_error("[[water]]\nmin = [0, 1]\nmax = [1, 1]\n"), {"must be below max"});
  expect_contains(parse_error(minimal_water + "[[wall]]\nmin = [2, 2]\nmax = [1, 3]\n"),
                  {"[[wall]] number 1", "must be below max"});
}

TEST(CaseValidation, NoWater) {
  expect_contains(parse_error("[domain]\ndx = 0.1\n"), {"no [[water]] region"});
}

TEST(CaseValidation, EmptyFormats) {
  expect_contains(parse_error("[output]\nformats = []\n" + minimal_water), {"output.formats is empty"});
}

TEST(CaseValidation, Probes) {
  const std::string p = "[[probe]]\nname = \"a\"\ntype = \"pressure\"\npoint = [1, 1]\n";
  EXPECT_NO_THROW(parse(minimal_water + p));
  expect_contains(parse_error(minimal_water + p + p), {"[[probe]] name \"a\" is used twice"});
  expect_contains(parse_error(minimal_water + "[[probe]]\nname = \"a/b\"\ntype = \"gauge\"\npoint = [1, 1]\n"),
                  {"name \"a/b\" must be non-empty, without spaces or slashes"});
  expect_contains(parse_error(minimal_water + "[[probe]]\nname = \"f\"\ntype = \"front\"\npoint = [1, 1]\ndirection = [0, 0]\n"),
                  {"direction must not be [0.0, 0.0]"});
}

// A pressure probe or a gauge outside the tank finds no water and records zeros: refused, as water
// outside the tank is, for every type of probe (a front measures from its point).
TEST(CaseValidation, ProbesOutsideTheTank) {
  const std::string tank = "[tank]\nwidth = 2.0\nheight = 1.5\n" + minimal_water;
  expect_contains(parse_error(tank + "[[probe]]\nname = \"far\"\ntype = \"pressure\"\npoint = [5.0, 0.1]\n"),
                  {"test.toml: [[probe]] \"far\" (a pressure probe at [5.0, 0.1]) lies outside the tank [0, 2] x [0, 1.5]",
                   "x = 5 is not within [0, 2]", "expected a point inside the tank"});
  expect_contains(parse_error(tank + "[[probe]]\nname = \"g\"\ntype = \"gauge\"\npoint = [-0.5, 0.0]\n"),
                  {"[[probe]] \"g\" (a gauge on the vertical line through [-0.5, 0.0]) lies outside the tank",
                   "x = -0.5 is not within [0, 2]"});
  expect_contains(parse_error(tank + "[[probe]]\nname = \"g\"\ntype = \"gauge\"\npoint = [1.0, 1.6]\nmeasure = \"column\"\n"),
                  {"[[probe]] \"g\"", "y = 1.6 is not within [0, 1.5]"});
  expect_contains(parse_error(tank + "[[probe]]\nname = \"f\"\ntype = \"front\"\npoint = [0.0, -1.0]\n"),
                  {"[[probe]] \"f\" (a front probe measuring from [0.0, -1.0]) lies outside the tank"});
  const std::string tank_3d = "[domain]\ndimension = 3\n[tank]\nwidth = 2.0\ndepth = 1.0\nheight = 1.5\n"
                              "[[water]]\nmin = [0, 0, 0]\nmax = [0.5, 1.0, 0.6]\n";
  expect_contains(parse_error(tank_3d + "[[probe]]\nname = \"p\"\ntype = \"pressure\"\npoint = [1.0, 1.2, 0.5]\n"),
                  {"[[probe]] \"p\"", "lies outside the tank [0, 2] x [0, 1] x [0, 1.5]", "y = 1.2 is not within [0, 1]"});
  // On the walls (a wall pressure sensor, a gauge at the back wall) and in the corners: accepted.
  EXPECT_NO_THROW(parse(tank + "[[probe]]\nname = \"wall\"\ntype = \"pressure\"\npoint = [2.0, 0.1]\n"
                               "[[probe]]\nname = \"back\"\ntype = \"gauge\"\npoint = [0.0, 0.0]\n"
                               "[[probe]]\nname = \"corner\"\ntype = \"front\"\npoint = [2.0, 1.5]\n"));
  // A --set that moves a probe out, or shrinks the tank under one, is refused too.
  Case c = parse(tank + "[[probe]]\nname = \"p\"\ntype = \"pressure\"\npoint = [1.5, 0.1]\n");
  expect_contains(override_error(c, "probe[0].point=[2.5, 0.1]"), {"[[probe]] \"p\"", "lies outside the tank"});
  expect_contains(override_error(c, "tank.width=1.2"), {"[[probe]] \"p\"", "lies outside the tank [0, 1.2] x [0, 1.5]"});
}

// A probe that moves with a wall names one of the case's walls (by its name, or wallN when it has none).
// [tank.translation] and [tank.rotation] are read as a wall's laws are, with messages that name them as
// written; a moving tank is refused until the solver moves the tank's own walls.
// law = "wave": a piston's and a flap's keys read; a flap hinged above the water or of order 2, and an
// order other than 1 or 2, refused;
// [damping] read, and refused with no direction or a start outside the tank.
TEST(CaseValidation, APistonWaveMakerAndADampingZone) {
  const std::string flume = "[tank]\nwidth = 6.0\nheight = 0.8\n[[water]]\nmin = [0.12, 0.0]\nmax = [6.0, 0.4]\n";
  const std::string piston = "[[wall]]\nname = \"piston\"\nmin = [0.04, 0.0]\nmax = [0.12, 0.7]\n[wall.translation]\n"
                             "law = \"wave\"\ndirection = [1.0, 0.0]\nheight = 0.08\nperiod = 1.2\ndepth = 0.4\norder = 2\n";
  const Case c = parse(flume + piston + "[damping]\nstart = [4.5, 0.0]\nlength = 1.5\n");
  EXPECT_EQ(c.walls[0].translation.law, MotionLawType::wave);
  EXPECT_EQ(c.walls[0].translation.height, 0.08);
  EXPECT_EQ(c.walls[0].translation.depth, 0.4);
  EXPECT_EQ(c.walls[0].translation.order, 2);
  EXPECT_EQ(c.walls[0].translation.gain, 1.0);
  EXPECT_TRUE(c.damps());
  EXPECT_EQ(c.damping_strength, 10.0);
  const std::string flap = flume + "[[wall]]\nname = \"flap\"\nmin = [0.04, 0.0]\nmax = [0.12, 0.7]\n[wall.rotation]\n"
                                   "law = \"wave\"\nheight = 0.08\nperiod = 1.2\ndepth = 0.4\n";
  EXPECT_EQ(parse(flap + "centre = [0.08, 0.1]\n").walls[0].rotation.law, MotionLawType::wave);
  expect_contains(parse_error(flap + "centre = [0.08, 0.5]\n"),
                  {"wall[0].rotation.centre = [0.08, 0.5]: a flap's hinge 0.5 m above the floor is not in the water"});
  expect_contains(parse_error(flume + "[tank.translation]\nlaw = \"wave\"\ndirection = [1.0, 0.0]\nheight = 0.08\n"
                                      "period = 1.2\ndepth = 0.4\n"),
                  {"tank.translation.law = \"wave\": the tank cannot be a wave maker"});
  expect_contains(parse_error(flap + "centre = [0.08, 0.1]\norder = 2\n"),
                  {"wall[0].rotation.order = 2: second-order generation is for a piston"});
  expect_contains(parse_error(flume + piston + "gain = 1.0\n" + "[damping]\nlength = 1.0\nstart = [7.0, 0.0]\n"),
                  {"damping.start = [7.0, 0.0] lies outside the tank [0, 6] x [0, 0.8]"});
  expect_contains(parse_error(flume + "[damping]\nlength = 1.0\nstart = [5.0, 0.0]\ndirection = [0.0, 0.0]\n"),
                  {"damping.direction = [0.0, 0.0]: a vector of length 0"});
  Case three = c;
  expect_contains(override_error(three, "wall[0].translation.order=3"), {"wall[0].translation.order"});
}

// Active absorption: absorb = true on a piston and law = "absorber" read with their defaults (0: chosen
// from the wave) and round-tripped by the template; refused on a flap, on the tank, on a piston moving
// vertically, on a wall that also turns, and absorb beside another law.
TEST(CaseValidation, AbsorbingPistons) {
  const std::string flume = "[tank]\nwidth = 6.0\nheight = 0.8\n[[water]]\nmin = [0.12, 0.0]\nmax = [5.8, 0.4]\n";
  const std::string piston = "[[wall]]\nname = \"piston\"\nmin = [0.04, 0.0]\nmax = [0.12, 0.7]\n[wall.translation]\n"
                             "law = \"wave\"\ndirection = [1.0, 0.0]\nheight = 0.08\nperiod = 1.2\ndepth = 0.4\n";
  const std::string absorber = "[[wall]]\nname = \"end\"\nmin = [5.8, 0.0]\nmax = [5.88, 0.7]\n[wall.translation]\n"
                               "law = \"absorber\"\ndirection = [-1.0, 0.0]\ndepth = 0.4\n";
  const Case c = parse(flume + piston + "absorb = true\n" + absorber + "absorption_limit = 0.05\n");
  EXPECT_TRUE(c.walls[0].translation.absorb);
  EXPECT_EQ(c.walls[0].translation.absorption_time, 0.0);
  EXPECT_EQ(c.walls[1].translation.law, MotionLawType::absorber);
  EXPECT_EQ(c.walls[1].translation.absorption_limit, 0.05);
  const Case again = parse(case_template(c));
  EXPECT_TRUE(again.walls[0].translation.absorb);
  EXPECT_EQ(again.walls[1].translation.law, MotionLawType::absorber);
  EXPECT_EQ(again.walls[1].translation.absorption_limit, 0.05);
  const std::string flap = flume + "[[wall]]\nname = \"flap\"\nmin = [0.04, 0.0]\nmax = [0.12, 0.7]\n[wall.rotation]\n"
                                   "law = \"wave\"\nheight = 0.08\nperiod = 1.2\ndepth = 0.4\ncentre = [0.08, 0.1]\n";
  expect_contains(parse_error(flap + "absorb = true\n"),
                  {"wall[0].rotation.absorb = true: active absorption is for a piston"});
  expect_contains(parse_error(flume + "[tank.translation]\nlaw = \"absorber\"\ndirection = [1.0, 0.0]\ndepth = 0.4\n"),
                  {"tank.translation.law = \"absorber\": the tank cannot absorb waves"});
  expect_contains(parse_error(flume + "[[wall]]\nname = \"end\"\nmin = [5.8, 0.0]\nmax = [5.88, 0.7]\n[wall.translation]\n"
                                      "law = \"absorber\"\ndirection = [-1.0, 0.5]\ndepth = 0.4\n"),
                  {"wall[0].translation.direction = [-1.0, 0.5]: an absorbing piston moves horizontally"});
  expect_contains(parse_error(flume + absorber + "[wall.rotation]\nlaw = \"sinusoidal\"\ncentre = [5.84, 0.0]\n"
                                                 "amplitude = 1.0\nperiod = 2.0\n"),
                  {"wall[0] (\"end\") absorbs waves and turns"});
  expect_contains(parse_error(flume + "[[wall]]\nname = \"end\"\nmin = [5.8, 0.0]\nmax = [5.88, 0.7]\n[wall.translation]\n"
                                      "law = \"absorber\"\ndirection = [-1.0, 0.0]\n"),
                  {"[wall.translation] of [[wall]] number 1 has no 'depth'"});
  expect_contains(parse_error(flume + "[[wall]]\nmin = [5.8, 0.0]\nmax = [5.88, 0.7]\n[wall.translation]\n"
                                      "law = \"linear\"\ndirection = [-1.0, 0.0]\nspeed = 0.1\nend = 1.0\nabsorb = true\n"),
                  {"absorb"});
}

// spectrum = "jonswap": its keys read with their defaults (gamma 3.3, 200 components, seed 1) and
// round-tripped by the template; a regular wave's height and period refused beside it and its keys
// beside a regular wave; each bad value refused, naming the key, the value and what was expected:
// out of range, second order, no ramp, and a spectrum the particles cannot carry.
TEST(CaseValidation, AJonswapWaveMaker) {
  const std::string flume = "[domain]\ndx = 0.025\n[tank]\nwidth = 6.0\nheight = 0.8\n[[water]]\nmin = [0.12, 0.0]\n"
                            "max = [6.0, 0.4]\n";
  const std::string wall = "[[wall]]\nname = \"piston\"\nmin = [0.04, 0.0]\nmax = [0.12, 0.7]\n[wall.translation]\n"
                           "law = \"wave\"\ndirection = [1.0, 0.0]\ndepth = 0.4\nramp = 2\n";
  const std::string piston = flume + wall + "spectrum = \"jonswap\"\nsignificant_height = 0.05\npeak_period = 1.2\n";
  const Case c = parse(piston);
  const MotionLawSpec& m = c.walls[0].translation;
  EXPECT_EQ(m.spectrum, WaveSpectrum::jonswap);
  EXPECT_EQ(m.significant_height, 0.05);
  EXPECT_EQ(m.peak_period, 1.2);
  EXPECT_EQ(m.gamma, 3.3);
  EXPECT_EQ(m.components, 200);
  EXPECT_EQ(m.seed, 1);
  EXPECT_EQ(parse(flume + wall + "height = 0.08\nperiod = 1.2\n").walls[0].translation.spectrum, WaveSpectrum::regular);
  const Case chosen = parse(piston + "gamma = 1.0\ncomponents = 64\nseed = 12345\ngain = 0.9\n");
  EXPECT_EQ(chosen.walls[0].translation.gamma, 1.0);
  EXPECT_EQ(chosen.walls[0].translation.components, 64);
  EXPECT_EQ(chosen.walls[0].translation.seed, 12345);
  const std::string text = case_template(chosen);
  EXPECT_NE(text.find("spectrum = \"jonswap\""), std::string::npos) << text;
  EXPECT_EQ(text.find("\nheight = ", text.rfind("[wall.translation]")), std::string::npos) << text;
  expect_cases_equal(parse_case(text, "template"), chosen);

  // Both kinds of keys at once.
  expect_contains(parse_error(piston + "height = 0.08\n"),
                  {"gives 'height', which a wave law with spectrum = \"jonswap\" does not use"});
  expect_contains(parse_error(piston + "period = 1.2\n"),
                  {"gives 'period', which a wave law with spectrum = \"jonswap\" does not use"});
  expect_contains(parse_error(flume + wall + "height = 0.08\nperiod = 1.2\nsignificant_height = 0.05\n"),
                  {"gives 'significant_height', which a wave law with spectrum = \"regular\" does not use"});
  expect_contains(parse_error(flume + wall + "spectrum = \"jonswap\"\npeak_period = 1.2\n"),
                  {"has no 'significant_height'"});
  expect_contains(parse_error(flume + wall + "spectrum = \"jonswap\"\nsignificant_height = 0.05\n"),
                  {"has no 'peak_period'"});
  expect_contains(parse_error(flume + wall + "spectrum = \"pierson\"\nsignificant_height = 0.05\npeak_period = 1.2\n"),
                  {"spectrum", "pierson", "jonswap"});
  // Values out of range.
  expect_contains(parse_error(piston + "gamma = 0.5\n"), {"gamma = 0.5: out of range"});
  expect_contains(parse_error(piston + "gamma = 50\n"), {"gamma = 50: out of range"});
  expect_contains(parse_error(piston + "components = 0\n"), {"components = 0: out of range"});
  expect_contains(parse_error(piston + "components = 1000000\n"), {"components = 1000000: out of range"});
  expect_contains(parse_error(piston + "seed = -1\n"), {"seed = -1: out of range"});
  expect_contains(parse_error(flume + wall + "spectrum = \"jonswap\"\nsignificant_height = 0.0\npeak_period = 1.2\n"),
                  {"significant_height = 0.0: out of range"});
  expect_contains(parse_error(flume + wall + "spectrum = \"jonswap\"\nsignificant_height = 0.05\npeak_period = -1.0\n"),
                  {"peak_period = -1.0: out of range; expected a number >= 1e-06 (s)"});
  // Second order, no ramp.
  expect_contains(parse_error(piston + "order = 2\n"),
                  {"wall[0].translation.order = 2: second-order generation of irregular (JONSWAP) waves is not "
                   "implemented; expected order = 1"});
  const std::string unramped = flume + "[[wall]]\nname = \"piston\"\nmin = [0.04, 0.0]\nmax = [0.12, 0.7]\n"
                               "[wall.translation]\nlaw = \"wave\"\ndirection = [1.0, 0.0]\ndepth = 0.4\n"
                               "spectrum = \"jonswap\"\nsignificant_height = 0.05\npeak_period = 1.2\n";
  expect_contains(parse_error(unramped), {"wall[0].translation.ramp = 0 peak periods", "expected a ramp of at least 1 "
                                                                                         "peak period"});
  EXPECT_NO_THROW(parse(unramped + "ramp = 1\n"));
  // A peak period of 0.25 s (Lp = 0.098 m) on dx = 0.025 m (4h = 0.2 m): almost nothing the particles
  // can carry; at dx = 0.005 m (4h = 0.04 m) it is made.
  expect_contains(parse_error(flume + wall + "spectrum = \"jonswap\"\nsignificant_height = 0.01\npeak_period = 0.25\n"),
                  {"wall[0].translation: the JONSWAP spectrum (significant_height = 0.01 m, peak_period = 0.25 s) has "
                   "little energy in the flume's range: 0.3 % of it at wavelengths of at least 4h = 0.2 m",
                   "peak wavelength 0.09758 m", "expected at least half of it there"});
  Case fine = c;
  apply_override(fine, "domain.dx=0.005");
  EXPECT_NO_THROW(apply_override(fine, "wall[0].translation.peak_period=0.25"));
  Case coarse = c;
  expect_contains(override_error(coarse, "wall[0].translation.peak_period=0.25"), {"little energy in the flume's range"});
  expect_contains(override_error(coarse, "wall[0].translation.ramp=0.5"), {"wall[0].translation.ramp = 0.5 peak periods"});
  // A flap: its hinge checked as a regular flap's, and the same refusal of second order.
  const std::string flap = flume + "[[wall]]\nname = \"flap\"\nmin = [0.04, 0.0]\nmax = [0.12, 0.7]\n[wall.rotation]\n"
                                   "law = \"wave\"\ndepth = 0.4\nramp = 2\nspectrum = \"jonswap\"\n"
                                   "significant_height = 0.05\npeak_period = 1.2\n";
  EXPECT_EQ(parse(flap + "centre = [0.12, 0.1]\n").walls[0].rotation.spectrum, WaveSpectrum::jonswap);
  expect_contains(parse_error(flap + "centre = [0.12, 0.5]\n"), {"a flap's hinge 0.5 m above the floor is not in the water"});
  expect_contains(parse_error(flap + "centre = [0.12, 0.1]\norder = 2\n"),
                  {"wall[0].rotation.order = 2: second-order generation of irregular (JONSWAP) waves"});
}

TEST(CaseValidation, TheTanksMotionTables) {
  const std::string tank = "[tank]\nwidth = 1.0\nheight = 1.0\n" + minimal_water;
  const std::string roll = "[tank.rotation]\nlaw = \"sinusoidal\"\ncentre = [0.5, 0.0]\namplitude = 2.0\nperiod = 1.5\n";
  const Case rolled = parse(tank + roll);
  EXPECT_TRUE(rolled.tank_moves());
  EXPECT_EQ(rolled.tank_rotation.law, MotionLawType::sinusoidal);
  EXPECT_EQ(rolled.tank_rotation.period, 1.5);
  EXPECT_EQ(rolled.tank_translation.law, MotionLawType::none);
  const std::string baffle = "[[wall]]\nname = \"baffle\"\nmin = [0.4, 0.0]\nmax = [0.45, 0.3]\n";
  expect_contains(parse_error(tank + roll + baffle),
                  {"wall[0] (\"baffle\") is fixed while the tank moves", "the tank's [tank.translation] / [tank.rotation]"});
  (void)parse(tank + roll + baffle + "[wall.rotation]\nlaw = \"sinusoidal\"\ncentre = [0.5, 0.0]\namplitude = 2.0\nperiod = 1.5\n");
  expect_contains(parse_error(tank + "[[wall]]\nname = \"tank\"\nmin = [0.4, 0.0]\nmax = [0.45, 0.3]\n"),
                  {"wall[0].name = \"tank\": that name belongs to the tank's own walls"});
  const std::string probe = "[[probe]]\nname = \"p\"\ntype = \"pressure\"\npoint = [0.0, 0.02]\nwall = \"tank\"\n";
  EXPECT_EQ(parse(tank + roll + probe).probes[0].wall, "tank");
  expect_contains(parse_error(tank + probe), {"wall = \"tank\" moves the probe with the tank's own walls",
                                              "this case's tank does not move"});
  expect_contains(parse_error(tank + "[tank.rotation]\nlaw = \"sinusoidal\"\nperiodd = 1.5\n"),
                  {"unknown key 'periodd' in [tank.rotation]; did you mean 'period'?"});
  expect_contains(parse_error(tank + "[tank.translation]\nlaw = \"linear\"\ndirection = [1.0, 0.0]\nspeed = \"fast\"\n"),
                  {"tank.translation.speed"});
  expect_contains(parse_error("[tank]\nwidth = 1.0\nrotation = 3\n" + minimal_water),
                  {"tank.rotation must be a table, [tank.rotation]"});
  Case c = parse(tank);
  expect_contains(override_error(c, "tank.rotation.amplitud=2"),
                  {"unknown key 'amplitud' in [tank.rotation]; did you mean 'tank.rotation.amplitude'?"});
  expect_contains(override_error(c, "tank.rotation.law=sinusoidal"), {"tank.rotation.period"});
  apply_overrides(c, {"tank.translation.law=linear", "tank.translation.direction=[1.0, 0.0]", "tank.translation.speed=0.1",
                      "tank.translation.end=1.0"});
  EXPECT_TRUE(c.tank_moves());
  EXPECT_EQ(c.tank_translation.speed, 0.1);
}

// release.gate: the first water region's +x face gets a plate 4 dx thick across the tank, from the
// floor to 4 dx above the water, lifted at gate_speed until its foot is dx above the water.
TEST(ReleaseGate, HoldsTheFirstWaterRegionBehindAPlateLiftedAtItsSpeed) {
  const std::string tank = "[domain]\ndx = 0.01\n[tank]\nwidth = 1.0\nheight = 0.8\n"
                           "[[water]]\nmin = [0.0, 0.0]\nmax = [0.2, 0.4]\n";
  const Case at_once = parse(tank);
  EXPECT_TRUE(with_release_gate(at_once).walls.empty());
  const Case c = parse(tank + "[release]\ngate = true\ngate_speed = 2.0\n");
  const Case expanded = with_release_gate(c);
  ASSERT_EQ(expanded.walls.size(), 1u);
  EXPECT_FALSE(expanded.release_gate);  // expanded once: a checkpoint's case is not expanded again
  EXPECT_EQ(with_release_gate(expanded).walls.size(), 1u);
  const Region& gate = expanded.walls[0];
  EXPECT_EQ(gate.name, "gate");
  EXPECT_EQ(gate.shape, Shape::box);
  EXPECT_DOUBLE_EQ(gate.min[0], 0.2);
  EXPECT_DOUBLE_EQ(gate.max[0], 0.24);
  EXPECT_DOUBLE_EQ(gate.min[1], 0.0);
  EXPECT_DOUBLE_EQ(gate.max[1], 0.44);
  EXPECT_EQ(gate.translation.law, MotionLawType::linear);
  EXPECT_EQ(gate.translation.direction, (Vec3{0.0, 1.0, 0.0}));
  EXPECT_DOUBLE_EQ(gate.translation.speed, 2.0);
  EXPECT_DOUBLE_EQ(gate.translation.end, 0.41 / 2.0);
  // In 3D the plate spans the tank's depth and rises along z.
  const Case c3 = parse("[domain]\ndimension = 3\ndx = 0.02\n[tank]\nwidth = 1.0\ndepth = 0.5\nheight = 0.8\n"
                        "[physics]\ngravity = [0.0, 0.0, -9.81]\n"
                        "[[water]]\nmin = [0.0, 0.0, 0.0]\nmax = [0.3, 0.5, 0.4]\n[release]\ngate = true\n");
  const Region gate3 = with_release_gate(c3).walls.at(0);
  EXPECT_EQ(gate3.min, (Vec3{0.3, 0.0, 0.0}));
  EXPECT_DOUBLE_EQ(gate3.max[1], 0.5);
  EXPECT_DOUBLE_EQ(gate3.max[2], 0.48);
  EXPECT_EQ(gate3.translation.direction, (Vec3{0.0, 0.0, 1.0}));
  // What it cannot hold: a first water region that is not a box; a wall named gate already.
  const Case polygon = parse("[release]\ngate = true\n[[water]]\nshape = \"polygon\"\n"
                             "points = [[0.0, 0.0], [0.2, 0.0], [0.0, 0.3]]\n");
  try {
    (void)with_release_gate(polygon);
    FAIL() << "a polygon of water behind a gate was accepted";
  } catch (const CaseError& e) {
    EXPECT_NE(std::string(e.what()).find("expected a first [[water]] region with shape = \"box\", found shape = "
                                         "\"polygon\""),
              std::string::npos)
        << e.what();
  }
  const Case named = parse(tank + "[release]\ngate = true\n[[wall]]\nname = \"gate\"\nmin = [0.6, 0.0]\nmax = [0.7, 0.1]\n");
  EXPECT_THROW((void)with_release_gate(named), CaseError);
}

TEST(CaseValidation, AProbesWallIsOneOfTheCasesWalls) {
  const std::string walls = minimal_water + "[[wall]]\nname = \"gate\"\nmin = [1.0, 0.0]\nmax = [1.1, 0.5]\n"
                                            "[[wall]]\nmin = [1.5, 0.0]\nmax = [1.6, 0.2]\n";
  const std::string probe = "[[probe]]\nname = \"p\"\ntype = \"pressure\"\npoint = [1.0, 0.1]\n";
  EXPECT_EQ(parse(walls + probe + "wall = \"gate\"\n").probes[0].wall, "gate");
  EXPECT_NO_THROW(parse(walls + probe + "wall = \"wall2\"\n"));
  expect_contains(parse_error(walls + probe + "wall = \"door\"\n"),
                  {"[[probe]] \"p\": wall = \"door\" names no [[wall]] of the case; expected one of \"gate\", \"wall2\""});
  expect_contains(parse_error(minimal_water + probe + "wall = \"gate\"\n"),
                  {"wall = \"gate\" names no [[wall]] of the case; expected no wall key (the case has no [[wall]])"});
}

TEST(CaseValidation, CaseNameIsAUsableFolderName) {
  for (const char* bad : {"\"\"", "\".\"", "\"..\"", "\"a/b\"", "\"a\\\\b\"", "\"a\\nb\""})
    expect_contains(parse_error(fmt::format("[case]\nname = {}\n", bad) + minimal_water),
                    {"case.name", "not a usable name"});
  EXPECT_EQ(parse("[case]\nname = \"tank 2 (fine)\"\n" + minimal_water).name, "tank 2 (fine)");
}

// The name is a file name (<name>.pvd, written through <name>.pvd.tmp<process id>): at most 240 bytes,
// counted in bytes, not characters.
TEST(CaseValidation, CaseNameFitsInAFileName) {
  EXPECT_NO_THROW(parse("[case]\nname = \"" + std::string(240, 'a') + "\"\n" + minimal_water));
  expect_contains(parse_error("[case]\nname = \"" + std::string(241, 'a') + "\"\n" + minimal_water),
                  {"test.toml: case.name = \"" + std::string(40, 'a') + "\"...: too long, 241 bytes; expected at most 240 "
                   "bytes", "<name>.pvd.tmp<process id>", "a file name holds at most 255 bytes"});
  // 122 characters, 243 bytes: the start shown stops before the character that byte 40 is part of.
  std::string accented = "a";
  for (int k = 0; k < 121; ++k) accented += "\u00e9";
  expect_contains(parse_error("[case]\nname = \"" + accented + "\"\n" + minimal_water),
                  {"case.name = \"" + accented.substr(0, 39) + "\"...: too long, 243 bytes"});
  Case c = parse(minimal_water);
  expect_contains(override_error(c, "case.name=" + std::string(300, 'x')), {"case.name", "too long, 300 bytes"});
}

TEST(CaseValidation, TankAndResolution) {
  expect_contains(parse_error("[domain]\ndx = 5\n[tank]\nwidth = 8\nheight = 8\n[[water]]\nmin = [0, 0]\nmax = [1, 1]\n"),
                  {"smaller than two particle spacings"});
  expect_contains(parse_error("[domain]\ndx = 0.0001\n[tank]\nwidth = 1000\nheight = 1000\n" + minimal_water),
                  {"domain.dx = 0.0001", "lattice points"});
}

// The wall function adds friction to walls that have none of their own, and needs water's viscosity.
TEST(CaseValidation, WallFrictionNeedsFrictionlessWallsAndAViscosity) {
  const std::string log_law = "[physics]\nwall_friction = \"log_law\"\n";
  expect_contains(parse_error(log_law + "wall_boundary = \"dynamic\"\n" + minimal_water),
                  {"physics.wall_friction = \"log_law\" with physics.wall_boundary = \"dynamic\"",
                   "hold moving water about 1.5 dx off the wall", "expected physics.wall_boundary = \"mdbc\""});
  expect_contains(parse_error(log_law + "wall_boundary = \"mdbc\"\nwall_slip = \"no_slip\"\n" + minimal_water),
                  {"physics.wall_slip = \"no_slip\"", "a friction of their own"});
  expect_contains(parse_error(log_law + "wall_boundary = \"adami\"\n[fluid]\nviscosity = 0.0\n" + minimal_water),
                  {"fluid.viscosity is 0", "water: 0.001 Pa s"});
  EXPECT_EQ(parse(log_law + "wall_boundary = \"mdbc\"\n" + minimal_water).wall_friction, WallFriction::log_law);
  EXPECT_EQ(parse(log_law + "wall_boundary = \"adami\"\n" + minimal_water).wall_friction, WallFriction::log_law);
  // "auto", the default: the wall function on mdbc free-slip walls in 2D, none on walls it does not suit
  // (and a case that chooses those walls is not refused for the default).
  EXPECT_EQ(parse(minimal_water).wall_friction, WallFriction::automatic);
  EXPECT_EQ(wall_friction_in_effect(parse(minimal_water)), WallFriction::log_law);
  for (const std::string walls : {"wall_boundary = \"dynamic\"\n", "wall_boundary = \"adami\"\n",
                                  "wall_slip = \"no_slip\"\n", "[fluid]\nviscosity = 0.0\n"})
    EXPECT_EQ(wall_friction_in_effect(parse("[physics]\n" + walls + minimal_water)), WallFriction::none) << walls;
  EXPECT_EQ(wall_friction_in_effect(parse("[physics]\nwall_friction = \"none\"\n" + minimal_water)), WallFriction::none);
}

// ---------------------------------------------------------------------------------------------
// Built-in cases and the template

TEST(CaseBuiltins, DamBreakIsBuiltIn) {
  const auto c = load_builtin_case("dam_break");
  ASSERT_TRUE(c.has_value());
  EXPECT_EQ(c->name, "dam_break");
  EXPECT_FALSE(c->description.empty());
  EXPECT_EQ(c->water.size(), 2u);
  EXPECT_FALSE(load_builtin_case("no_such_case").has_value());
}

// The integrators the built-in cases run (docs/physics.md, "Time integration"): the default case and spheric2
// the leapfrog, one force evaluation per step; the validation cases the predictor-corrector, the
// default of a case file that does not say.
TEST(CaseBuiltins, TheDefaultCaseRunsTheLeapfrog) {
  EXPECT_EQ(load_builtin_case("dam_break")->integrator, Integrator::leapfrog);
  EXPECT_EQ(load_builtin_case("spheric2")->integrator, Integrator::leapfrog);
  for (const char* name : {"martin_moyce", "koshizuka_oka", "buchner"})
    EXPECT_EQ(load_builtin_case(name)->integrator, Integrator::predictor_corrector) << name;
}

TEST(CaseBuiltins, EveryBuiltInCaseLoadsAndIsNamedAfterItsFile) {
  ASSERT_FALSE(builtin_cases().empty());
  for (const auto& b : builtin_cases()) {
    SCOPED_TRACE(b.name);
    std::optional<Case> c;
    ASSERT_NO_THROW(c = load_builtin_case(b.name));
    ASSERT_TRUE(c.has_value());
    EXPECT_EQ(c->name, b.name);
    EXPECT_FALSE(c->description.empty());
  }
}

TEST(CaseTemplate, RoundTripsEveryBuiltInCase) {
  for (const auto& b : builtin_cases()) {
    SCOPED_TRACE(b.name);
    const Case c = *load_builtin_case(b.name);
    Case back;
    ASSERT_NO_THROW(back = parse_case(case_template(c), "template of " + b.name)) << case_template(c);
    expect_cases_equal(back, c);
    EXPECT_EQ(case_template(back), case_template(c));
  }
}

TEST(CaseTemplate, RoundTripsWallsProbesAndOddValues) {
  const Case c = unusual_case();
  ASSERT_EQ(c.walls.size(), 1u);
  ASSERT_EQ(c.probes.size(), 3u);
  EXPECT_NE(c.description.find('\n'), std::string::npos);
  Case back;
  ASSERT_NO_THROW(back = parse_case(case_template(c), "template")) << case_template(c);
  expect_cases_equal(back, c);
}

TEST(CaseTemplate, RoundTripsAfterOverrides) {
  Case c = *load_builtin_case("dam_break");
  apply_overrides(c, {"domain.dx=0.123456789", "case.description=tab\there", "water[1].max=[2.5, 4.75]",
                      "output.formats=npz", "physics.gravity=[1e-7, -9.81]"});
  expect_cases_equal(parse_case(case_template(c), "template"), c);
}

TEST(CaseTemplate, DocumentsEveryKey) {
  const Case c = *load_builtin_case("dam_break");
  const std::string t = case_template(c);
  std::vector<std::string> lines;
  {
    std::istringstream in(t);
    for (std::string line; std::getline(in, line);) lines.push_back(line);
  }
  auto find_line = [&](const std::string& text, std::size_t from = 0) -> std::size_t {
    for (std::size_t i = from; i < lines.size(); ++i)
      if (lines[i] == text) return i;
    return lines.size();
  };
  for (const auto& p : case_params()) {
    SCOPED_TRACE(p.key);
    if (p.only_3d) continue;  // a 2D case's template leaves out the keys of 3D cases
    const auto dot = p.key.find('.');
    const std::size_t header = find_line("[" + p.key.substr(0, dot) + "]");
    ASSERT_LT(header, lines.size()) << "no section header";
    // The key's line, within its section.
    std::size_t at = lines.size();
    for (std::size_t i = header + 1; i < lines.size() && (lines[i].empty() || lines[i][0] != '['); ++i)
      if (lines[i].rfind(p.key.substr(dot + 1) + " = ", 0) == 0) at = i;
    ASSERT_LT(at, lines.size()) << "key not written";
    ASSERT_GE(at, header + 3);
    // Two comment lines above it: the description, then unit | default | allowed.
    EXPECT_EQ(lines[at - 2], "# " + p.description);
    const std::string& facts = lines[at - 1];
    if (!p.unit.empty()) expect_contains(facts, {"unit: " + p.unit});
    else EXPECT_EQ(facts.find("unit:"), std::string::npos) << facts;
    expect_contains(facts, {"default: ", "allowed: "});
    if (p.lower <= p.upper) {
      // Integers with a huge upper bound, and numbers with an unbounded one, are written as ">= lower".
      const bool is_int = std::holds_alternative<int Case::*>(p.field);
      const bool open_above = is_int ? p.upper >= 1e8 : p.upper >= 1e299;
      const std::string range = open_above ? fmt::format(">= {}", p.lower) : fmt::format("from {} to {}", p.lower, p.upper);
      expect_contains(facts, {range});
    }
    for (const auto& choice : p.choices) expect_contains(facts, {"\"" + choice + "\""});
    // The documented default is the declared one: write it into a case of its own and read it back.
    const auto d = facts.find("default: ");
    const std::string default_text = facts.substr(d + 9, facts.find(" | ", d) - d - 9);
    const Case with_default =
        parse_case(fmt::format("[{}]\n{} = {}\n", p.key.substr(0, dot), p.key.substr(dot + 1), default_text) + minimal_water,
                   "default of " + p.key);
    EXPECT_EQ(value_of(with_default, p), p.default_value) << default_text;
  }
  // Keys of array items are documented in comments, whether or not the case has such items.
  for (const auto& [section, params] : {std::pair{"water", &region_params()}, std::pair{"wall", &region_params()}}) {
    const std::size_t block = find_line(fmt::format("# Keys of each [[{}]]:", section));
    ASSERT_LT(block, lines.size()) << section;
    for (const auto& p : *params) expect_contains(t.substr(t.find(lines[block])), {"#   " + p.key + ":"});
  }
  const std::size_t probe_block = find_line("# Keys of each [[probe]]:");
  ASSERT_LT(probe_block, lines.size());
  for (const auto& p : probe_params()) {
    const std::size_t at = find_line("#   " + p.key + ":", probe_block);
    ASSERT_LT(at + 2, lines.size()) << p.key;
    EXPECT_EQ(lines[at + 1], "#     # " + p.description);
    expect_contains(lines[at + 2], {"allowed: "});
    if (std::holds_alternative<std::monostate>(p.default_value)) expect_contains(lines[at + 2], {"required"});
    if (!p.unit.empty()) expect_contains(lines[at + 2], {"unit: " + p.unit});
  }
  expect_contains(t, {"(this case has no [[probe]] entries)", "(this case has no [[wall]] entries)"});
  // Every section's description is there.
  for (const auto& s : case_sections()) expect_contains(t, {"# " + s.description});
}

TEST(CaseTemplate, ConcreteLinesForOneKey) {
  // One key's documentation spelled out in full, as `sluice init` writes it.
  const std::string t = case_template(*load_builtin_case("dam_break"));
  expect_contains(t, {"[domain]\n# Space dimensions: 2 (x, y; y up) or 3 (x, y, z; z up)."});
  expect_contains(t, {"dimension = 2\n# Particle spacing (dx); particle mass is rho0 * dx^2 (dx^3 in 3D).\n"
                      "# unit: m | default: 0.2 | allowed: a number from 0.0001 to 100 (m)\ndx = 0.2\n"});
  expect_contains(t, {"[[water]]\nshape = \"box\"\nmin = [0.0, 2.0]\nmax = [3.0, 5.0]\n"});
}

// ---------------------------------------------------------------------------------------------
// Suggestions

TEST(ClosestMatch, FindsLikelyTypos) {
  const std::vector<std::string> sections = {"case", "domain", "tank", "fluid", "physics", "time", "output", "water"};
  EXPECT_EQ(closest_match("domian", sections), "domain");
  EXPECT_EQ(closest_match("watr", sections), "water");
  EXPECT_EQ(closest_match("ouput", sections), "output");
  EXPECT_FALSE(closest_match("zzzzzzzz", sections).has_value());
  EXPECT_FALSE(closest_match("", std::vector<std::string>{}).has_value());
  const std::vector<std::string> keys = {"domain.dx", "domain.h_over_dx", "time.end"};
  EXPECT_EQ(closest_match("domain.ddx", keys), "domain.dx");
  EXPECT_EQ(closest_match("ddx", keys), "domain.dx");  // the last part of a key counts
  EXPECT_EQ(closest_match("h_over_d", keys), "domain.h_over_dx");
}

TEST(CaseRegions, PolygonsParseAndShapeKeysAreCheckedBothWays) {
  const Case c = parse(minimal_water + "[[wall]]\nshape = \"polygon\"\npoints = [[12, 0], [20, 0], [20, 4]]\n");
  ASSERT_EQ(c.walls.size(), 1u);
  EXPECT_EQ(c.walls[0].shape, Shape::polygon);
  ASSERT_EQ(c.walls[0].points.size(), 3u);
  EXPECT_EQ(c.walls[0].points[2], (Vec2{20.0, 4.0}));
  expect_contains(parse_error(minimal_water + "[[wall]]\nshape = \"polygon\"\n"), {"has no 'points'"});
  expect_contains(parse_error(minimal_water + "[[wall]]\nshape = \"polygon\"\npoints = [[0, 0], [1, 1]]\nmin = [0, 0]\n"),
                  {"gives 'min', which a polygon does not use"});
  expect_contains(parse_error(minimal_water + "[[wall]]\nshape = \"polygon\"\npoints = [[0, 0], [1, 1]]\n"),
                  {"at least 3 points"});
  expect_contains(parse_error(minimal_water + "[[wall]]\nshape = \"polygon\"\npoints = [[0, 0], [1, 1], [2, 2]]\n"),
                  {"enclose no area"});
  expect_contains(parse_error(minimal_water + "[[wall]]\nshape = \"polygon\"\npoints = [[0, 0], [1], [2, 2]]\n"),
                  {"wall[0].points", "an array of points"});
  expect_contains(parse_error(minimal_water + "[[wall]]\nmin = [0, 0]\nmax = [1, 1]\npoints = [[0, 0], [1, 0], [1, 1]]\n"),
                  {"gives 'points', which a box does not use"});
}

// A polygon whose edges cross or touch has no single inside: the set-up would fill and wall it
// wrongly. So is a repeated point (an edge of no length, or the polygon touching itself).
TEST(CaseRegions, PolygonsMustBeSimple) {
  const auto polygon = [](const std::string& section, const std::string& points) {
    return parse_error(minimal_water + "[[" + section + "]]\nshape = \"polygon\"\npoints = " + points + "\n");
  };
  expect_contains(polygon("wall", "[[0, 0], [1, 0], [0, 1], [1, 1]]"),
                  {"test.toml: [[wall]] number 1: the polygon crosses itself: edge 2 (from (1, 0) to (0, 1)) crosses "
                   "edge 4 (from (1, 1) to (0, 0))",
                   "expected a simple polygon, whose edges meet only at the corners they share"});
  expect_contains(polygon("water", "[[0, 0], [1, 0], [0, 1], [1, 1]]"), {"[[water]] number 2: the polygon crosses itself"});
  // A corner on another edge, and an edge that turns back along the one before it.
  expect_contains(polygon("wall", "[[0, 0], [4, 0], [4, 2], [2, 0], [0, 2]]"),
                  {"the polygon touches itself: edge 1 (from (0, 0) to (4, 0)) touches edge 3 (from (4, 2) to (2, 0))"});
  expect_contains(polygon("wall", "[[0, 0], [2, 0], [2, 2], [2, 1], [0, 2]]"),
                  {"the polygon touches itself: edge 2 (from (2, 0) to (2, 2)) touches edge 4 (from (2, 1) to (0, 2))"});
  expect_contains(polygon("wall", "[[0.1, 0.1], [0.7, 0.3], [0.4, 0.2], [0.3, 0.9]]"), {"the polygon touches itself"});
  // Repeated points: the first again at the end, two in a row, and one that comes back later.
  expect_contains(polygon("wall", "[[0, 0], [1, 0], [1, 1], [0, 0]]"),
                  {"[[wall]] number 1: points 1 and 4 are the same point (0, 0), so that edge 4 has no length",
                   "the first point is not repeated at the end"});
  expect_contains(polygon("wall", "[[0, 0], [1, 0], [1, 0], [1, 1]]"),
                  {"points 2 and 3 are the same point (1, 0), so that edge 2 has no length"});
  expect_contains(polygon("wall", "[[0, 0], [2, 0], [1, 1], [2, 2], [0, 2], [1, 1]]"),
                  {"points 3 and 6 are the same point (1, 1): the polygon touches itself there"});
  // Convex and concave polygons, and a thin one, are simple.
  EXPECT_NO_THROW(parse(minimal_water + "[[wall]]\nshape = \"polygon\"\npoints = [[12, 0], [20, 0], [20, 4]]\n"));
  EXPECT_NO_THROW(parse(minimal_water + "[[wall]]\nshape = \"polygon\"\npoints = [[0, 0], [4, 0], [4, 2], [2, 1], [0, 2]]\n"));
  EXPECT_NO_THROW(parse(minimal_water + "[[wall]]\nshape = \"polygon\"\npoints = [[0, 0], [10, 0], [10, 1e-6], [0, 1e-6]]\n"));
}

// Every pair of edges is checked: a polygon of a few thousand points (a finely drawn circle) still
// loads at once.
TEST(CaseRegions, ALargeSimplePolygonChecksQuickly) {
  const int n = 5000;
  std::string points;
  for (int k = 0; k < n; ++k) {
    const double angle = 2.0 * 3.141592653589793 * k / n;
    points += fmt::format("{}[{}, {}]", k == 0 ? "" : ", ", 5.0 + 2.0 * std::cos(angle), 5.0 + 2.0 * std::sin(angle));
  }
  const std::string text = minimal_water + "[[wall]]\nshape = \"polygon\"\npoints = [" + points + "]\n";
  const auto start = std::chrono::steady_clock::now();
  EXPECT_NO_THROW(parse(text));
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_LT(seconds, 1.0);
  // The same circle with two of its points swapped crosses itself.
  std::string swapped = text;
  const std::string a = fmt::format("[{}, {}]", 5.0 + 2.0 * std::cos(2.0 * 3.141592653589793 * 100 / n),
                                    5.0 + 2.0 * std::sin(2.0 * 3.141592653589793 * 100 / n));
  const std::string b = fmt::format("[{}, {}]", 5.0 + 2.0 * std::cos(2.0 * 3.141592653589793 * 101 / n),
                                    5.0 + 2.0 * std::sin(2.0 * 3.141592653589793 * 101 / n));
  const auto at_a = swapped.find(a), at_b = swapped.find(b);
  ASSERT_NE(at_a, std::string::npos);
  ASSERT_NE(at_b, std::string::npos);
  swapped.replace(at_b, b.size(), a);
  swapped.replace(at_a, a.size(), b);
  expect_contains(parse_error(swapped), {"the polygon crosses itself: edge 100 ", "crosses edge 102 "});
}

// What messages show of a case file's text: keys, sections and names with their control characters
// escaped, so that none reaches the terminal.
TEST(CaseText, KeysSectionsAndNamesFromTheFileAreShownEscaped) {
  const std::string unknown_key = parse_error("[domain]\n\"d\\u001b[31mx\" = 1\n" + minimal_water);
  expect_contains(unknown_key, {R"(unknown key 'domain.d\u001B[31mx')"});
  expect_contains(parse_error("[\"dom\\u001bain\"]\ndx = 0.1\n" + minimal_water), {R"(unknown section 'dom\u001Bain')"});
  expect_contains(parse_error("\"\\u009b2J\" = 1\n" + minimal_water), {R"(key '\u009B2J' is outside any section)"});
  expect_contains(parse_error(minimal_water + "[[probe]]\nname = \"p\"\ntype = \"gauge\"\npoint = [1, 1]\n\"b\\u001b\" = 1\n"),
                  {R"(unknown key 'b\u001B' in [[probe]])"});
  const std::string p = "[[probe]]\nname = \"a\\u001b[31m\"\ntype = \"pressure\"\npoint = [1, 1]\n";
  expect_contains(parse_error(minimal_water + p + p), {R"([[probe]] name "a\u001B[31m" is used twice)"});
  for (const std::string& message : {unknown_key, parse_error(minimal_water + p + p)})
    for (const char c : message) EXPECT_NE(c, '\x1b') << message;
}

// quote() writes a TOML string, printable() text to be shown: both escape the characters a terminal
// may take as commands and the bytes that are not UTF-8, and leave other text as it is.
TEST(CaseText, QuoteAndPrintableEscapeControlCharactersAndBytesThatAreNotUtf8) {
  EXPECT_EQ(printable("plain \u00e9t\u00e9 \u6c34 \U0001F30A \"q\" \\"), "plain \u00e9t\u00e9 \u6c34 \U0001F30A \"q\" \\");
  EXPECT_EQ(printable("a\nb\tc\rd\x1b[0m\x7f"), R"(a\nb\tc\rd\u001B[0m\u007F)");
  EXPECT_EQ(printable("\xc2\x9b" "31m \xc2\xa0"), "\\u009B31m \u00a0");  // C1 CSI escaped, a no-break space kept
  // A stray continuation byte, a truncated sequence, an overlong '/', a surrogate, past U+10FFFF.
  EXPECT_EQ(printable("\x80 \xe6\xb0 \xc0\xaf \xed\xa0\x80 \xf4\x90\x80\x80"),
            R"(\x80 \xE6\xB0 \xC0\xAF \xED\xA0\x80 \xF4\x90\x80\x80)");
  EXPECT_EQ(quote("a\"b\\c\x1b\xff"), R"("a\"b\\c\u001B\xFF")");
  EXPECT_TRUE(is_utf8("\u00e9t\u00e9 \U0001F30A"));
  EXPECT_FALSE(is_utf8("caf\xe9"));
  // A C1 control in a case string reads back from the template unchanged.
  Case c = parse(minimal_water);
  c.description = "odd \u0085 line";
  EXPECT_EQ(parse_case(case_template(c), "template").description, c.description);
}

// ---------------------------------------------------------------------------------------------
// Dimension

const std::string minimal_3d = "[domain]\ndimension = 3\n[tank]\nwidth = 2.0\ndepth = 1.0\nheight = 1.5\n"
                               "[[water]]\nmin = [0, 0, 0]\nmax = [0.5, 1.0, 0.6]\n";

TEST(CaseDimension, ThreeDimensionalCaseReadsThreeComponentVectorsAndZUp) {
  const Case c = parse(minimal_3d);
  EXPECT_EQ(c.dimension, 3);
  EXPECT_EQ(c.tank_depth, 1.0);
  EXPECT_EQ(c.tank_size(), (Vec3{2.0, 1.0, 1.5}));
  EXPECT_EQ(c.gravity, (Vec3{0.0, 0.0, -9.81}));  // z is up in 3D
  EXPECT_EQ(c.water[0].max, (Vec3{0.5, 1.0, 0.6}));
  EXPECT_EQ(parse(minimal_water).gravity, (Vec3{0.0, -9.81, 0.0}));  // y is up in 2D
}

TEST(CaseDimension, VectorsMustHaveTheCaseDimension) {
  expect_contains(parse_error("[domain]\ndimension = 3\n[tank]\ndepth = 1.0\n[[water]]\nmin = [0, 0]\nmax = [1, 1]\n"),
                  {"water[0].max = [1, 1]", "wrong type (2 components in a 3D case, domain.dimension = 3)",
                   "expected an array of three numbers [x, y, z] (m)"});
  // The numbers as written, not in toml++'s round-trip form (0.69999999999999996).
  expect_contains(parse_error("[domain]\ndimension = 3\n[tank]\ndepth = 1.0\n[[water]]\nmin = [0, 0]\nmax = [0.7, 2.0]\n"),
                  {"water[0].max = [0.7, 2.0]: wrong type"});
  expect_contains(parse_error("[physics]\ngravity = [0, 0, -9.81]\n" + minimal_water),
                  {"physics.gravity", "3 components in a 2D case", "an array of two numbers [x, y]"});
}

TEST(CaseDimension, ThreeDimensionalKeysAreRefusedInTwoDimensions) {
  expect_contains(parse_error("[tank]\ndepth = 2.0\n" + minimal_water),
                  {"test.toml:2:9", "tank.depth = 2.0", "a key of 3D cases", "domain.dimension = 2"});
  expect_contains(parse_error("[domain]\ndimension = 4\n" + minimal_water), {"domain.dimension = 4", "out of range"});
  Case c = parse(minimal_water);
  expect_contains(override_error(c, "domain.dimension=3"), {"the dimension cannot be changed with --set"});
}

TEST(CaseDimension, PolygonsAreTwoDimensional) {
  expect_contains(parse_error(minimal_3d + "[[wall]]\nshape = \"polygon\"\npoints = [[0, 0], [1, 0], [1, 1]]\n"),
                  {"[[wall]] number 1", "a polygon is a 2D shape and this case is 3D"});
}

TEST(CaseDimension, ThreeDimensionalTemplateRoundTrips) {
  Case c = parse(minimal_3d + "[[probe]]\nname = \"p\"\ntype = \"front\"\npoint = [0, 0.5, 0]\n"
                              "direction = [1, 0, 0]\n");
  apply_override(c, "probe[0].point=[0.1, 0.2, 0.3]");
  EXPECT_EQ(c.probes[0].point, (Vec3{0.1, 0.2, 0.3}));
  const std::string t = case_template(c);
  expect_contains(t, {"dimension = 3\n", "depth = 1.0\n", "gravity = [0.0, 0.0, -9.81]\n",
                      "max = [0.5, 1.0, 0.6]\n", "point = [0.1, 0.2, 0.3]\n"});
  expect_cases_equal(parse_case(t, "3D template"), c);
  // The 2D template leaves the 3D keys out.
  EXPECT_EQ(case_template(parse(minimal_water)).find("depth ="), std::string::npos);
}

// ---------------------------------------------------------------------------------------------
// Bodies: a wall's name and its motion's laws ([wall.translation], [wall.rotation]).

TEST(CaseBodies, WallsAreNamedBodiesWithMotionLaws) {
  const std::string gate = minimal_water + R"([[wall]]
name = "gate"
min = [0.2, 0.0]
max = [0.22, 0.6]
[wall.translation]
law = "polynomial"
direction = [0.0, 2.0]
coefficients = [0.0, 0.1463, 72.305, -285.115]
end = 0.15
[[wall]]
min = [0.5, 0.0]
max = [0.6, 0.1]
[wall.rotation]
law = "sinusoidal"
centre = [0.55, 0.0]
amplitude = 5.0
period = 2.0
ramp = 1.0
)";
  const Case c = parse(gate);
  ASSERT_EQ(c.walls.size(), 2u);
  EXPECT_EQ(c.walls[0].name, "gate");
  EXPECT_EQ(c.walls[1].name, "wall2");
  EXPECT_EQ(c.walls[0].translation.law, MotionLawType::polynomial);
  EXPECT_EQ(c.walls[0].translation.coefficients, (std::vector<double>{0.0, 0.1463, 72.305, -285.115}));
  EXPECT_EQ(c.walls[0].translation.after, AfterMotion::hold);
  EXPECT_EQ(c.walls[0].rotation.law, MotionLawType::none);
  EXPECT_EQ(c.walls[1].rotation.law, MotionLawType::sinusoidal);
  EXPECT_EQ(c.walls[1].rotation.period, 2.0);
  EXPECT_TRUE(c.walls[0].moves());
  // The template writes them back, and reads as the same case.
  const Case again = parse(case_template(c));
  EXPECT_EQ(again.walls[1].rotation.amplitude, 5.0);
  EXPECT_EQ(again.walls[0].translation.coefficients, c.walls[0].translation.coefficients);
  EXPECT_EQ(again.walls[1].name, "wall2");
  // --set reaches a law's keys.
  Case changed = c;
  apply_override(changed, "wall[1].rotation.period=2.5");
  EXPECT_EQ(changed.walls[1].rotation.period, 2.5);
  expect_contains(override_error(changed, "wall[1].rotation.perod=2"), {"unknown key 'perod'", "period"});
  expect_contains(override_error(changed, "wall[5].rotation.period=2"), {"there is no wall[5]"});
  // A law's own keys are required, and other laws' refused.
  expect_contains(parse_error(minimal_water + "[[wall]]\nmin = [0.2, 0.0]\nmax = [0.3, 0.5]\n[wall.translation]\n"
                                              "law = \"linear\"\ndirection = [1.0, 0.0]\nend = 1.0\n"),
                  {"[wall.translation] of [[wall]] number 1 has no 'speed'"});
  expect_contains(parse_error(minimal_water + "[[wall]]\nmin = [0.2, 0.0]\nmax = [0.3, 0.5]\n[wall.translation]\n"
                                              "law = \"linear\"\ndirection = [1.0, 0.0]\nspeed = 1.0\nend = 1.0\n"
                                              "period = 2.0\n"),
                  {"[wall.translation] of [[wall]] number 1 gives 'period', which a linear law does not use"});
  expect_contains(parse_error(minimal_water + "[[wall]]\nmin = [0.2, 0.0]\nmax = [0.3, 0.5]\n[wall.rotation]\n"
                                              "law = \"linear\"\nsped = 1.0\nend = 1.0\n"),
                  {"unknown key 'sped' in [wall.rotation] of [[wall]] number 1", "did you mean 'speed'?"});
  expect_contains(parse_error(minimal_water + "[[wall]]\nmin = [0.2, 0.0]\nmax = [0.3, 0.5]\n[wall.translation]\n"
                                              "law = \"linear\"\ndirection = [0.0, 0.0]\nspeed = 1.0\nend = 1.0\n"),
                  {"wall[0].translation.direction = [0.0, 0.0]", "length 0"});
  expect_contains(parse_error(minimal_water + "[[wall]]\nname = \"a b\"\nmin = [0.2, 0.0]\nmax = [0.3, 0.5]\n"),
                  {"wall[0].name = \"a b\"", "letters, digits"});
  expect_contains(parse_error(minimal_water + "[[wall]]\nname = \"g\"\nmin = [0.2, 0.0]\nmax = [0.3, 0.5]\n"
                                              "[[wall]]\nname = \"g\"\nmin = [0.5, 0.0]\nmax = [0.6, 0.5]\n"),
                  {"wall[1].name = \"g\"", "another wall has that name"});
  // Water does not move.
  expect_contains(parse_error("[[water]]\nmin = [0.0, 0.0]\nmax = [1.0, 1.0]\n[water.translation]\nlaw = \"linear\"\n"),
                  {"unknown key 'translation' in [[water]]"});
}
