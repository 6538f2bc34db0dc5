// A solid that moves rigidly: a shape given at its start pose (a box, polygon or mesh) and the body's
// current pose (geometry/motion.hpp). Every query is the shape's, asked at the point taken back to
// the start pose, with the answer (a surface point, a normal) carried forward to now; so leak
// detection and put-back, the wall-approach stop and mDBC's ghost nodes, which ask the Solid
// interface, follow a moving wall without knowing that it moves.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <utility>

#include "sluice/geometry/motion.hpp"
#include "sluice/geometry/solid.hpp"

namespace sluice {

template <int Dim>
class MovingSolid final : public Solid<Dim> {
 public:
  explicit MovingSolid(std::shared_ptr<const Solid<Dim>> shape) : shape_(std::move(shape)) { update_bounds(); }

  // The pose the queries answer for (the start pose until the first call).
  void set_state(const BodyState<Dim>& state) {
    state_ = state;
    update_bounds();
  }
  [[nodiscard]] const BodyState<Dim>& state() const { return state_; }
  [[nodiscard]] const Solid<Dim>& shape() const { return *shape_; }

  [[nodiscard]] bool contains(const Vec<Dim>& x) const override { return shape_->contains(to_start<Dim>(state_, x)); }
  [[nodiscard]] double signed_distance(const Vec<Dim>& x) const override {
    return shape_->signed_distance(to_start<Dim>(state_, x));  // a rigid motion keeps distances
  }
  [[nodiscard]] SurfacePoint<Dim> closest_surface_point(const Vec<Dim>& x) const override {
    const SurfacePoint<Dim> s = shape_->closest_surface_point(to_start<Dim>(state_, x));
    return {point_motion<Dim>(state_, s.point).position, rotate_to_now<Dim>(state_, s.normal)};
  }
  [[nodiscard]] bool moves() const override { return true; }
  [[nodiscard]] Vec<Dim> velocity_at(const Vec<Dim>& x) const override { return motion_at<Dim>(state_, x).velocity; }
  [[nodiscard]] Vec<Dim> lower() const override { return lower_; }
  [[nodiscard]] Vec<Dim> upper() const override { return upper_; }
  // An axis-aligned box stays one while it only translates.
  [[nodiscard]] bool is_box() const override { return shape_->is_box() && state_.angle == 0.0; }
  void for_each_face_point(const Vec<Dim>& x, const std::function<void(const Vec<Dim>&)>& f) const override {
    shape_->for_each_face_point(to_start<Dim>(state_, x),
                                [&](const Vec<Dim>& q) { f(point_motion<Dim>(state_, q).position); });
  }
  void for_each_face_outside(const Vec<Dim>& x, double reach,
                             const std::function<void(const Vec<Dim>&, const Vec<Dim>&)>& f) const override {
    shape_->for_each_face_outside(to_start<Dim>(state_, x), reach, [&](const Vec<Dim>& q, const Vec<Dim>& normal) {
      f(point_motion<Dim>(state_, q).position, rotate_to_now<Dim>(state_, normal));
    });
  }
  void fill_surface_layers(double dx, int layers, const std::function<void(const Vec<Dim>&)>& add) const override {
    shape_->fill_surface_layers(dx, layers, [&](const Vec<Dim>& q) { add(point_motion<Dim>(state_, q).position); });
  }

 private:
  // The bounding box of the shape's bounding box's corners carried to now: it holds the moved shape
  // (a rotated box's corners bound it), a little larger than the shape's own when turned.
  void update_bounds() {
    const Vec<Dim> lo = shape_->lower(), hi = shape_->upper();
    for (int d = 0; d < Dim; ++d) {
      lower_[d] = std::numeric_limits<double>::infinity();
      upper_[d] = -std::numeric_limits<double>::infinity();
    }
    for (int corner = 0; corner < (1 << Dim); ++corner) {
      Vec<Dim> c{};
      for (int d = 0; d < Dim; ++d) c[d] = (corner >> d) & 1 ? hi[d] : lo[d];
      const Vec<Dim> now = point_motion<Dim>(state_, c).position;
      for (int d = 0; d < Dim; ++d) {
        lower_[d] = std::min(lower_[d], now[d]);
        upper_[d] = std::max(upper_[d], now[d]);
      }
    }
  }

  std::shared_ptr<const Solid<Dim>> shape_;
  BodyState<Dim> state_{};
  Vec<Dim> lower_{}, upper_{};
};

}  // namespace sluice
