#include "sluice/render/scene3d.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

#include "sluice/render/render_error.hpp"

namespace sluice::render {

void Box3::add(const Vec3& p) {
  for (int a = 0; a < 3; ++a) {
    lo[a] = std::min(lo[a], p[a]);
    hi[a] = std::max(hi[a], p[a]);
  }
}

namespace {

constexpr std::array<char, 3> axis_names = {'x', 'y', 'z'};

Vec3 position(const FrameData& d, std::size_t i) { return {d.x[i], d.y[i], d.z[i]}; }

// The eight corners of a box.
std::array<Vec3, 8> corners(const Box3& b) {
  std::array<Vec3, 8> c;
  for (int k = 0; k < 8; ++k) c[k] = {(k & 1) ? b.hi[0] : b.lo[0], (k & 2) ? b.hi[1] : b.lo[1], (k & 4) ? b.hi[2] : b.lo[2]};
  return c;
}

// Distance of p inside the box from face f (axis f / 2; low side for even f).
double face_distance(const Box3& b, const Vec3& p, int f) {
  const int a = f / 2;
  return f % 2 == 0 ? p[a] - b.lo[a] : b.hi[a] - p[a];
}

// Which faces of the walls' box are walls: the outermost layer of wall particles covers most of
// the face (an open top has wall particles only along its rim).
std::array<bool, 6> closed_faces(const Box3& walls, const FrameData& first) {
  const double dx = first.dx;
  std::array<bool, 6> closed{};
  for (int f = 0; f < 6; ++f) {
    const int a = f / 2, b = (a + 1) % 3, c = (a + 2) % 3;
    // Cells centred on the lattice from the box's corner (rounded: positions are single precision).
    const int nb = static_cast<int>(std::lround((walls.hi[b] - walls.lo[b]) / dx)) + 1;
    const int nc = static_cast<int>(std::lround((walls.hi[c] - walls.lo[c]) / dx)) + 1;
    std::vector<char> covered(static_cast<std::size_t>(nb) * nc, 0);
    for (std::size_t i = 0; i < first.size(); ++i) {
      if (first.kind[i] == 0) continue;
      const Vec3 p = position(first, i);
      if (!(face_distance(walls, p, f) < 0.75 * dx)) continue;
      const int ib = std::clamp(static_cast<int>(std::lround((p[b] - walls.lo[b]) / dx)), 0, nb - 1);
      const int ic = std::clamp(static_cast<int>(std::lround((p[c] - walls.lo[c]) / dx)), 0, nc - 1);
      covered[static_cast<std::size_t>(ib) * nc + ic] = 1;
    }
    closed[f] = 2 * std::count(covered.begin(), covered.end(), 1) > static_cast<std::ptrdiff_t>(covered.size());
  }
  return closed;
}

}  // namespace

CameraScene::CameraScene(Camera camera, const Box3& run_box, const FrameData& first) : projection_(camera) {
  for (std::size_t i = 0; i < first.size(); ++i)
    if (first.kind[i] != 0 && first.z.size() == first.size()) walls_.add(position(first, i));
  band_ = 4.0 * first.dx;  // deeper than the walls' layers (2h at h up to 2 dx)
  if (!walls_.empty()) closed_ = closed_faces(walls_, first);
  const Vec3& toward = projection_.toward_camera();
  for (int f = 0; f < 6; ++f) cut_[f] = closed_[f] && (f % 2 == 0 ? -toward[f / 2] : toward[f / 2]) > 1e-9;
  double u0 = INFINITY, u1 = -INFINITY, v0 = INFINITY, v1 = -INFINITY;
  depth_lo_ = INFINITY;
  depth_hi_ = -INFINITY;
  for (const Vec3& c : corners(run_box)) {
    const Projected p = projection_(c);
    u0 = std::min(u0, p.u), u1 = std::max(u1, p.u), v0 = std::min(v0, p.v), v1 = std::max(v1, p.v);
    depth_lo_ = std::min(depth_lo_, p.depth), depth_hi_ = std::max(depth_hi_, p.depth);
  }
  const double pad = 0.75 * first.dx;
  world_ = {u0 - pad, v0 - pad, u1 + pad, v1 + pad};
  if (!(depth_hi_ > depth_lo_)) depth_hi_ = depth_lo_ + 1.0;
}

// A wall particle belongs to the nearest closed face within band_; it is left out when that face
// is cut away. Wall particles elsewhere (solids inside the tank) are always drawn.
bool CameraScene::hidden_wall(const Vec3& p) const {
  int nearest = -1;
  double best = band_;
  for (int f = 0; f < 6; ++f) {
    const double d = face_distance(walls_, p, f);
    if (closed_[f] && d < best) best = d, nearest = f;
  }
  return nearest >= 0 && cut_[nearest];
}

FrameData CameraScene::view(const FrameData& frame) const {
  std::vector<std::pair<double, std::uint32_t>> order;
  order.reserve(frame.size());
  std::vector<Projected> projected(frame.size());
  for (std::size_t i = 0; i < frame.size(); ++i) {
    const Vec3 p = position(frame, i);
    if (frame.kind[i] == 1 && hidden_wall(p)) continue;  // a body ([[wall]], kind 2) is never cut away
    projected[i] = projection_(p);
    if (std::isfinite(projected[i].depth))
      order.emplace_back(projected[i].depth, static_cast<std::uint32_t>(i));
  }
  std::sort(order.begin(), order.end());
  FrameData d;
  d.time = frame.time;
  d.dx = frame.dx;
  d.dimension = 3;
  const double span = depth_hi_ - depth_lo_;
  for (const auto& [depth, i] : order) {
    d.x.push_back(static_cast<float>(projected[i].u));
    d.y.push_back(static_cast<float>(projected[i].v));
    d.depth.push_back(static_cast<float>(std::clamp((projected[i].depth - depth_lo_) / span, 0.0, 1.0)));
    d.value.push_back(frame.value[i]);
    d.kind.push_back(frame.kind[i]);
  }
  return d;
}

Slice parse_slice(std::string_view text) {
  const auto eq = text.find('=');
  const std::string_view axis = eq == std::string_view::npos ? text : text.substr(0, eq);
  if (eq == std::string_view::npos || axis.size() != 1 || std::find(axis_names.begin(), axis_names.end(), axis[0]) == axis_names.end())
    throw RenderError(fmt::format("--slice '{}': expected AXIS=VALUE with AXIS x, y or z, e.g. y=0.2", text));
  std::string_view s = text.substr(eq + 1);
  if (!s.empty() && s.front() == '+') s.remove_prefix(1);
  Slice slice;
  slice.axis = static_cast<int>(std::find(axis_names.begin(), axis_names.end(), axis[0]) - axis_names.begin());
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), slice.value);
  if (s.empty() || ec != std::errc() || end != s.data() + s.size() || !std::isfinite(slice.value))
    throw RenderError(fmt::format("--slice '{}': the value must be a position in metres, e.g. {}=0.2", text, axis));
  return slice;
}

double parse_thickness(std::string_view text) {
  double t = 0.0;
  const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), t);
  if (text.empty() || ec != std::errc() || end != text.data() + text.size() || !std::isfinite(t) || !(t > 0.0))
    throw RenderError(fmt::format("--thickness '{}': expected a positive length in metres, e.g. 0.05", text));
  return t;
}

FrameData slice_frame(const FrameData& frame, const Slice& slice) {
  const int a = slice.axis, b = a == 0 ? 1 : 0, c = a == 2 ? 1 : 2;
  const double half = 0.5 * slice.thickness_for(frame.dx);
  FrameData d;
  d.time = frame.time;
  d.dx = frame.dx;
  d.dimension = 2;
  for (std::size_t i = 0; i < frame.size(); ++i) {
    const Vec3 p = position(frame, i);
    if (!(std::abs(p[a] - slice.value) < half)) continue;
    d.x.push_back(static_cast<float>(p[b]));
    d.y.push_back(static_cast<float>(p[c]));
    d.value.push_back(frame.value[i]);
    d.kind.push_back(frame.kind[i]);
  }
  return d;
}

Box slice_box(const Box3& box, int axis) {
  const int b = axis == 0 ? 1 : 0, c = axis == 2 ? 1 : 2;
  return {box.lo[b], box.lo[c], box.hi[b], box.hi[c]};
}

std::string describe(const Slice& slice) {
  return fmt::format("slice {} = {:g} m", axis_names[static_cast<std::size_t>(slice.axis)], slice.value);
}

}  // namespace sluice::render
