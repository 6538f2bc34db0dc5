// The per-particle terms of the pair loop (P/rho^2, 1/rho, ...), computed once per evaluation
// instead of once per pair.
#pragma once

#include <algorithm>
#include <cmath>
#include <type_traits>
#include <vector>

#include "sluice/core/parallel.hpp"
#include "sluice/core/particles.hpp"
#include "sluice/physics/eos.hpp"

namespace sluice {

struct ParticleTerms {
  std::vector<double> p_over_rho2;  // P / rho^2
  std::vector<double> inv_rho;      // 1 / rho
  std::vector<double> hydro_k;      // rho / c^2: d(rho)/d(P) for the hydrostatic density difference
  std::vector<double> fluid_mask;   // 1 for fluid, 0 for wall
  std::vector<double> tension;      // artificial pressure R (only filled when it is on)

  template <int Dim>
  void compute(const Particles<Dim>& p, const TaitEos& eos, int threads, double artificial_pressure = 0.0) {
    const long n = static_cast<long>(p.size());
    for (auto* v : {&p_over_rho2, &inv_rho, &hydro_k, &fluid_mask}) v->resize(static_cast<std::size_t>(n));
    tension.resize(artificial_pressure > 0.0 ? static_cast<std::size_t>(n) : 0);
    // One loop per case, so that each is a straight loop the compiler vectorises: gamma = 7 (x^7 by
    // three multiplications, as TaitEos::pressure does) or any gamma (pow), with or without tension.
    const auto fill = [&](auto power, auto with_tension) {
      const double c0_2 = eos.sound_speed * eos.sound_speed;
      const double stiffness = eos.stiffness(), rho0 = eos.rest_density, gamma = eos.gamma;
      const double* __restrict density = p.density.data();
      const Kind* __restrict kind = p.kind.data();
      double* __restrict pr = p_over_rho2.data();
      double* __restrict ir = inv_rho.data();
      double* __restrict hk = hydro_k.data();
      double* __restrict fm = fluid_mask.data();
      double* __restrict tn = tension.data();
      parallel::for_chunks(n, threads, [&](long begin, long end) {
#pragma omp simd
      for (long i = begin; i < end; ++i) {
        const double rho = density[i];
        const double pressure = stiffness * (power(rho / rho0) - 1.0);
        ir[i] = 1.0 / rho;
        pr[i] = pressure * ir[i] * ir[i];
        // c^2 = dP/drho = gamma (P + B) / rho
        const double c2 = gamma * (pressure + stiffness) * ir[i];
        hk[i] = rho / std::max(c2, 1e-12 * c0_2);
        fm[i] = kind[i] == Kind::fluid ? 1.0 : 0.0;
        // Monaghan (2000): eps |P|/rho^2 under tension, 0.01 P/rho^2 under compression.
        if constexpr (decltype(with_tension)::value)
          tn[i] = pressure < 0.0 ? -artificial_pressure * pr[i] : 0.01 * pr[i];
      }
      });
    };
    const auto seventh = [](double x) {
      const double x2 = x * x;
      return x2 * x2 * x2 * x;
    };
    const auto any_power = [g = eos.gamma](double x) { return std::pow(x, g); };
    const bool on = artificial_pressure > 0.0;
    if (eos.gamma == 7.0) {
      if (on) fill(seventh, std::true_type{});
      else fill(seventh, std::false_type{});
    } else {
      if (on) fill(any_power, std::true_type{});
      else fill(any_power, std::false_type{});
    }
  }
};

}  // namespace sluice
