#include "sluice/geometry/leaks.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "sluice/core/parallel.hpp"
#include "sluice/geometry/near_solids.hpp"

namespace sluice {

using near_solids::Bounded;
using near_solids::bounded;
using near_solids::containing;
using near_solids::in_box;
using near_solids::outward_normal;

template <int Dim>
SolidReach<Dim>::SolidReach(const Solids<Dim>& solids, const Vec<Dim>& lower, const Vec<Dim>& upper, double cell,
                            double reach, std::size_t max_cells)
    : lower_(lower), reach_(reach) {
  if (!(cell > 0.0) || !(reach >= 0.0)) throw std::invalid_argument("SolidReach: the cell size must be positive and the reach not negative");
  const auto cells_of = [&](double size) {
    std::size_t total = 1;
    for (int d = 0; d < Dim; ++d) {
      count_[d] = std::max(1, static_cast<int>(std::ceil((upper[d] - lower[d]) / size)));
      total *= static_cast<std::size_t>(count_[d]);
    }
    return total;
  };
  while (cells_of(cell) > max_cells) cell *= 1.5;
  cell_ = cell;
  inv_cell_ = 1.0 / cell;
  const double half_diagonal = 0.5 * cell * std::sqrt(static_cast<double>(Dim));
  const std::size_t total = cells_of(cell);
  clear_.assign(total, 1);
  for (std::size_t c = 0; c < total; ++c) {
    Vec<Dim> centre{};
    std::size_t rest = c;
    for (int d = 0; d < Dim; ++d) {
      centre[d] = lower_[d] + (static_cast<double>(rest % static_cast<std::size_t>(count_[d])) + 0.5) * cell;
      rest /= static_cast<std::size_t>(count_[d]);
    }
    for (const auto& s : solids) {
      // Outside the solid's bounding box grown by reach plus the half diagonal, the cell is clear of it
      // without asking its distance.
      bool far = false;
      for (int d = 0; d < Dim; ++d)
        far = far || centre[d] < s->lower()[d] - reach - half_diagonal || centre[d] > s->upper()[d] + reach + half_diagonal;
      if (far) continue;
      if (!(s->signed_distance(centre) - half_diagonal > reach)) {
        clear_[c] = 0;
        break;
      }
    }
  }
}

template <int Dim>
void SolidReach<Dim>::update(const std::vector<const Solid<Dim>*>& moving) {
  if (clear_.empty()) return;
  for (const std::size_t c : marked_) clear_[c] = 1;
  marked_.clear();
  const double half_diagonal = 0.5 * cell_ * std::sqrt(static_cast<double>(Dim));
  for (const Solid<Dim>* s : moving) {
    std::array<int, Dim> first{}, last{};
    for (int d = 0; d < Dim; ++d) {
      const double grow = reach_ + half_diagonal;
      first[d] = std::clamp(static_cast<int>(std::floor((s->lower()[d] - grow - lower_[d]) * inv_cell_)), 0, count_[d] - 1);
      last[d] = std::clamp(static_cast<int>(std::floor((s->upper()[d] + grow - lower_[d]) * inv_cell_)), 0, count_[d] - 1);
    }
    std::array<int, Dim> i = first;
    while (true) {
      std::size_t c = 0;
      Vec<Dim> centre{};
      for (int d = Dim - 1; d >= 0; --d) {
        c = c * static_cast<std::size_t>(count_[d]) + static_cast<std::size_t>(i[d]);
        centre[d] = lower_[d] + (i[d] + 0.5) * cell_;
      }
      if (clear_[c] && !(s->signed_distance(centre) - half_diagonal > reach_)) {
        clear_[c] = 0;
        marked_.push_back(c);
      }
      int d = 0;
      while (d < Dim && ++i[d] > last[d]) i[d] = first[d], ++d;
      if (d == Dim) break;
    }
  }
}

template <int Dim>
double SolidReach<Dim>::clear_fraction() const {
  if (clear_.empty()) return 0.0;
  return static_cast<double>(std::count(clear_.begin(), clear_.end(), std::uint8_t{1})) /
         static_cast<double>(clear_.size());
}

namespace {

// The sum of slow(i, x) over the fluid particles in [begin, end) outside `clear`'s cells (and not
// marked in `skip`, if given). The test that passes over the others, most of the water, is a few
// operations a particle, kept in this loop; `slow` is called out of line for the few near a solid.
template <int Dim, class Slow>
long sum_near_solids(const Particles<Dim>& p, long begin, long end, typename SolidReach<Dim>::Lookup clear,
                     const std::uint8_t* skip, Slow&& slow) {
  const Kind* const kind = p.kind.data();
  std::array<const double*, Dim> position;
  for (int d = 0; d < Dim; ++d) position[d] = p.position[d].data();
  long part = 0;
  for (long i = begin; i < end; ++i) {
    Vec<Dim> x;
    for (int d = 0; d < Dim; ++d) x[d] = position[d][i];
    if (kind[i] != Kind::fluid || clear(x) || (skip != nullptr && skip[i])) continue;
    part += slow(i, x);
  }
  return part;
}

template <int Dim>
[[gnu::noinline]] long put_back_one(Particles<Dim>& p, const std::vector<Bounded<Dim>>& boxes, double dx, long i,
                                    Vec<Dim> x) {
  const Solid<Dim>* solid = containing<Dim>(boxes, x);
  if (solid == nullptr) return 0;
  Vec<Dim> v{};
  for (int d = 0; d < Dim; ++d) v[d] = p.velocity[d][i];
  // A few passes: put back across one wall face may land inside an adjoining wall at a corner.
  for (int pass = 0; pass < 4 && solid != nullptr; ++pass) {
    const SurfacePoint<Dim> surface = solid->closest_surface_point(x);
    if (norm(surface.point - x) < 1e-12 * dx) break;  // on the surface already
    x = surface.point + (0.5 * dx) * surface.normal;
    // Reflected relative to the wall, which may move.
    const double vn = dot(solid->moves() ? v - solid->velocity_at(surface.point) : v, surface.normal);
    if (vn < 0.0) v = v - (2.0 * vn) * surface.normal;
    solid = containing<Dim>(boxes, x);
  }
  for (int d = 0; d < Dim; ++d) {
    p.position[d][i] = x[d];
    p.velocity[d][i] = v[d];
  }
  p.needs_density_repair[i] = 1;
  return 1;
}

template <int Dim>
[[gnu::noinline]] long stop_approach_one(const std::array<double*, Dim>& velocity, const std::vector<Bounded<Dim>>& boxes,
                                         double dx, double band,
                                         const typename Particles<Dim>::template Vector<double>* acceleration,
                                         double tau, bool relative, long i, const Vec<Dim>& x) {
  long changed = 0;
  for (const Bounded<Dim>& b : boxes) {
    if (!in_box<Dim>(b, x)) continue;
    const double distance = b.solid->signed_distance(x);
    if (distance >= band) continue;
    const Vec<Dim> wall = relative && b.moving ? b.solid->velocity_at(x) : Vec<Dim>{};
    // The velocity's part towards the surface along `normal`, taken away in full at the surface and
    // less with the distance from it.
    const auto stop = [&](const Vec<Dim>& normal, double from_surface) {
      double un = 0.0;
      for (int d = 0; d < Dim; ++d) {
        const double a = acceleration != nullptr ? (*acceleration)[d][i] : 0.0;
        un += (velocity[d][i] + tau * a - wall[d]) * normal[d];
      }
      if (!(un < 0.0)) return;
      const double f = std::clamp(1.0 - from_surface / band, 0.0, 2.0);
      for (int d = 0; d < Dim; ++d) velocity[d][i] -= f * un * normal[d];
      changed = 1;
    };
    const Vec<Dim> normal = outward_normal<Dim>(*b.solid, x, distance, dx);
    stop(normal, distance);
    // In a corner of a solid that wraps around the water the other face is as near: the velocity
    // into it is stopped too, or the particle slides along the nearest face into the corner.
    if (distance > 0.0 && !b.box)
      b.solid->for_each_face_outside(x, band, [&](const Vec<Dim>& foot, const Vec<Dim>& face_normal) {
        if (dot(face_normal, normal) < 1.0 - 1e-9) stop(face_normal, norm(x - foot));
      });
  }
  return changed;
}

}  // namespace

template <int Dim>
WallChecks<Dim>::WallChecks(const Solids<Dim>& solids, double dx, const SolidReach<Dim>* near_cells)
    : solids_(bounded<Dim>(solids, 0.0)),
      banded_(bounded<Dim>(solids, 0.25 * dx)),
      clear_(near_cells != nullptr ? near_cells->lookup() : typename SolidReach<Dim>::Lookup{}),
      dx_(dx) {
  if (near_cells != nullptr && !(near_cells->reach() >= 0.25 * dx))
    throw std::invalid_argument("the wall checks' clear cells reach less than dx/4 from the walls");
}

template <int Dim>
long WallChecks<Dim>::put_back(Particles<Dim>& p, long begin, long end, const std::uint8_t* skip) const {
  return sum_near_solids<Dim>(p, begin, end, clear_, skip,
                              [&](long i, const Vec<Dim>& x) { return put_back_one<Dim>(p, solids_, dx_, i, x); });
}

template <int Dim>
long WallChecks<Dim>::stop_approach(Particles<Dim>& p, long begin, long end,
                                    const typename Particles<Dim>::template Vector<double>* acceleration,
                                    double tau) const {
  std::array<double*, Dim> velocity{};
  for (int d = 0; d < Dim; ++d) velocity[d] = p.velocity[d].data();
  return sum_near_solids<Dim>(p, begin, end, clear_, nullptr, [&](long i, const Vec<Dim>& x) {
    return stop_approach_one<Dim>(velocity, banded_, dx_, 0.25 * dx_, acceleration, tau, true, i, x);
  });
}

template <int Dim>
long WallChecks<Dim>::stop_shift(const Particles<Dim>& p, const std::array<double*, Dim>& shift_velocity, long begin,
                                 long end) const {
  return sum_near_solids<Dim>(p, begin, end, clear_, nullptr, [&](long i, const Vec<Dim>& x) {
    return stop_approach_one<Dim>(shift_velocity, banded_, dx_, 0.25 * dx_, nullptr, 0.0, false, i, x);
  });
}

namespace {

// f(checks, begin, end) over all particles, in chunks on `threads` threads: the sum of its counts.
template <int Dim, class F>
std::size_t over_chunks(const Particles<Dim>& p, int threads, F&& f) {
  long total = 0;
  parallel::for_chunks(static_cast<long>(p.size()), threads, [&](long begin, long end) {
    const long part = f(begin, end);
#pragma omp atomic
    total += part;
  });
  return static_cast<std::size_t>(total);
}

}  // namespace

template <int Dim>
std::size_t put_back_leaked(Particles<Dim>& p, const Solids<Dim>& solids, double dx, int threads,
                            const SolidReach<Dim>* near) {
  const WallChecks<Dim> checks(solids, dx, near);
  return over_chunks<Dim>(p, threads, [&](long begin, long end) { return checks.put_back(p, begin, end); });
}

template <int Dim>
std::size_t stop_wall_approach(Particles<Dim>& p, const Solids<Dim>& solids, double dx,
                               const typename Particles<Dim>::template Vector<double>* acceleration, double tau,
                               int threads, const SolidReach<Dim>* near) {
  const WallChecks<Dim> checks(solids, dx, near);
  return over_chunks<Dim>(p, threads,
                          [&](long begin, long end) { return checks.stop_approach(p, begin, end, acceleration, tau); });
}

template <int Dim>
std::size_t stop_shift_approach(Particles<Dim>& p, const std::array<double*, Dim>& shift_velocity,
                                const Solids<Dim>& solids, double dx, int threads, const SolidReach<Dim>* near) {
  const WallChecks<Dim> checks(solids, dx, near);
  return over_chunks<Dim>(p, threads,
                          [&](long begin, long end) { return checks.stop_shift(p, shift_velocity, begin, end); });
}

template class WallChecks<2>;
template class WallChecks<3>;
template class SolidReach<2>;
template class SolidReach<3>;
template std::size_t put_back_leaked<2>(Particles<2>&, const Solids<2>&, double, int, const SolidReach<2>*);
template std::size_t put_back_leaked<3>(Particles<3>&, const Solids<3>&, double, int, const SolidReach<3>*);
template std::size_t stop_wall_approach<2>(Particles<2>&, const Solids<2>&, double,
                                           const Particles<2>::Vector<double>*, double, int, const SolidReach<2>*);
template std::size_t stop_wall_approach<3>(Particles<3>&, const Solids<3>&, double,
                                           const Particles<3>::Vector<double>*, double, int, const SolidReach<3>*);
template std::size_t stop_shift_approach<2>(Particles<2>&, const std::array<double*, 2>&, const Solids<2>&, double, int,
                                            const SolidReach<2>*);
template std::size_t stop_shift_approach<3>(Particles<3>&, const std::array<double*, 3>&, const Solids<3>&, double, int,
                                            const SolidReach<3>*);

}  // namespace sluice
