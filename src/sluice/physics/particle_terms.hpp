// The per-particle terms of the pair loop (P/rho^2, 1/rho, ...), computed once per evaluation
// instead of once per pair, in the precision of the pair arithmetic: doubles, or floats for the
// single-precision pair loop, with float copies of the positions, velocities and densities too.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <type_traits>
#include <vector>

#include "sluice/core/parallel.hpp"
#include "sluice/core/particles.hpp"
#include "sluice/physics/eos.hpp"

namespace sluice {

// What the pair loop reads of every particle, as arrays of R. A particle's density is rho_base +
// rho[i]: in single precision rho holds rho - rho0, so that the small density differences of the
// density diffusion keep their digits (a float of 1000 is exact to 6e-5 kg/m^3 only).
template <class R>
struct PairFields {
  std::array<const R*, 3> x{}, v{};
  std::array<const R*, 3> rho_gradient{};  // the density gradient density diffusion leaves alone
  const R *rho = nullptr, *inv_rho = nullptr, *p_over_rho2 = nullptr, *fluid = nullptr, *tension = nullptr;
  double rho_base = 0.0;
};

struct ParticleTerms {
  // Double precision: the derived terms; positions, velocities and densities are the particles' own.
  std::vector<double> p_over_rho2;  // P / rho^2
  std::vector<double> inv_rho;      // 1 / rho
  // The density gradient the density diffusion does not diffuse: the hydrostatic one, (rho / c^2) g
  // (c^2 = dP/drho), or the renormalised gradient of the density field (physics/density_gradient.hpp).
  std::array<std::vector<double>, 3> rho_gradient;
  std::vector<double> tension;      // artificial pressure R (only filled when it is on)
  std::vector<double> fluid_mask;   // 1 for fluid, 0 for wall (both precisions: shifting reads it)
  // Single precision: all of it, positions relative to `origin` (the middle of the domain, where a
  // float's spacing is smallest), densities as rho - rho0.
  struct Single {
    std::array<std::vector<float>, 3> x, v, rho_gradient;
    std::vector<float> rho_excess, p_over_rho2, inv_rho, tension, fluid;
  } single;
  bool single_precision = false;
  double rest_density = 0.0;

  // `gravity` gives the hydrostatic density gradient (a run with the renormalised one overwrites it:
  // set_rho_gradient).
  template <int Dim>
  void compute(const Particles<Dim>& p, const TaitEos& eos, const std::type_identity_t<Vec<Dim>>& gravity, int threads,
               double artificial_pressure = 0.0, bool single_precision_pairs = false,
               const std::type_identity_t<Vec<Dim>>& origin = {}) {
    single_precision = single_precision_pairs;
    rest_density = eos.rest_density;
    const long n = static_cast<long>(p.size());
    const auto size = static_cast<std::size_t>(n);
    const bool on = artificial_pressure > 0.0;
    fluid_mask.resize(size);
    if (single_precision) {
      for (auto* v : {&single.rho_excess, &single.p_over_rho2, &single.inv_rho, &single.fluid}) v->resize(size);
      single.tension.resize(on ? size : 0);
      for (int d = 0; d < Dim; ++d) {
        single.x[d].resize(size);
        single.v[d].resize(size);
        single.rho_gradient[d].resize(size);
      }
      parallel::for_chunks(n, threads, [&](long begin, long end) {
        for (int d = 0; d < Dim; ++d) {
          const double* __restrict x = p.position[d].data();
          const double* __restrict v = p.velocity[d].data();
          float* __restrict xf = single.x[d].data();
          float* __restrict vf = single.v[d].data();
          const double o = origin[d];
#pragma omp simd
          for (long i = begin; i < end; ++i) {
            xf[i] = static_cast<float>(x[i] - o);
            vf[i] = static_cast<float>(v[i]);
          }
        }
      });
      fill(p, eos, gravity, threads, artificial_pressure, single.p_over_rho2.data(), single.inv_rho.data(),
           single.rho_gradient, single.tension.data(), single.fluid.data(), single.rho_excess.data());
    } else {
      for (auto* v : {&p_over_rho2, &inv_rho}) v->resize(size);
      for (int d = 0; d < Dim; ++d) rho_gradient[d].resize(size);
      tension.resize(on ? size : 0);
      fill(p, eos, gravity, threads, artificial_pressure, p_over_rho2.data(), inv_rho.data(), rho_gradient,
           tension.data(), static_cast<double*>(nullptr), static_cast<double*>(nullptr));
    }
  }

  // Replaces the density gradient of the pair loop's precision with g[d][i] (after compute()).
  template <std::size_t Dim>
  void set_rho_gradient(const std::array<std::vector<double>, Dim>& g, int threads) {
    const long n = static_cast<long>(g[0].size());
    parallel::for_chunks(n, threads, [&](long begin, long end) {
      for (std::size_t d = 0; d < Dim; ++d) {
        const double* __restrict from = g[d].data();
        if (single_precision) {
          float* __restrict to = single.rho_gradient[d].data();
          for (long i = begin; i < end; ++i) to[i] = static_cast<float>(from[i]);
        } else {
          double* __restrict to = rho_gradient[d].data();
          for (long i = begin; i < end; ++i) to[i] = from[i];
        }
      }
    });
  }

  // The arrays of the pair loop of precision R (after compute() in that precision).
  template <class R, int Dim>
  [[nodiscard]] PairFields<R> fields(const Particles<Dim>& p) const {
    PairFields<R> f;
    if constexpr (std::is_same_v<R, float>) {
      for (int d = 0; d < Dim; ++d) {
        f.x[d] = single.x[d].data();
        f.v[d] = single.v[d].data();
        f.rho_gradient[d] = single.rho_gradient[d].data();
      }
      f.rho = single.rho_excess.data();
      f.inv_rho = single.inv_rho.data();
      f.p_over_rho2 = single.p_over_rho2.data();
      f.fluid = single.fluid.data();
      f.tension = single.tension.data();
      f.rho_base = rest_density;
    } else {
      for (int d = 0; d < Dim; ++d) {
        f.x[d] = p.position[d].data();
        f.v[d] = p.velocity[d].data();
        f.rho_gradient[d] = rho_gradient[d].data();
      }
      f.rho = p.density.data();
      f.inv_rho = inv_rho.data();
      f.p_over_rho2 = p_over_rho2.data();
      f.fluid = fluid_mask.data();
      f.tension = tension.data();
    }
    return f;
  }

 private:
  // The derived terms into arrays of R (and, if `excess` is given, rho - rho0 there). One loop per
  // case, so that each is a straight loop the compiler vectorises: gamma = 7 (x^7 by three
  // multiplications, as TaitEos::pressure does) or any gamma (pow), with or without tension.
  // With the hydrostatic density gradient (rho / c^2) g, c^2 = dP/drho = gamma (P + B) / rho.
  template <int Dim, class R>
  void fill(const Particles<Dim>& p, const TaitEos& eos, const std::type_identity_t<Vec<Dim>>& gravity, int threads,
            double artificial_pressure, R* pr, R* ir, std::array<std::vector<R>, 3>& gradient, R* tn, R* fm_r,
            R* excess) {
    const long n = static_cast<long>(p.size());
    const auto run = [&](auto power, auto with_tension, auto with_copies) {
      const double c0_2 = eos.sound_speed * eos.sound_speed;
      const double stiffness = eos.stiffness(), rho0 = eos.rest_density, gamma = eos.gamma;
      const double* __restrict density = p.density.data();
      const Kind* __restrict kind = p.kind.data();
      double* __restrict fm = fluid_mask.data();
      R* __restrict pr_ = pr;
      R* __restrict ir_ = ir;
      std::array<R*, Dim> gr_{};
      for (int d = 0; d < Dim; ++d) gr_[d] = gradient[d].data();
      R* __restrict tn_ = tn;
      R* __restrict fr_ = fm_r;
      R* __restrict ex_ = excess;
      parallel::for_chunks(n, threads, [&](long begin, long end) {
#pragma omp simd
        for (long i = begin; i < end; ++i) {
          const double rho = density[i];
          const double pressure = stiffness * (power(rho / rho0) - 1.0);
          const double inv = 1.0 / rho;
          const double p_rho2 = pressure * inv * inv;
          ir_[i] = static_cast<R>(inv);
          pr_[i] = static_cast<R>(p_rho2);
          const double c2 = gamma * (pressure + stiffness) * inv;
          const double k = rho / std::max(c2, 1e-12 * c0_2);
          for (int d = 0; d < Dim; ++d) gr_[d][i] = static_cast<R>(k * gravity[d]);
          fm[i] = kind[i] == Kind::fluid ? 1.0 : 0.0;
          if constexpr (decltype(with_copies)::value) {
            fr_[i] = static_cast<R>(fm[i]);
            ex_[i] = static_cast<R>(rho - rho0);
          }
          // Monaghan (2000): eps |P|/rho^2 under tension, 0.01 P/rho^2 under compression.
          if constexpr (decltype(with_tension)::value)
            tn_[i] = static_cast<R>(pressure < 0.0 ? -artificial_pressure * p_rho2 : 0.01 * p_rho2);
        }
      });
    };
    const auto seventh = [](double x) {
      const double x2 = x * x;
      return x2 * x2 * x2 * x;
    };
    const auto any_power = [g = eos.gamma](double x) { return std::pow(x, g); };
    const bool on = artificial_pressure > 0.0;
    const auto with = [&](auto power) {
      const auto copies = [&](auto with_tension) {
        if (excess != nullptr) run(power, with_tension, std::true_type{});
        else run(power, with_tension, std::false_type{});
      };
      if (on) copies(std::true_type{});
      else copies(std::false_type{});
    };
    if (eos.gamma == 7.0) with(seventh);
    else with(any_power);
  }
};

}  // namespace sluice
