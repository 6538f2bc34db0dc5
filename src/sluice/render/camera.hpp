// The camera of pictures of 3D runs: an orthographic projection seen from a direction given by an
// azimuth about the vertical z axis and an elevation above the horizontal, and the named views.
#pragma once

#include <array>
#include <string>
#include <string_view>

namespace sluice::render {

using Vec3 = std::array<double, 3>;

// The direction the camera looks from, in degrees: from the point at azimuth `azimuth` (0 on +x, 90
// on +y) and `elevation` above the horizontal (90: straight down from above), towards the scene.
struct Camera {
  double azimuth = -60.0;
  double elevation = 30.0;
};

// The named views: iso (the default; from the front right, above), front (looking along +y), side
// (looking along -x), top (looking down z, x to the right and y up). RenderError naming them for
// any other name.
Camera named_view(std::string_view name);
std::string_view default_view_name();

// An angle in degrees given to `flag`; RenderError naming the flag unless it is a finite number (and,
// for --elevation, in [-90, 90]).
double parse_azimuth(std::string_view text);
double parse_elevation(std::string_view text);

// Where a camera puts a point: u to the right and v up in the picture (metres), and its depth (larger
// is nearer the camera). Orthographic: sizes do not shrink with distance.
struct Projected {
  double u = 0.0, v = 0.0, depth = 0.0;
};

class Projection {
 public:
  explicit Projection(Camera camera);
  [[nodiscard]] Projected operator()(const Vec3& p) const;
  // The unit vector from the scene towards the camera.
  [[nodiscard]] const Vec3& toward_camera() const { return toward_; }

 private:
  Vec3 toward_, right_, up_;
};

// "azimuth -60°, elevation 30°", or the view's name when it is a named one.
std::string describe(Camera camera);

}  // namespace sluice::render
