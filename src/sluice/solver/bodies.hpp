// The bodies of a run and the walls that move. Body 1 is the tank's own walls, body k + 2 the case's
// [[wall]] number k (core/particles.hpp, body_id); a wall with a translation or rotation law moves as
// its RigidMotion (case/motions.hpp) says. Each moving body keeps its particles' positions at the start
// pose, by id, and places them at any time from those: a particle's position at time t is a function
// of t alone (no sum of small steps), so a restart, another thread count or another process count
// places it to the same bits. Its shape is a MovingSolid, so that the leak put-back, the wall-approach
// stop and the wall friction see it where it is.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "sluice/case/case.hpp"
#include "sluice/case/case_error.hpp"
#include "sluice/case/rigid_motion.hpp"
#include "sluice/core/parallel.hpp"
#include "sluice/core/particles.hpp"
#include "sluice/geometry/setup.hpp"
#include "sluice/geometry/floating_body.hpp"
#include "sluice/geometry/mass_properties.hpp"
#include "sluice/geometry/motion.hpp"
#include "sluice/geometry/wave_theory.hpp"
#include "sluice/geometry/moving_solid.hpp"
#include "sluice/geometry/solid.hpp"
#include "sluice/physics/wall_motion.hpp"

namespace sluice {

template <int Dim>
class Bodies {
 public:
  struct Body {
    std::string name;
    std::uint8_t id = 0;
    bool moves = false;
    RigidMotion<Dim> motion;                      // when it moves
    std::shared_ptr<MovingSolid<Dim>> solid;      // when it moves: its shape at the current pose
    std::uint32_t first_id = 0;                   // its particles' ids run from first_id, contiguous
    std::vector<Vec<Dim>> start;                  // when it moves: their positions at the start pose
    // An absorbing piston: where the vertical line it measures the surface on stands at the start
    // (on the floor, motion.gauge_distance in front of its face), and the still water's depth.
    Vec<Dim> gauge_foot{};
    double depth = 0.0;
    // A floating body ([wall.floating]): moved by its dynamics, not by laws.
    bool floats = false;
    FloatingBody floating;
    double friction = 0.0;  // its contacts' Coulomb coefficient
  };

  // A floating body's contacts: the force (N; N/m in 2D) and moment about its centre of gravity that
  // the other solids exert on it where its particles come closer to them than half a spacing.
  struct ContactLoad {
    Vec3 force{}, moment{};
    int points = 0;
  };

  Bodies() = default;

  // `built`: the particles the case's set-up made (ids 0..n-1, in that order); `solids`: its solids,
  // the walls' the last c.walls.size() of them, in order. A moving wall's solid is replaced there by
  // its MovingSolid.
  Bodies(const Case& c, const Particles<Dim>& built, Solids<Dim>& solids) {
    const std::size_t walls = c.walls.size();
    bodies_.resize(body_id::first_wall + walls);
    bodies_[body_id::water].name = "water";
    bodies_[body_id::tank].name = "tank";
    for (std::size_t b = 0; b < bodies_.size(); ++b) bodies_[b].id = static_cast<std::uint8_t>(b);
    motion_.moving.assign(bodies_.size(), 0);
    contact_reach_ = 0.5 * c.dx;
    motion_.state.assign(bodies_.size(), BodyState<Dim>{});
    motion_.lower.assign(bodies_.size(), Vec<Dim>{});
    motion_.upper.assign(bodies_.size(), Vec<Dim>{});
    if (c.tank_moves()) {
      // The tank's walls: one solid, the set-up's first (geometry/tank_walls.hpp).
      Body& body = bodies_[body_id::tank];
      Region tank;
      tank.translation = c.tank_translation;
      tank.rotation = c.tank_rotation;
      body.moves = true;
      body.motion = rigid_motion_of<Dim>(tank);
      body.solid = std::make_shared<MovingSolid<Dim>>(solids.front());
      solids.front() = body.solid;
      motion_.moving[body.id] = 1;
      motion_.any = true;
    }
    for (std::size_t k = 0; k < walls; ++k) {
      Body& body = bodies_[body_id::first_wall + k];
      const Region& wall = c.walls[k];
      body.name = wall.name;
      if (!wall.moves()) continue;
      body.moves = true;
      if (wall.floats) {
        body.floats = true;
        body.floating = FloatingBody(floating_model(wall.floating, mass_properties(wall, Dim), Dim, c.gravity),
                                     wall.floating);
        body.friction = wall.floating.friction;
      } else {
        // An absorbing piston measures the surface a kernel support and a spacing in front of its
        // face, where the water's kernel sum is not cut by the piston's own particles.
        const double g = norm(c.gravity) > 0.0 ? norm(c.gravity) : waves::kGravity;
        body.motion = rigid_motion_of<Dim>(wall, g, 2.0 * c.smoothing_length() + c.dx);
        body.depth = wall.translation.depth;
      }
      std::shared_ptr<const Solid<Dim>>& shape = solids[solids.size() - walls + k];
      body.solid = std::make_shared<MovingSolid<Dim>>(shape);
      shape = body.solid;
      motion_.moving[body.id] = 1;
      motion_.any = true;
    }
    if (!motion_.any) return;
    // The start positions of each moving body's particles, whose ids the set-up gave in one run.
    std::vector<std::uint8_t> seen(bodies_.size(), 0);
    for (std::size_t i = 0; i < built.size(); ++i) {
      Body& body = bodies_[built.body[i]];
      if (!body.moves) continue;
      if (!seen[body.id]) body.first_id = built.id[i], seen[body.id] = 1;
      if (built.id[i] != body.first_id + body.start.size())
        throw std::logic_error("Bodies: a moving body's particles are not numbered in one run");
      Vec<Dim> x{};
      for (int d = 0; d < Dim; ++d) x[d] = built.position[d][i];
      body.start.push_back(x);
    }
    for (Body& body : bodies_) {
      if (!body.motion.absorber || body.start.empty()) continue;
      // The face: the furthest particle along the direction, half a spacing further; the line stands
      // in front of it, across from the piston's centre, on the floor.
      const Vec<Dim>& dir = body.motion.direction;
      Vec<Dim> centre{};
      double face = -std::numeric_limits<double>::infinity();
      for (const Vec<Dim>& x : body.start) {
        centre = centre + (1.0 / static_cast<double>(body.start.size())) * x;
        face = std::max(face, dot(x, dir));
      }
      face += 0.5 * c.dx;
      body.gauge_foot = centre + (face + body.motion.gauge_distance - dot(centre, dir)) * dir;
      body.gauge_foot[Dim - 1] = 0.0;
    }
  }

  // Whether a body is an absorbing piston, which the solver feeds with the surface in front of it.
  [[nodiscard]] bool absorbs() const {
    return std::any_of(bodies_.begin(), bodies_.end(), [](const Body& b) { return b.motion.absorber != nullptr; });
  }
  // Each absorbing piston observes the surface at time t (the bodies' time): `level(point)` gives the
  // free surface's height on the vertical line from `point` up (every process calls it alike).
  template <class Level>
  void absorb(double t, Level&& level) {
    for (Body& body : bodies_) {
      if (!body.motion.absorber) continue;
      const Vec<Dim> foot = body.gauge_foot + motion_.state[body.id].displacement;
      const double h = level(foot);
      // No water on the line (the surface not found): nothing to correct by.
      if (h > 0.0) body.motion.absorber->observe(t, h - body.depth);
    }
  }
  // The absorbing pistons' states, in body order (AbsorbingLaw::state_size values each), for a
  // checkpoint; and their restoration.
  [[nodiscard]] std::vector<double> absorber_state() const {
    std::vector<double> v;
    for (const Body& body : bodies_) {
      if (!body.motion.absorber) continue;
      const auto a = body.motion.absorber->packed();
      v.insert(v.end(), a.begin(), a.end());
    }
    return v;
  }
  void set_absorber_state(const std::vector<double>& v) {
    std::size_t n = 0;
    for (const Body& body : bodies_) n += body.motion.absorber ? 1 : 0;
    if (v.size() != n * AbsorbingLaw::state_size)
      throw CaseError(fmt::format("the saved state holds {} values for the absorbing pistons, where the case's {} "
                                  "absorbing piston{} need {}",
                                  v.size(), n, n == 1 ? "" : "s", n * AbsorbingLaw::state_size));
    std::size_t k = 0;
    for (Body& body : bodies_) {
      if (!body.motion.absorber) continue;
      body.motion.absorber->unpack(v.data() + k);
      k += AbsorbingLaw::state_size;
    }
  }

  // The contacts of each floating body (in body order) with the other solids of `solids` (the
  // set-up's, the walls' the last `walls` of them, a floating wall's its MovingSolid) at the bodies'
  // current poses. A particle of a floating body whose centre is closer than dx/2 to another solid's
  // surface (the body's surface, half a spacing beyond its outer particles, then touches it) by
  // delta = dx/2 - d is pushed out along that surface's normal n by
  //   F_n = max(0, k delta - c (u . n)),     F_t = -min(mu F_n, c |u_t|) u_t / |u_t|,
  // u the particle's velocity relative to the solid's surface there: k = `stiffness` per particle (the
  // water's own stiffness at a particle, rho0 c0^2 dx^(Dim-2), which the time step already resolves),
  // c = sqrt(k M / n) for the body's mass M shared by its n points in contact (half the critical
  // damping of each), mu the body's friction. Between two floating bodies each point of either is
  // tested against the other, and each body receives the reaction of the forces it exerts. A function
  // of the poses alone: every process computes it alike.
  [[nodiscard]] std::vector<ContactLoad> contact_loads(const Solids<Dim>& solids, std::size_t walls, double dx,
                                                       double stiffness) const {
    std::vector<ContactLoad> loads(bodies_.size());
    const double reach = 0.5 * dx;
    const std::size_t first_wall = solids.size() - walls;
    const auto apart = [&](const Solid<Dim>& a, const Solid<Dim>& s) {
      for (int d = 0; d < Dim; ++d)
        if (a.lower()[d] > s.upper()[d] + reach || a.upper()[d] < s.lower()[d] - reach) return true;
      return false;
    };
    const auto add = [&](std::size_t b, const Vec<Dim>& at, const Vec3& f) {
      const BodyState<Dim>& s = motion_.state[b];
      Vec3 r{}, force = f;
      for (int d = 0; d < Dim; ++d) r[d] = at[d] - s.centre[d] - s.displacement[d];
      loads[b].force = loads[b].force + force;
      loads[b].moment = loads[b].moment + Vec3{r[1] * f[2] - r[2] * f[1], r[2] * f[0] - r[0] * f[2], r[0] * f[1] - r[1] * f[0]};
    };
    for (const Body& body : bodies_) {
      if (!body.floats) continue;
      const Solid<Dim>& own = *body.solid;
      // Its points in contact, with what they push against: found first, to share the damping.
      struct Touch {
        Vec<Dim> at, normal, relative;
        double depth;
        std::size_t other;  // the other body's id
      };
      std::vector<Touch> touches;
      for (std::size_t k = 0; k < solids.size(); ++k) {
        const Solid<Dim>& other = *solids[k];
        if (&other == &own || apart(own, other)) continue;
        // The other body's id: a wall's, or the tank's (its slabs and its moving walls are body 1).
        const std::size_t other_id = k >= first_wall ? body_id::first_wall + (k - first_wall) : body_id::tank;
        // A pair of floating bodies is taken once, from the lower id, each side's points tested.
        const bool both_float = other_id < bodies_.size() && bodies_[other_id].floats;
        if (both_float && other_id < body.id) continue;
        // The points of `mover` against `against`; the reaction goes to `reacting` if it floats.
        const auto test = [&](const Body& mover, const Solid<Dim>& against, std::size_t reacting, bool flip) {
          for (const Vec<Dim>& start : mover.start) {
            const PointMotion<Dim> m = point_motion<Dim>(motion_.state[mover.id], start);
            bool near = true;
            for (int d = 0; d < Dim; ++d)
              near = near && m.position[d] > against.lower()[d] - reach && m.position[d] < against.upper()[d] + reach;
            if (!near) continue;
            const double distance = against.signed_distance(m.position);
            if (!(distance < reach)) continue;
            const SurfacePoint<Dim> surface = against.closest_surface_point(m.position);
            const Vec<Dim> normal = surface.normal;  // outward: inside the solid, the way out
            const Vec<Dim> relative = m.velocity - against.velocity_at(m.position);
            Touch t{m.position, normal, relative, reach - distance, reacting};
            if (flip) {
              // A point of the other floating body pressing into this one: the force on this body is
              // the reaction, at the same point, along -n.
              t.normal = -1.0 * normal;
              t.relative = -1.0 * relative;
            }
            touches.push_back(t);
          }
        };
        test(body, other, other_id, false);
        if (both_float) test(bodies_[other_id], own, other_id, true);
      }
      if (touches.empty()) continue;
      const double mass = body.floating.model().mass;
      const double damping = std::sqrt(stiffness * mass / static_cast<double>(touches.size()));
      for (const Touch& t : touches) {
        const double un = dot(t.relative, t.normal);
        const double fn = std::max(0.0, stiffness * t.depth - damping * un);
        Vec<Dim> f = fn * t.normal;
        const Vec<Dim> ut = t.relative - un * t.normal;
        const double speed = norm(ut);
        if (body.friction > 0.0 && speed > 0.0) f = f - (std::min(body.friction * fn, damping * speed) / speed) * ut;
        Vec3 f3{};
        for (int d = 0; d < Dim; ++d) f3[d] = f[d];
        add(body.id, t.at, f3);
        loads[body.id].points += 1;
        if (t.other < bodies_.size() && bodies_[t.other].floats) add(t.other, t.at, -1.0 * f3);
      }
    }
    return loads;
  }

  // Boxes that hold everywhere a floating body may go: the tank's inside grown by `margin`, and above
  // an open tank as far again as the body's size (where the cell grid must reach).
  [[nodiscard]] Solids<Dim> floating_extent(double margin, const Vec3& tank, bool lid) const {
    Solids<Dim> boxes;
    for (const Body& body : bodies_) {
      if (!body.floats) continue;
      Vec<Dim> lo = body.solid->lower(), hi = body.solid->upper();
      const double size = norm(hi - lo);
      for (int d = 0; d < Dim; ++d) {
        lo[d] = std::min(lo[d], 0.0) - margin;
        hi[d] = std::max(hi[d], tank[d]) + margin + (d == Dim - 1 && !lid ? size : 0.0);
      }
      boxes.push_back(box_solid<Dim>(lo, hi));
    }
    return boxes;
  }
  // The floating bodies' solids where they are now.
  [[nodiscard]] std::vector<const Solid<Dim>*> floating_solids() const {
    std::vector<const Solid<Dim>*> solids;
    for (const Body& body : bodies_)
      if (body.floats) solids.push_back(body.solid.get());
    return solids;
  }

  // Whether a body floats; f(body) for each floating one.
  [[nodiscard]] bool floats() const {
    return std::any_of(bodies_.begin(), bodies_.end(), [](const Body& b) { return b.floats; });
  }
  template <class F>
  void each_floating(F&& f) {
    for (Body& body : bodies_)
      if (body.floats) f(body);
  }
  // The floating bodies' states, in body order (FloatingState::packed_size values each), for the
  // clock and a checkpoint; and their restoration (the walls follow at the next set_time).
  [[nodiscard]] std::vector<double> floating_state() const {
    std::vector<double> v;
    for (const Body& body : bodies_) {
      if (!body.floats) continue;
      const auto a = body.floating.packed();
      v.insert(v.end(), a.begin(), a.end());
    }
    return v;
  }
  void set_floating_state(const std::vector<double>& v) {
    std::size_t n = 0;
    for (const Body& body : bodies_) n += body.floats ? 1 : 0;
    if (v.empty() && n > 0) return;  // a fresh start: the bodies' own start states
    if (v.size() != n * FloatingState::packed_size)
      throw CaseError(fmt::format("the saved state holds {} values for the floating bodies, where the case's {} "
                                  "floating bod{} need {}",
                                  v.size(), n, n == 1 ? "y" : "ies", n * FloatingState::packed_size));
    std::size_t k = 0;
    for (Body& body : bodies_) {
      if (!body.floats) continue;
      body.floating.unpack(v.data() + k);
      k += FloatingState::packed_size;
    }
  }

  [[nodiscard]] bool any_moving() const { return motion_.any; }
  [[nodiscard]] const WallMotion<Dim>& motion() const { return motion_; }
  [[nodiscard]] const std::vector<Body>& list() const { return bodies_; }
  [[nodiscard]] double time() const { return time_; }

  // The moving bodies' states at time t, and their solids' poses.
  void set_time(double t) {
    time_ = t;
    for (Body& body : bodies_) {
      if (!body.moves) continue;
      motion_.state[body.id] = body.floats ? body.floating.template pose<Dim>() : body_state<Dim>(body.motion, t);
      body.solid->set_state(motion_.state[body.id]);
      motion_.lower[body.id] = body.solid->lower();
      motion_.upper[body.id] = body.solid->upper();
    }
  }

  // Where the body point that was at `start` is now.
  [[nodiscard]] Vec<Dim> carried(std::uint8_t body, const Vec<Dim>& start) const {
    return point_motion<Dim>(motion_.state[body], start).position;
  }
  // A moving body's particle's position at the start pose.
  [[nodiscard]] const Vec<Dim>& start_position(std::uint8_t body, std::uint32_t id) const {
    const Body& b = bodies_[body];
    return b.start[id - b.first_id];
  }

  // The positions and velocities of the moving bodies' particles among p, at the current time.
  void place(Particles<Dim>& p, int threads) const {
    if (!motion_.any) return;
    parallel::for_chunks(static_cast<long>(p.size()), threads, [&](long begin, long end) {
      for (long i = begin; i < end; ++i) {
        const std::uint8_t b = p.body[i];
        if (!motion_.moves(b)) continue;
        const PointMotion<Dim> m = point_motion<Dim>(motion_.state[b], start_position(b, p.id[i]));
        for (int d = 0; d < Dim; ++d) {
          p.position[d][i] = m.position[d];
          p.velocity[d][i] = m.velocity[d];
        }
      }
    });
  }

  // Throws CaseError if a moving body's shape leaves the tank's inside at a time up to `end` (found
  // by sampling its bounds at 2000 times): through the floor, a side wall, or the lid (over an open
  // tank it may rise). `size`: the tank's inside.
  void check_inside_tank(double end, const Vec3& size, bool lid) const {
    constexpr int samples = 2000;
    for (const Body& body : bodies_) {
      if (!body.moves || body.id == body_id::tank) continue;
      MovingSolid<Dim> solid(std::shared_ptr<const Solid<Dim>>(body.solid, &body.solid->shape()));
      // A floating body goes where the water takes it: it must start inside.
      for (int s = 0; s <= (body.floats ? 0 : samples); ++s) {
        const double t = end * s / samples;
        solid.set_state(body.floats ? body.floating.template pose<Dim>() : body_state<Dim>(body.motion, t));
        Vec<Dim> lo = solid.lower(), hi = solid.upper();
        grow_by_correction(body, lo, hi);
        const Exit exit = exit_of(body, lo, hi, size, lid);
        const std::string absorbing =
            body.motion.absorber
                ? fmt::format("; an absorbing piston may move up to its absorption_limit ({:.4g} m) beyond its "
                              "target's motion: give it that room or set a smaller absorption_limit",
                              body.motion.absorber->limit())
                : "";
        if (!exit.what.empty() && body.floats)
          throw CaseError(fmt::format("{} at the start ({}): a floating body must start inside the tank", exit.what,
                                      exit.where));
        if (!exit.what.empty())
          throw CaseError(fmt::format("{} at t = {:.4g} s ({}): a moving wall must stay inside the tank until "
                                      "time.end = {:.4g} s{}{}",
                                      exit.what, t, exit.where, end, exit.hint, absorbing));
      }
    }
  }

  // The first moving body whose shape is outside the tank's inside now, said as check_inside_tank
  // says it ("wall 1 (gate) leaves the tank through the floor (its bounds reach ...)"); empty when
  // every body is inside. The instability guard's check of the walls (Solver::check_health): the
  // set-up's samples may miss a motion faster than them.
  [[nodiscard]] std::string outside_tank(const Vec3& size, bool lid) const {
    for (const Body& body : bodies_) {
      if (!body.moves || body.id == body_id::tank) continue;
      // A floating body in contact with the tank presses into it by a little: up to half a spacing.
      const Exit exit = exit_of(body, body.solid->lower(), body.solid->upper(), size, lid, body.floats ? contact_reach_ : 0.0);
      if (!exit.what.empty()) return fmt::format("{} ({}){}", exit.what, exit.where, exit.hint);
    }
    return "";
  }

  // Throws CaseError if a moving wall and another wall overlap at the start: a wall particle of one
  // strictly inside the other's shape (`solids`, the set-up's, the walls' the last ones in order). Walls
  // may touch (a gate standing on the floor); fixed walls may overlap each other as before.
  void check_apart(const Particles<Dim>& built, const Solids<Dim>& solids, const std::vector<Region>& walls) const {
    if (!motion_.any) return;
    const std::size_t first = solids.size() - walls.size();
    for (std::size_t i = 0; i < built.size(); ++i) {
      const std::uint8_t a = built.body[i];
      if (a < body_id::first_wall) continue;
      Vec<Dim> x{};
      for (int d = 0; d < Dim; ++d) x[d] = built.position[d][i];
      for (std::size_t k = 0; k < walls.size(); ++k) {
        const auto b = static_cast<std::uint8_t>(body_id::first_wall + k);
        if (b == a || !(motion_.moves(a) || motion_.moves(b))) continue;
        const Solid<Dim>& other = *solids[first + k];
        if (!other.contains(x) || other.signed_distance(x) > -1e-9) continue;
        std::string at;
        for (int d = 0; d < Dim; ++d) at += fmt::format("{}{:.4g}", d ? ", " : "", x[d]);
        throw CaseError(fmt::format(
            "walls {} ({}) and {} ({}) overlap at the start: a particle of {} at ({}) m lies inside {}; a moving "
            "wall and another wall must start apart (they may touch)",
            a - body_id::first_wall + 1, bodies_[a].name, k + 1, bodies_[b].name, bodies_[a].name, at,
            bodies_[b].name));
      }
    }
  }

  // Boxes that hold everything each moving body's shape covers over the run (sampled, and grown by
  // the most a sample's bounds moved from the one before plus `margin`): where the leak and friction
  // checks must look, and where the cell grid must reach.
  [[nodiscard]] Solids<Dim> swept(double end, double margin) const {
    Solids<Dim> boxes;
    constexpr int samples = 2000;
    for (const Body& body : bodies_) {
      if (!body.moves || body.floats) continue;
      // Up to when its laws settle, where they do, so that the box (and the grid that covers it) is
      // the same for a run and its restart with a later end.
      const double settled = settled_after(body.motion);
      const double until = std::isfinite(settled) ? std::max(settled, 1e-9) : end;
      MovingSolid<Dim> solid(std::shared_ptr<const Solid<Dim>>(body.solid, &body.solid->shape()));
      Vec<Dim> lo{}, hi{}, last_lo{}, last_hi{};
      double jump = 0.0;
      for (int s = 0; s <= samples; ++s) {
        solid.set_state(body_state<Dim>(body.motion, until * s / samples));
        const Vec<Dim> l = solid.lower(), u = solid.upper();
        for (int d = 0; d < Dim; ++d) {
          if (s > 0) jump = std::max({jump, std::abs(l[d] - last_lo[d]), std::abs(u[d] - last_hi[d])});
          lo[d] = s == 0 ? l[d] : std::min(lo[d], l[d]);
          hi[d] = s == 0 ? u[d] : std::max(hi[d], u[d]);
        }
        last_lo = l;
        last_hi = u;
      }
      for (int d = 0; d < Dim; ++d) {
        lo[d] -= jump + margin;
        hi[d] += jump + margin;
      }
      grow_by_correction(body, lo, hi);
      boxes.push_back(box_solid<Dim>(lo, hi));
    }
    return boxes;
  }

 private:
  // How a body whose shape spans [lo, hi] leaves the tank's inside `size` (an open tank lets a wall
  // rise): which wall and through what, where its bounds reach, and a hint; `what` empty if inside.
  struct Exit {
    std::string what, where, hint;
  };
  // An absorbing piston may stand up to its correction's limit from where its target puts it, along
  // its direction: the bounds [lo, hi] of its target's pose grown by as much.
  static void grow_by_correction(const Body& body, Vec<Dim>& lo, Vec<Dim>& hi) {
    if (!body.motion.absorber) return;
    for (int d = 0; d < Dim; ++d) {
      const double reach = body.motion.absorber->limit() * std::abs(body.motion.direction[d]);
      lo[d] -= reach;
      hi[d] += reach;
    }
  }
  static Exit exit_of(const Body& body, const Vec<Dim>& lo, const Vec<Dim>& hi, const Vec3& size, bool lid,
                      double allowed = 0.0) {
    constexpr int up = Dim - 1;
    const double slack = 1e-9 * (1.0 + size[0]) + allowed;
    for (int d = 0; d < Dim; ++d) {
      const bool below = lo[d] < -slack, above = hi[d] > size[d] + slack && (d != up || lid);
      if (!below && !above) continue;
      const char* side = d == up ? (below ? "through the floor" : "through the lid (tank.lid = true)")
                                 : (below ? "through the wall at the low end of " : "through the wall at the high end of ");
      return {fmt::format("wall {} ({}) leaves the tank {}{}", body.id - body_id::first_wall + 1, body.name, side,
                          d == up ? "" : std::string(1, "xyz"[d])),
              fmt::format("its bounds reach {} = {:.4g} m, the tank's inside spans 0 to {:.4g} m", "xyz"[d],
                          below ? lo[d] : hi[d], size[d]),
              d == up && !below ? "; an open tank (tank.lid = false) lets it rise out of the water" : ""};
    }
    return {};
  }

  std::vector<Body> bodies_;
  WallMotion<Dim> motion_;
  double contact_reach_ = 0.0;  // half a spacing: how close a floating body's particles come to a solid
  double time_ = 0.0;
};

}  // namespace sluice
