// What is drawn of a 3D run: the particles a camera sees, ordered far to near, or a slab of them
// (a slice) drawn as a 2D run is.
#pragma once

#include <array>
#include <limits>
#include <string>
#include <string_view>

#include "sluice/render/camera.hpp"
#include "sluice/render/fields.hpp"
#include "sluice/render/frame_renderer.hpp"

namespace sluice::render {

struct Box3 {
  Vec3 lo{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
          std::numeric_limits<double>::infinity()};
  Vec3 hi{-std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(),
          -std::numeric_limits<double>::infinity()};
  void add(const Vec3& p);
  [[nodiscard]] bool empty() const { return !(hi[0] >= lo[0] && hi[1] >= lo[1] && hi[2] >= lo[2]); }
};

// A 3D run seen by a camera, the same for every frame. The tank's walls that face the camera (those
// between it and the water) are left out, so that the water is seen through the open side of a
// cut-away tank; the walls behind it are drawn faint (FrameRenderer).
class CameraScene {
 public:
  // `run_box`: every particle of the run (walls included), which the picture shows whole;
  // `first`: the run's first 3D frame, whose wall particles tell the tank's walls.
  CameraScene(Camera camera, const Box3& run_box, const FrameData& first);

  // The picture's extent in the camera's plane (u right, v up; metres), the particles' radius included.
  [[nodiscard]] const Box& world() const { return world_; }
  // The frame's particles in the camera's plane (x, y = u, v), far to near, with their depth (0 the
  // far corner of run_box, 1 the near one); the walls facing the camera left out.
  [[nodiscard]] FrameData view(const FrameData& frame) const;
  // Whether the wall particle at p is left out.
  [[nodiscard]] bool hidden_wall(const Vec3& p) const;

 private:
  Projection projection_;
  Box3 walls_;                  // the tank's walls: the first frame's wall particles
  double band_ = 0.0;           // wall particles this near a face belong to it
  std::array<bool, 6> cut_{};   // faces x lo, x hi, y lo, y hi, z lo, z hi: closed and facing the camera
  std::array<bool, 6> closed_{};
  Box world_;
  double depth_lo_ = 0.0, depth_hi_ = 1.0;
};

// A slab |x_axis - value| < thickness / 2 of a 3D run.
struct Slice {
  int axis = 1;            // 0 x, 1 y, 2 z
  double value = 0.0;      // metres
  double thickness = 0.0;  // metres; 0: two particle spacings
  [[nodiscard]] double thickness_for(double dx) const { return thickness > 0.0 ? thickness : 2.0 * dx; }
};

// "y=0.5"; RenderError naming --slice for anything else.
Slice parse_slice(std::string_view text);
// A positive length in metres; RenderError naming --thickness.
double parse_thickness(std::string_view text);

// The slab's particles drawn as a 2D frame: the other two axes as x and y (z stays up; a z slice is
// seen from above, x to the right).
FrameData slice_frame(const FrameData& frame, const Slice& slice);
// The run's box in the slice's plane.
Box slice_box(const Box3& box, int axis);
// "slice y = 0.5 m"
std::string describe(const Slice& slice);

}  // namespace sluice::render
