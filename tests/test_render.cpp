// sluice render, the library: colour maps, the rasteriser, the layout, option parsing, and the errors
// for bad requests and damaged runs. tests/test_render.py decodes the files with an independent reader.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <numbers>
#include <numeric>

#include "sluice/io/atomic_file.hpp"
#include "sluice/io/frames.hpp"
#include "sluice/io/npz.hpp"
#include "sluice/render/camera.hpp"
#include "sluice/render/color_range.hpp"
#include "sluice/render/encoders.hpp"
#include "sluice/render/fields.hpp"
#include "sluice/render/frame_renderer.hpp"
#include "sluice/render/options.hpp"
#include "sluice/render/render.hpp"
#include "sluice/render/render_error.hpp"
#include "sluice/render/scene3d.hpp"
#include "sluice/render/ticks.hpp"

using namespace sluice;
using namespace sluice::render;
namespace fs = std::filesystem;

namespace {

double luminance(Rgb c) {  // relative luminance of sRGB (WCAG), enough to order colours
  auto lin = [](double v) {
    v /= 255.0;
    return v <= 0.04045 ? v / 12.92 : std::pow((v + 0.055) / 1.055, 2.4);
  };
  return 0.2126 * lin(c.r) + 0.7152 * lin(c.g) + 0.0722 * lin(c.b);
}

// A scratch directory, removed afterwards.
struct TempDir {
  fs::path path;
  TempDir() {
    path = fs::temp_directory_path() /
           ("sluice_test_render_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
};

// A frame with the given particles: (x, y, vx, kind).
Frame make_test_frame(double time, double dx, const std::vector<std::array<double, 4>>& particles) {
  Frame f;
  f.time = time;
  f.dx = dx;
  for (std::size_t i = 0; i < particles.size(); ++i) {
    const auto& p = particles[i];
    f.position().insert(f.position().end(), {p[0], p[1]});
    f.velocity().insert(f.velocity().end(), {p[2], 0.0});
    f.density().push_back(1000.0);
    f.pressure().push_back(0.0);
    f.kind().push_back(static_cast<std::uint8_t>(p[3]));
    f.id().push_back(static_cast<std::uint32_t>(i));
    f.body().push_back(static_cast<std::uint8_t>(p[3]));
  }
  return f;
}

// A little run directory: a 1 m x 1 m box of wall particles with a few fluid particles moving right.
void write_test_run(const fs::path& dir, int frames) {
  fs::create_directories(dir / "frames");
  for (int k = 0; k < frames; ++k) {
    std::vector<std::array<double, 4>> ps;
    for (int i = -1; i <= 10; ++i) {
      ps.push_back({(i + 0.5) * 0.1, -0.05, 0.0, 1.0});
      ps.push_back({-0.05, (i + 0.5) * 0.1, 0.0, 1.0});
      ps.push_back({1.05, (i + 0.5) * 0.1, 0.0, 1.0});
    }
    for (int i = 0; i < 5; ++i) ps.push_back({0.05 + 0.1 * i + 0.01 * k, 0.05, 0.5 * k, 0.0});
    write_file_atomic(dir / "frames" / fmt::format("frame_{:06}.npz", k),
                      frame_to_npz(make_test_frame(0.1 * k, 0.1, ps)));
  }
}


// A 3D frame reduced to speed: particles (x, y, z, speed, kind).
FrameData make_frame_3d(double dx, const std::vector<std::array<double, 5>>& particles) {
  FrameData d;
  d.time = 0.5;
  d.dx = dx;
  d.dimension = 3;
  for (const auto& p : particles) {
    d.x.push_back(static_cast<float>(p[0]));
    d.y.push_back(static_cast<float>(p[1]));
    d.z.push_back(static_cast<float>(p[2]));
    d.value.push_back(static_cast<float>(p[3]));
    d.kind.push_back(static_cast<std::uint8_t>(p[4]));
  }
  return d;
}

// A cube of n spacings dx of one layer of wall particles (with or without its lid), and a block of
// water in its middle fifth, [0.3, 0.7]^3 of it, moving at 1 m/s.
FrameData cube_with_water(bool lid, int n = 10, double dx = 0.1) {
  std::vector<std::array<double, 5>> ps;
  auto in_water = [n](int i) { return 10 * i >= 3 * n && 10 * i <= 7 * n; };
  for (int i = 0; i <= n; ++i)
    for (int j = 0; j <= n; ++j)
      for (int k = 0; k <= n; ++k) {
        const bool face = i == 0 || i == n || j == 0 || j == n || k == 0 || (k == n && lid);
        if (face) ps.push_back({dx * i, dx * j, dx * k, 0.0, 1.0});
        else if (in_water(i) && in_water(j) && in_water(k)) ps.push_back({dx * i, dx * j, dx * k, 1.0, 0.0});
      }
  return make_frame_3d(dx, ps);
}

Box3 box_of(const FrameData& d) {
  Box3 b;
  for (std::size_t i = 0; i < d.size(); ++i) b.add({d.x[i], d.y[i], d.z[i]});
  return b;
}
}  // namespace

// --- colour maps ------------------------------------------------------------------------------

TEST(Colormap, ViridisEndsAndMiddleAreMatplotlibs) {
  // matplotlib's viridis: entries 0, 128 (of 256: t = 128/255) and 255.
  EXPECT_EQ(colormap_at(Colormap::viridis, 0.0), (Rgb{68, 1, 84}));
  EXPECT_EQ(colormap_at(Colormap::viridis, 1.0), (Rgb{253, 231, 37}));
  EXPECT_EQ(colormap_at(Colormap::viridis, 128.0 / 255.0), (Rgb{33, 145, 140}));
  EXPECT_EQ(colormap_at(Colormap::viridis, -3.0), colormap_at(Colormap::viridis, 0.0));  // clamped
  EXPECT_EQ(colormap_at(Colormap::viridis, 7.0), colormap_at(Colormap::viridis, 1.0));
  EXPECT_EQ(colormap_at(Colormap::viridis, std::nan("")), colormap_at(Colormap::viridis, 0.0));
}

TEST(Colormap, CoolwarmIsBlueGreyRed) {
  // Moreland's CoolWarmFloat33: (59, 76, 192) blue, (221, 221, 221) grey, (180, 4, 38) red.
  EXPECT_EQ(colormap_at(Colormap::coolwarm, 0.0), (Rgb{59, 76, 192}));
  EXPECT_EQ(colormap_at(Colormap::coolwarm, 0.5), (Rgb{221, 221, 221}));
  EXPECT_EQ(colormap_at(Colormap::coolwarm, 1.0), (Rgb{180, 4, 38}));
}

TEST(Colormap, ViridisLightensMonotonically) {
  // Perceptual ordering: low values dark, high values light, never back (in steps of 8 entries:
  // between neighbours the 8-bit rounding can swap the order by a hair).
  double previous = -1.0;
  for (int k = 0; k <= 255; k += k == 248 ? 7 : 8) {
    const double l = luminance(colormap_at(Colormap::viridis, k / 255.0));
    EXPECT_GT(l, previous) << "k = " << k;
    previous = l;
  }
}

TEST(Colormap, CoolwarmIsLightestInTheMiddleAndSymmetric) {
  for (int k = 1; k <= 16; ++k) {
    const double lo = luminance(colormap_at(Colormap::coolwarm, 0.5 - k / 32.0));
    const double hi = luminance(colormap_at(Colormap::coolwarm, 0.5 + k / 32.0));
    EXPECT_LT(lo, luminance(colormap_at(Colormap::coolwarm, 0.5 - (k - 1) / 32.0)));
    EXPECT_LT(hi, luminance(colormap_at(Colormap::coolwarm, 0.5 + (k - 1) / 32.0)));
    EXPECT_NEAR(lo, hi, 0.06) << "k = " << k;  // equal lightness either side (within the table's accuracy)
  }
}

TEST(Palette, LevelsSpanTheMapAndGreysRunWhiteToBlack) {
  const Palette p = Palette::for_map(Colormap::viridis);
  EXPECT_EQ(Palette::map_index(0.0), 0);
  EXPECT_EQ(Palette::map_index(1.0), Palette::map_levels - 1);
  EXPECT_EQ(Palette::map_index(-1.0), 0);
  EXPECT_EQ(Palette::map_index(2.0), Palette::map_levels - 1);
  EXPECT_EQ(Palette::map_index(std::nan("")), 0);
  EXPECT_EQ(p.colours[0], colormap_at(Colormap::viridis, 0.0));
  EXPECT_EQ(p.colours[Palette::map_levels - 1], colormap_at(Colormap::viridis, 1.0));
  EXPECT_EQ(p.colours[Palette::white], (Rgb{255, 255, 255}));
  EXPECT_EQ(p.colours[Palette::black], (Rgb{0, 0, 0}));
  EXPECT_EQ(Palette::grey(0), Palette::white);
  EXPECT_EQ(Palette::grey(Palette::grey_levels - 1), Palette::black);
}

// --- rasteriser ---------------------------------------------------------------------------------

TEST(Raster, DiscCoversThePixelCentresWithinItsRadius) {
  IndexedImage image(40, 30, 0);
  const double cx = 12.3, cy = 17.8, r = 4.2;
  fill_disc(image, cx, cy, r, 7, image.bounds());
  int count = 0;
  for (int y = 0; y < image.height; ++y)
    for (int x = 0; x < image.width; ++x) {
      const double d = std::hypot(x + 0.5 - cx, y + 0.5 - cy);
      if (std::abs(d - r) < 1e-9) continue;  // exactly on the rim: either way
      EXPECT_EQ(image.at(x, y), d < r ? 7 : 0) << x << "," << y;
      count += image.at(x, y) == 7;
    }
  EXPECT_NEAR(count, std::numbers::pi * r * r, 0.15 * std::numbers::pi * r * r);
}

TEST(Raster, TinyDiscStillMarksItsPixelAndClipIsRespected) {
  IndexedImage image(10, 10, 0);
  fill_disc(image, 3.7, 6.2, 0.1, 5, image.bounds());
  EXPECT_EQ(image.at(3, 6), 5);
  EXPECT_EQ(std::count(image.pixels.begin(), image.pixels.end(), 5), 1);
  // A disc overlapping the clip rectangle's edge stays inside it.
  fill_disc(image, 5.0, 5.0, 3.0, 9, Rect{5, 0, 10, 10});
  for (int y = 0; y < 10; ++y)
    for (int x = 0; x < 5; ++x) EXPECT_NE(image.at(x, y), 9);
  EXPECT_EQ(image.at(5, 5), 9);
  // Off the picture and non-finite centres do nothing (and do not crash).
  fill_disc(image, -100.0, 5.0, 3.0, 11, image.bounds());
  fill_disc(image, std::nan(""), 5.0, 3.0, 11, image.bounds());
  EXPECT_EQ(std::count(image.pixels.begin(), image.pixels.end(), 11), 0);
}

// --- layout and drawing -----------------------------------------------------------------------------

TEST(FrameRenderer, ParticlesLandWhereTheLayoutSaysInTheMapsColour) {
  const FieldInfo& speed = field_info(Field::speed);
  const FrameRenderer renderer(speed, Range{0.0, 2.0}, Box{0.0, 0.0, 2.0, 1.0}, 600, 400, Style{"test", false, false, 2, false, {}});
  const Layout& L = renderer.layout();
  EXPECT_EQ(L.width, 600);
  EXPECT_EQ(L.height, 400);
  // Equal aspect ratio: the 2:1 domain is twice as wide as high, within a pixel.
  EXPECT_NEAR(L.plot.width(), 2.0 * L.plot.height(), 2.0);
  EXPECT_LE(L.plot.x1, L.bar.x0);

  // Fluid at rest (speed 0), fast fluid (speed 2 = the top of the range), beyond it (4), a wall.
  Frame f = make_test_frame(1.25, 0.1, {{0.25, 0.25, 0.0, 0}, {1.0, 0.5, 2.0, 0}, {1.75, 0.75, 4.0, 0}, {1.5, 0.2, 0, 1}});
  const IndexedImage image = renderer.draw(extract(f, Field::speed));
  auto index_at = [&](double x, double y) {
    const auto p = L.to_pixel(x, y);
    return image.at(static_cast<int>(p[0]), static_cast<int>(p[1]));
  };
  EXPECT_EQ(index_at(0.25, 0.25), 0);
  EXPECT_EQ(index_at(1.0, 0.5), Palette::map_levels - 1);
  EXPECT_EQ(index_at(1.75, 0.75), Palette::map_levels - 1);  // clamped to the end colour
  EXPECT_EQ(index_at(1.5, 0.2), Palette::grey(FrameRenderer::wall_grey));
  // A disc of area dx^2 (radius 0.0564 m): covered 0.05 m from the centre, not 0.065 m away.
  EXPECT_EQ(index_at(0.25 + 0.05, 0.25), 0);
  EXPECT_EQ(index_at(0.25, 0.25 - 0.05), 0);
  EXPECT_EQ(index_at(0.25 + 0.065, 0.25), Palette::white);
  EXPECT_EQ(index_at(1.0, 0.25), Palette::white);  // empty space
  // y is up: the particle at y = 0.75 is above (smaller row) the one at y = 0.25.
  EXPECT_LT(L.to_pixel(0, 0.75)[1], L.to_pixel(0, 0.25)[1]);
  // The colour bar: low at the bottom, high at the top.
  const int bx = (L.bar.x0 + L.bar.x1) / 2;
  EXPECT_EQ(image.at(bx, L.bar.y1 - 1), 0);
  EXPECT_EQ(image.at(bx, L.bar.y0), Palette::map_levels - 1);
  // The time stamp is drawn: dark pixels in the top band, right of the middle.
  int dark = 0;
  for (int y = 0; y < L.plot.y0; ++y)
    for (int x = L.width / 2; x < L.plot.x1; ++x) dark += image.at(x, y) >= Palette::grey(20);
  EXPECT_GT(dark, 20);
  // ... and it changes with the time.
  f.time = 7.5;
  const IndexedImage later = renderer.draw(extract(f, Field::speed));
  EXPECT_NE(image.pixels, later.pixels);
}

TEST(FrameRenderer, DefaultSizeFollowsTheDomainAndIsEven) {
  const FieldInfo& info = field_info(Field::vx);
  const FrameRenderer wide(info, Range{-1, 1}, Box{0, 0, 20, 10}, 0, 0, Style{});
  EXPECT_EQ(wide.layout().width % 2, 0);
  EXPECT_EQ(wide.layout().height % 2, 0);
  EXPECT_GT(wide.layout().width, 800);
  EXPECT_LT(wide.layout().width, 1300);
  EXPECT_NEAR(wide.layout().plot.width(), 2.0 * wide.layout().plot.height(), 2.0);
  const FrameRenderer tall(info, Range{-1, 1}, Box{0, 0, 1, 3}, 0, 0, Style{});
  EXPECT_NEAR(3.0 * tall.layout().plot.width(), tall.layout().plot.height(), 3.0);
  EXPECT_LT(tall.layout().width, tall.layout().height);
  EXPECT_THROW(FrameRenderer(info, Range{-1, 1}, Box{0, 0, 1, 1}, 160, 120, Style{}, "/no/such/font.ttf"), RenderError);
}

TEST(FrameRenderer, SignedFieldsUseTheDivergingMap) {
  const FrameRenderer r(field_info(Field::vy), Range{-1, 1}, Box{0, 0, 1, 1}, 300, 200, Style{});
  EXPECT_EQ(r.palette().colours[0], colormap_at(Colormap::coolwarm, 0.0));
  const FrameRenderer s(field_info(Field::density), Range{990, 1010}, Box{0, 0, 1, 1}, 300, 200, Style{});
  EXPECT_EQ(s.palette().colours[0], colormap_at(Colormap::viridis, 0.0));
}

// --- 3D: the camera, the scene, the slice ------------------------------------------------------------

TEST(Camera, AzimuthZeroElevationZeroLooksAlongMinusX) {
  const Projection side(Camera{0.0, 0.0});
  const Projected px = side({1.0, 0.0, 0.0});  // on +x: straight in front of the camera, nearest
  EXPECT_NEAR(px.u, 0.0, 1e-12);
  EXPECT_NEAR(px.v, 0.0, 1e-12);
  EXPECT_NEAR(px.depth, 1.0, 1e-12);
  EXPECT_NEAR(side({0.0, 1.0, 0.0}).u, 1.0, 1e-12);  // +y to the right
  EXPECT_NEAR(side({0.0, 0.0, 1.0}).v, 1.0, 1e-12);  // z up
  EXPECT_NEAR(side({-2.0, 0.0, 0.0}).depth, -2.0, 1e-12);
  // Azimuth 90: the camera on +y; +x is then to the left.
  EXPECT_NEAR(Projection(Camera{90.0, 0.0})({1.0, 0.0, 0.0}).u, -1.0, 1e-12);
}

TEST(Camera, NamedViews) {
  const Projection top(named_view("top"));  // looking down z: x right, y up, z nearer
  const Projected p = top({0.3, 0.7, 0.2});
  EXPECT_NEAR(p.u, 0.3, 1e-12);
  EXPECT_NEAR(p.v, 0.7, 1e-12);
  EXPECT_NEAR(p.depth, 0.2, 1e-12);
  const Projection front(named_view("front"));  // along +y: x right, z up, smaller y nearer
  const Projected q = front({0.3, 0.7, 0.2});
  EXPECT_NEAR(q.u, 0.3, 1e-12);
  EXPECT_NEAR(q.v, 0.2, 1e-12);
  EXPECT_NEAR(q.depth, -0.7, 1e-12);
  const Projection side(named_view("side"));  // along -x: y right, z up
  EXPECT_NEAR(side({0.3, 0.7, 0.2}).u, 0.7, 1e-12);
  EXPECT_NEAR(side({0.3, 0.7, 0.2}).v, 0.2, 1e-12);
  // iso: from the front right, above: the near top corner of a cube is nearer than the far bottom one.
  const Projection iso(named_view("iso"));
  EXPECT_GT(iso({1.0, 0.0, 1.0}).depth, iso({0.0, 1.0, 0.0}).depth);
  EXPECT_EQ(describe(named_view("iso")), "iso view");
  EXPECT_THROW(named_view("perspective"), RenderError);
  EXPECT_DOUBLE_EQ(parse_azimuth("-45"), -45.0);
  EXPECT_DOUBLE_EQ(parse_elevation("90"), 90.0);
  for (const char* bad : {"91", "-90.5", "x", "", "nan"}) EXPECT_THROW(parse_elevation(bad), RenderError) << bad;
  EXPECT_THROW(parse_azimuth("inf"), RenderError);
}

TEST(CameraScene, OrdersFarToNearAndCutsTheWallsFacingTheCamera) {
  const FrameData cube = cube_with_water(true);
  const CameraScene scene(named_view("iso"), box_of(cube), cube);
  const FrameData v = scene.view(cube);
  ASSERT_FALSE(v.depth.empty());
  EXPECT_TRUE(std::is_sorted(v.depth.begin(), v.depth.end()));  // painter's order: far first
  EXPECT_GE(v.depth.front(), 0.0f);
  EXPECT_LE(v.depth.back(), 1.0f);
  // The iso camera is on the +x, -y side, above: those walls and the lid go, the others stay.
  EXPECT_TRUE(scene.hidden_wall({1.0, 0.5, 0.5}));
  EXPECT_TRUE(scene.hidden_wall({0.5, 0.0, 0.5}));
  EXPECT_TRUE(scene.hidden_wall({0.5, 0.5, 1.0}));
  EXPECT_FALSE(scene.hidden_wall({0.0, 0.5, 0.5}));
  EXPECT_FALSE(scene.hidden_wall({0.5, 1.0, 0.5}));
  EXPECT_FALSE(scene.hidden_wall({0.5, 0.5, 0.0}));
  EXPECT_EQ(std::count(v.kind.begin(), v.kind.end(), 0), 125);  // all the water is drawn
  // Without a lid the top is open: the back walls' top rows stay.
  const FrameData open = cube_with_water(false);
  const CameraScene open_scene(named_view("iso"), box_of(open), open);
  EXPECT_FALSE(open_scene.hidden_wall({0.5, 1.0, 1.0}));
  EXPECT_FALSE(open_scene.hidden_wall({0.0, 0.5, 1.0}));
  EXPECT_TRUE(open_scene.hidden_wall({0.5, 0.0, 1.0}));
  // A spacing that single-precision positions do not divide exactly finds the same walls.
  const FrameData fine = cube_with_water(false, 40, 0.0175);
  const CameraScene fine_scene(named_view("iso"), box_of(fine), fine);
  EXPECT_TRUE(fine_scene.hidden_wall({0.35, 0.0, 0.35}));
  EXPECT_TRUE(fine_scene.hidden_wall({0.7, 0.35, 0.35}));
  EXPECT_FALSE(fine_scene.hidden_wall({0.35, 0.7, 0.35}));
  EXPECT_FALSE(fine_scene.hidden_wall({0.35, 0.35, 0.0}));
  // Two particles on one line of sight: the nearer is drawn last.
  const FrameData two = make_frame_3d(0.1, {{0.5, 0.5, 0.9, 1.0, 0.0}, {0.5, 0.5, 0.1, 0.0, 0.0}});
  const CameraScene top(named_view("top"), box_of(cube), cube);
  const FrameData seen = top.view(two);
  ASSERT_EQ(seen.size(), 2u);
  EXPECT_FLOAT_EQ(seen.value.back(), 1.0f);  // the upper one, nearer a camera looking down
  EXPECT_LT(seen.depth.front(), seen.depth.back());
}

TEST(FrameRenderer, A3DFrameShowsTheWaterInShadedMapColoursAndFaintFarWalls) {
  const FrameData cube = cube_with_water(true);
  const CameraScene scene(named_view("iso"), box_of(cube), cube);
  Style style;
  style.title = "3D";
  style.shaded = true;
  const FieldInfo& speed = field_info(Field::speed);
  const FrameRenderer renderer(speed, Range{0.0, 2.0}, scene.world(), 700, 600, style);
  const IndexedImage image = renderer.draw(scene.view(cube));
  const Layout& L = renderer.layout();
  const Projection iso(named_view("iso"));
  auto pixel_of = [&](const Vec3& p) {
    const Projected q = iso(p);
    const auto px = L.to_pixel(q.u, q.v);
    return image.at(static_cast<int>(px[0]), static_cast<int>(px[1]));
  };
  // The water's near corner (the walls in front of it are cut away): speed 1 of 0..2, the map's
  // middle, in one of its shades.
  const std::uint8_t water = pixel_of({0.7, 0.3, 0.7});
  ASSERT_LT(water, Palette::map_levels);
  EXPECT_EQ(water % Palette::shaded_levels, Palette::shaded_index(0.5, 0) % Palette::shaded_levels);
  const Rgb c = renderer.palette().colours[water], m = colormap_at(Colormap::viridis, 0.5);
  const double f = static_cast<double>(c.g) / m.g;
  EXPECT_GE(f, Palette::darkest_shade - 0.02);
  EXPECT_LE(f, 1.0 + 1e-9);
  EXPECT_NEAR(c.r, f * m.r, 2.0);
  EXPECT_NEAR(c.b, f * m.b, 2.0);
  // The shaded palette: shade 0 is darkest_shade times the map, the top shade the map itself.
  EXPECT_EQ(renderer.palette().colours[Palette::shaded_index(1.0, Palette::shade_levels - 1)],
            colormap_at(Colormap::viridis, 1.0));
  // The far walls (x = 0, y = 1, the floor) are faint grey, well away from the water.
  for (const Vec3& p : std::vector<Vec3>{{0.0, 1.0, 0.95}, {0.0, 0.1, 0.9}, {0.9, 0.9, 0.0}}) {
    const Rgb w = renderer.palette().colours[pixel_of(p)];
    EXPECT_TRUE(w.r == w.g && w.g == w.b) << p[0] << "," << p[1] << "," << p[2];
    EXPECT_GE(w.r, 170) << p[0] << "," << p[1] << "," << p[2];
    EXPECT_LT(w.r, 255) << p[0] << "," << p[1] << "," << p[2];
  }
  // The colour bar is the map's own colours, low at the bottom.
  const int bx = (L.bar.x0 + L.bar.x1) / 2;
  EXPECT_EQ(renderer.palette().colours[image.at(bx, L.bar.y1 - 1)], colormap_at(Colormap::viridis, 0.0));
  EXPECT_EQ(renderer.palette().colours[image.at(bx, L.bar.y0)], colormap_at(Colormap::viridis, 1.0));
}

TEST(Slice, PicksExactlyTheParticlesInTheSlab) {
  std::vector<std::array<double, 5>> ps;
  for (int j = 0; j <= 10; ++j) ps.push_back({0.25, 0.1 * j, 0.75, 0.1 * j, j == 0 ? 1.0 : 0.0});
  const FrameData d = make_frame_3d(0.1, ps);
  Slice s = parse_slice("y=0.5");
  EXPECT_EQ(s.axis, 1);
  EXPECT_DOUBLE_EQ(s.value, 0.5);
  s.thickness = 0.25;  // |y - 0.5| < 0.125: y = 0.4, 0.5, 0.6
  const FrameData slab = slice_frame(d, s);
  ASSERT_EQ(slab.size(), 3u);
  EXPECT_EQ(slab.dimension, 2);
  EXPECT_TRUE(slab.depth.empty());
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_FLOAT_EQ(slab.x[i], 0.25f);  // x stays x, z is up
    EXPECT_FLOAT_EQ(slab.y[i], 0.75f);
    EXPECT_NEAR(slab.value[i], 0.4 + 0.1 * static_cast<double>(i), 1e-6);
  }
  s.value = 0.45;
  s.thickness = 0.0;  // the default: 2 dx, |y - 0.45| < 0.1: y = 0.4 and 0.5
  const FrameData narrow = slice_frame(d, s);
  ASSERT_EQ(narrow.size(), 2u);
  EXPECT_NEAR(narrow.value[0], 0.4, 1e-6);
  EXPECT_NEAR(narrow.value[1], 0.5, 1e-6);
  // An x slice shows (y, z); a z slice (x, y).
  const FrameData xs = slice_frame(d, parse_slice("x=0.25"));
  ASSERT_EQ(xs.size(), 11u);
  EXPECT_FLOAT_EQ(xs.x[3], d.y[3]);
  EXPECT_FLOAT_EQ(xs.y[3], 0.75f);
  EXPECT_EQ(slice_frame(d, parse_slice("z=0.75")).size(), 11u);
  EXPECT_EQ(slice_frame(d, parse_slice("z=0.5")).size(), 0u);
  for (const char* bad : {"y", "w=0.5", "y=", "y=a", "xy=1", "=1"}) EXPECT_THROW(parse_slice(bad), RenderError) << bad;
  EXPECT_THROW(parse_thickness("0"), RenderError);
  EXPECT_THROW(parse_thickness("-1"), RenderError);
  EXPECT_DOUBLE_EQ(parse_thickness("0.05"), 0.05);
}

TEST(RenderRun, CameraSliceAndVzOnA2DRunAreClearErrors) {
  TempDir tmp;
  write_test_run(tmp.path, 2);
  auto message = [&](const RenderOptions& o) {
    try {
      render_run(tmp.path, o);
    } catch (const RenderError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  RenderOptions o;
  o.camera = named_view("top");
  o.camera_flag = "--elevation";
  EXPECT_NE(message(o).find("--elevation: the run is 2D"), std::string::npos) << message(o);
  o = RenderOptions{};
  o.slice = parse_slice("y=0.5");
  EXPECT_NE(message(o).find("--slice: the run is 2D"), std::string::npos) << message(o);
  o = RenderOptions{};
  o.field = Field::vz;
  EXPECT_NE(message(o).find("--field vz: the run is 2D"), std::string::npos) << message(o);
  EXPECT_FALSE(fs::exists(tmp.path / "speed.gif"));
  EXPECT_FALSE(fs::exists(tmp.path / "vz.gif"));
}

// --- options -----------------------------------------------------------------------------------

TEST(Options, RangeParses) {
  EXPECT_DOUBLE_EQ(parse_range("0:5").lo, 0.0);
  EXPECT_DOUBLE_EQ(parse_range("0:5").hi, 5.0);
  EXPECT_DOUBLE_EQ(parse_range("-2.5:2.5").lo, -2.5);
  EXPECT_DOUBLE_EQ(parse_range("1e-3:+2").hi, 2.0);
  EXPECT_DOUBLE_EQ(parse_range(" 990 : 1010 ").lo, 990.0);
  for (const char* bad : {"", "5", "5:0", "1:1", "a:b", "1:2:3", ":2", "1:", "0:inf", "nan:1"})
    EXPECT_THROW(parse_range(bad), RenderError) << bad;
}

TEST(Options, SizeTimesFieldsFormats) {
  EXPECT_EQ(parse_size("640x480"), (std::pair{640, 480}));
  EXPECT_EQ(parse_size("1920X1080"), (std::pair{1920, 1080}));
  for (const char* bad : {"640", "10x10", "640x", "x480", "640x480x3", "axb", "99999x480"})
    EXPECT_THROW(parse_size(bad), RenderError) << bad;
  EXPECT_EQ(parse_times("0,1.5, 3"), (std::vector<double>{0.0, 1.5, 3.0}));
  for (const char* bad : {"", "1,,2", "-1", "a", "1;2"}) EXPECT_THROW(parse_times(bad), RenderError) << bad;
  EXPECT_EQ(parse_field("pressure"), Field::pressure);
  EXPECT_EQ(parse_format("mp4"), Format::mp4);
  try {
    parse_field("velocity");
    FAIL() << "no error for an unknown field";
  } catch (const RenderError& e) {
    EXPECT_NE(std::string(e.what()).find("unknown field 'velocity'"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("vx, vy, vz, speed, pressure, density"), std::string::npos) << e.what();
  }
  EXPECT_THROW(parse_format("avi"), RenderError);
}

TEST(Options, NiceTicksAndLabels) {
  EXPECT_EQ(nice_ticks({0.0, 5.249}, 6), (std::vector<double>{0, 1, 2, 3, 4, 5}));
  EXPECT_EQ(nice_ticks({0.0, 5.249}, 3), (std::vector<double>{0, 2, 4}));
  EXPECT_EQ(nice_ticks({-5.1, 5.1}, 6), (std::vector<double>{-4, -2, 0, 2, 4}));
  const auto dense = nice_ticks({993.3, 1113.0}, 8);
  EXPECT_LE(dense.size(), 8u);
  EXPECT_GE(dense.size(), 4u);
  EXPECT_EQ(tick_label(-2.0, 1.0), "\u22122");  // a real minus sign
  EXPECT_EQ(tick_label(0.5, 0.25), "0.50");
  EXPECT_EQ(tick_label(-0.0, 0.1), "0.0");
  EXPECT_EQ(tick_label(1000.0, 20.0), "1000");
}

TEST(Options, DataRangeIsRobustAndShapedByTheField) {
  std::vector<float> speeds(10000);
  std::iota(speeds.begin(), speeds.end(), 0.0f);
  speeds.push_back(1e9f);  // one wild particle does not wash the picture out
  const Range s = data_range(field_info(Field::speed), speeds);
  EXPECT_EQ(s.lo, 0.0);
  EXPECT_NEAR(s.hi, 9990.0, 2.0);
  std::vector<float> vx = {-3.0f, 1.0f, 2.0f};
  const Range v = data_range(field_info(Field::vx), vx);
  EXPECT_DOUBLE_EQ(v.lo, -v.hi);
  EXPECT_NEAR(v.hi, 3.0, 1e-6);
  const Range d = data_range(field_info(Field::density), {1000.0f, 1000.0f});  // uniform: still a range
  EXPECT_LT(d.lo, 1000.0);
  EXPECT_GT(d.hi, 1000.0);
  const Range empty = data_range(field_info(Field::pressure), {});
  EXPECT_LT(empty.lo, empty.hi);
}

// --- runs on disk: files and errors ----------------------------------------------------------------

TEST(RenderRun, WritesAGifAndSnapshots) {
  TempDir tmp;
  write_test_run(tmp.path, 4);
  RenderOptions o;
  o.field = Field::vx;
  const RenderResult gif = render_run(tmp.path, o);
  ASSERT_EQ(gif.files.size(), 1u);
  EXPECT_EQ(gif.files[0], tmp.path / "vx.gif");
  EXPECT_EQ(gif.frames, 4);
  EXPECT_DOUBLE_EQ(gif.range.hi, 1.5);  // |vx| up to 1.5 m/s in the last frame
  EXPECT_DOUBLE_EQ(gif.range.lo, -1.5);
  EXPECT_EQ(read_file(gif.files[0]).substr(0, 6), "GIF89a");

  o.format = Format::png;
  o.times = {0.1, 0.29};
  const RenderResult png = render_run(tmp.path, o);
  ASSERT_EQ(png.files.size(), 2u);
  EXPECT_EQ(png.files[0], tmp.path / "snapshots" / "vx_000001.png");
  EXPECT_EQ(png.files[1], tmp.path / "snapshots" / "vx_000003.png");
  EXPECT_EQ(read_file(png.files[1]).substr(1, 3), "PNG");

  o.times = {0.0};
  o.output = tmp.path / "one.png";
  EXPECT_EQ(render_run(tmp.path, o).files, std::vector<fs::path>{tmp.path / "one.png"});
  EXPECT_TRUE(fs::exists(tmp.path / "one.png"));
}

TEST(RenderRun, BadRequestsAreClearErrors) {
  TempDir tmp;
  write_test_run(tmp.path, 3);
  RenderOptions o;
  o.format = Format::png;
  o.times = {5.0};  // the frames end at 0.2 s
  try {
    render_run(tmp.path, o);
    FAIL() << "no error for a time without a frame";
  } catch (const RenderError& e) {
    EXPECT_NE(std::string(e.what()).find("no frame at t = 5 s"), std::string::npos) << e.what();
  }
  o.times = {0.0, 0.1};
  o.output = tmp.path / "one.png";  // two pictures, one file
  EXPECT_THROW(render_run(tmp.path, o), RenderError);
  RenderOptions gif;
  gif.fps = 60;  // GIF cannot play that
  EXPECT_THROW(render_run(tmp.path, gif), RenderError);
  gif.fps = 20;
  gif.times = {0.0};  // --times is for PNG
  EXPECT_THROW(render_run(tmp.path, gif), RenderError);
  EXPECT_FALSE(fs::exists(tmp.path / "speed.gif"));
}

TEST(RenderRun, EmptyOrMissingDirectoryIsAClearError) {
  TempDir tmp;
  try {
    render_run(tmp.path, RenderOptions{});
    FAIL() << "no error for an empty directory";
  } catch (const RenderError& e) {
    EXPECT_NE(std::string(e.what()).find("no frames"), std::string::npos) << e.what();
  }
  EXPECT_THROW(render_run(tmp.path / "nope", RenderOptions{}), RenderError);
  fs::create_directories(tmp.path / "frames");
  std::ofstream(tmp.path / "frames" / "frame_000000.vtu") << "<VTKFile/>";
  try {
    render_run(tmp.path, RenderOptions{});
    FAIL() << "no error for a run without npz frames";
  } catch (const RenderError& e) {
    EXPECT_NE(std::string(e.what()).find("npz"), std::string::npos) << e.what();
  }
}

TEST(RenderRun, DamagedOrMissingFrameIsAClearErrorAndWritesNothing) {
  TempDir tmp;
  write_test_run(tmp.path, 4);
  const fs::path damaged = tmp.path / "frames" / "frame_000002.npz";
  const std::string bytes = read_file(damaged);
  write_file_atomic(damaged, bytes.substr(0, bytes.size() / 2));  // truncated
  try {
    render_run(tmp.path, RenderOptions{});
    FAIL() << "no error for a damaged frame";
  } catch (const FormatError& e) {
    EXPECT_NE(std::string(e.what()).find("frame_000002.npz"), std::string::npos) << e.what();
  }
  EXPECT_FALSE(fs::exists(tmp.path / "speed.gif"));

  fs::remove(damaged);
  try {
    render_run(tmp.path, RenderOptions{});
    FAIL() << "no error for a missing frame";
  } catch (const FormatError& e) {
    EXPECT_NE(std::string(e.what()).find("frame 2 is missing"), std::string::npos) << e.what();
  }
}

// A frame whose positions or time are not finite was drawn (the particle left out, the time stamp
// "nan"): it is refused, naming the frame's file, and nothing is written.
TEST(RenderRun, AFrameWithANonFinitePositionOrTimeIsRefused) {
  for (const bool time : {false, true}) {
    SCOPED_TRACE(time ? "time" : "position");
    TempDir tmp;
    write_test_run(tmp.path, 4);
    const fs::path bad = tmp.path / "frames" / "frame_000002.npz";
    Frame f = frame_from_npz(read_file(bad), "frame 2");
    if (time) f.time = std::numeric_limits<double>::quiet_NaN();
    else f.position()[7] = std::numeric_limits<double>::quiet_NaN();
    write_file_atomic(bad, frame_to_npz(f));
    try {
      render_run(tmp.path, RenderOptions{});
      FAIL() << "no error for a frame that is not finite";
    } catch (const FormatError& e) {
      EXPECT_NE(std::string(e.what()).find(bad.string() + ": not a sluice frame: " +
                                           (time ? "its time t = nan is not finite"
                                                 : "the position of particle id 3 (row 3 of x) is not finite")),
                std::string::npos)
          << e.what();
    }
    EXPECT_FALSE(fs::exists(tmp.path / "speed.gif"));
  }
}

TEST(RenderRun, Mp4NeedsFfmpegOrSaysSo) {
  TempDir tmp;
  write_test_run(tmp.path, 3);
  RenderOptions o;
  o.format = Format::mp4;
  if (find_program("ffmpeg")) {
    const RenderResult r = render_run(tmp.path, o);
    ASSERT_EQ(r.files.size(), 1u);
    EXPECT_GT(fs::file_size(r.files[0]), 100u);
    EXPECT_EQ(read_file(r.files[0]).substr(4, 4), "ftyp");  // an MP4 (ISO BMFF) file
  } else {
    try {
      render_run(tmp.path, o);
      FAIL() << "no error without ffmpeg";
    } catch (const IoError& e) {
      EXPECT_NE(std::string(e.what()).find("ffmpeg"), std::string::npos) << e.what();
    }
  }
}
