// The WCSPH interaction of a particle pair (i, j), written once: a function of the two particles'
// fields and their separation r_ij = x_i - x_j that returns what both receive (Newton's third law:
// the forces are opposite, the continuity terms equal, the density-diffusion flux opposite). T is a
// double or a vector of pairs (core/lanes-inl.hpp); the pair loop (physics/pair_loop-inl.hpp) loads
// the fields, calls it and adds the results, knowing nothing of the physics.
//
// The equations are the pair terms of physics/pair_terms-inl.hpp; the wall treatment `Walls`
// (physics/walls.hpp) says which apply between a fluid and a wall particle.
//
// No include guard and no includes: included inside a namespace that has `simd`, `shape` and `pair`
// for T (see physics/pair_loop-inl.hpp).

// R is the precision of the pair arithmetic and of the fields it reads (ParticleTerms::fields); C the
// type of its constants: doubles, or vectors of R (with<T>(), made once outside the pair loop, so
// that the loop does not convert them from double on every pass).
template <int Dim, class Kernel, class Walls, bool WithArtificialPressure, class R = double, class C = double>
struct WcsphPair {
  using Real = R;

  // What the interaction reads of one particle.
  template <class T>
  struct Side {
    std::array<T, Dim> v;
    std::array<T, Dim> rho_gradient;  // the gradient density diffusion leaves alone
    T rho, inv_rho, p_over_rho2, fluid, tension;
  };

  // What it returns: the force on i (j receives -force), both density rates, and what the time step
  // and the clumping check need, over the pairs that have a fluid particle. The pair loop adds them
  // to the accelerations and the density rates, in that order.
  static constexpr std::size_t kOpposite = Dim, kOwn = 1, kOutputs = kOpposite + kOwn;
  template <class T>
  struct Rates {
    std::array<T, kOpposite> opposite;  // the force on i
    std::array<T, kOwn> to_i, to_j;     // the density rates
    T speed2;                           // |v_ij|^2, or 0 for a wall-wall pair
    T fluid_r2;                         // r^2, or far_r2 for a wall-wall pair
  };

  decltype(std::declval<Kernel>().template as<C>()) kernel;
  C m = 0.0, c0 = 0.0, h = 0.0, mu = 0.0, alpha = 0.0, delta_h_c0 = 0.0;
  C inv_w_dx = 0.0;  // 1 / W(dx), for the artificial pressure
  int ap_n = 0;      // artificial pressure exponent
  C far_r2 = 0.0;    // beyond the support
  C wall_pair_floor = -std::numeric_limits<double>::infinity();  // RateSettings::wall_pair_pressure_floor
  // The particle fields (physics/particle_terms.hpp); a density is rho_base + rho[i].
  std::array<const R*, Dim> v{}, rho_gradient{};
  const R *rho = nullptr, *inv_rho = nullptr, *p_over_rho2 = nullptr, *fluid = nullptr, *tension = nullptr;
  C rho_base = 0.0;

  // The same pair with its constants as T.
  template <class T>
  WcsphPair<Dim, Kernel, Walls, WithArtificialPressure, R, T> with() const {
    const auto c = [](double x) { return simd::opaque(T(x)); };
    WcsphPair<Dim, Kernel, Walls, WithArtificialPressure, R, T> q{kernel.template as<T>()};
    q.kernel.h = c(kernel.h);
    q.kernel.inv_h = c(kernel.inv_h);
    q.kernel.norm = c(kernel.norm);
    q.m = c(m);
    q.c0 = c(c0);
    q.h = c(h);
    q.mu = c(mu);
    q.alpha = c(alpha);
    q.delta_h_c0 = c(delta_h_c0);
    q.inv_w_dx = c(inv_w_dx);
    q.ap_n = ap_n;
    q.far_r2 = c(far_r2);
    q.wall_pair_floor = T(wall_pair_floor);
    q.v = v;
    q.rho_gradient = rho_gradient;
    q.rho = rho;
    q.inv_rho = inv_rho;
    q.p_over_rho2 = p_over_rho2;
    q.fluid = fluid;
    q.tension = tension;
    q.rho_base = c(rho_base);
    return q;
  }

  // The interaction of the run's settings over the particles' fields.
  static WcsphPair of(const Particles<Dim>& p, const RateSettings<Dim>& s, const ParticleTerms& t) {
    const Kernel kernel(s.h);
    WcsphPair pair{kernel};
    pair.m = s.mass;
    pair.c0 = s.eos.sound_speed;
    pair.h = s.h;
    pair.mu = s.viscosity;
    pair.alpha = s.alpha;
    pair.delta_h_c0 = s.delta * s.h * s.eos.sound_speed;
    pair.inv_w_dx = WithArtificialPressure ? 1.0 / kernel.value(s.spacing) : 0.0;
    pair.ap_n = s.artificial_pressure_exponent;
    pair.far_r2 = Kernel::support * Kernel::support * s.h * s.h;
    pair.wall_pair_floor = s.wall_pair_pressure_floor;
    const PairFields<R> f = t.template fields<R>(p);
    for (int d = 0; d < Dim; ++d) {
      pair.v[d] = f.v[d];
      pair.rho_gradient[d] = f.rho_gradient[d];
    }
    pair.rho = f.rho;
    pair.inv_rho = f.inv_rho;
    pair.p_over_rho2 = f.p_over_rho2;
    pair.fluid = f.fluid;
    pair.tension = f.tension;
    pair.rho_base = f.rho_base;
    return pair;
  }

  // One side of a pair, each field read by `load(array)`: a broadcast of particle i, or a load of
  // the candidates j. (Densities are rho - rho_base: their differences are those of rho.)
  template <class T, class Load>
  Side<T> side(Load&& load) const {
    Side<T> s;
    for (int d = 0; d < Dim; ++d) s.v[d] = load(v[d]);
    for (int d = 0; d < Dim; ++d) s.rho_gradient[d] = load(rho_gradient[d]);
    s.rho = load(rho);
    s.inv_rho = load(inv_rho);
    s.p_over_rho2 = load(p_over_rho2);
    s.fluid = load(fluid);
    s.tension = WithArtificialPressure ? load(tension) : T(0.0);
    return s;
  }

  template <class T>
  Rates<T> operator()(const Side<T>& i, const Side<T>& j, const std::array<T, Dim>& r_ij) const {
    std::array<T, Dim> v_ij;
    for (int d = 0; d < Dim; ++d) v_ij[d] = i.v[d] - j.v[d];
    T r2 = r_ij[0] * r_ij[0], v_dot_r = v_ij[0] * r_ij[0], v2 = v_ij[0] * v_ij[0];
    T gradient_dot_r = (i.rho_gradient[0] + j.rho_gradient[0]) * r_ij[0];
    for (int d = 1; d < Dim; ++d) {
      r2 = r2 + r_ij[d] * r_ij[d];
      v_dot_r = v_dot_r + v_ij[d] * r_ij[d];
      gradient_dot_r = gradient_dot_r + (i.rho_gradient[d] + j.rho_gradient[d]) * r_ij[d];
      v2 = v2 + v_ij[d] * v_ij[d];
    }
    const T r = simd::sqrt(r2);
    const T F = shape::gradient_factor(kernel, r, simd::inverse_root(r2, r));
    const T both_fluid = i.fluid * j.fluid;
    const T alpha_ij = Walls::fluid_wall_viscosity ? T(alpha) : both_fluid * alpha;

    // Between a fluid and a wall particle, each side's P/rho^2 is at least wall_pair_floor: 0 where
    // walls cannot hold the water in tension (physics.wall_tension = false: water in tension beside a
    // wall leaves it instead of pulling itself into it), no floor (-inf) otherwise.
    const T floor = simd::select(both_fluid != 0.0, T(-std::numeric_limits<R>::infinity()), T(wall_pair_floor));
    T along_r = pair::pressure(m, simd::max(i.p_over_rho2, floor), simd::max(j.p_over_rho2, floor), F) +
                pair::artificial_viscosity(alpha_ij, c0, h, m, v_dot_r, r2, rho_base + 0.5 * (i.rho + j.rho), F);
    if constexpr (WithArtificialPressure) {
      const T f = shape::value_inside(kernel, r) * inv_w_dx;
      T f_n = 1.0;
      for (int e = 0; e < ap_n; ++e) f_n = f_n * f;
      along_r += pair::artificial_pressure(m, i.tension, j.tension, f_n, F);
    }
    const T along_v = pair::laminar_viscosity(mu, m, i.inv_rho * i.inv_rho, j.inv_rho * j.inv_rho, F);

    Rates<T> out;
    for (int d = 0; d < Dim; ++d) out.opposite[d] = along_r * r_ij[d] + along_v * v_ij[d];
    // rho_j - rho_i of the mean of the two particles' density gradients (the hydrostatic one, or the
    // field's own: physics/density_gradient.hpp), which the diffusion leaves alone.
    const T drho_hydro = -0.5 * gradient_dot_r;
    // The continuity equation sees the walls at rest, as they are: the velocity a wall treatment gives
    // its particles (mDBC's no slip or free slip, physics/mdbc.hpp) is for the viscous terms only.
    T rest_v_dot_r = (i.fluid * i.v[0] - j.fluid * j.v[0]) * r_ij[0];
    for (int d = 1; d < Dim; ++d) rest_v_dot_r = rest_v_dot_r + (i.fluid * i.v[d] - j.fluid * j.v[d]) * r_ij[d];
    const T continuity = pair::continuity(m, F, rest_v_dot_r);
    // Density diffusion acts between fluid particles only.
    const T flux = both_fluid * pair::density_diffusion_flux(delta_h_c0, m, i.rho, j.rho, drho_hydro, F);
    out.to_i[0] = continuity + flux * j.inv_rho;
    out.to_j[0] = continuity - flux * i.inv_rho;
    const T any_fluid = simd::max(i.fluid, j.fluid);
    out.speed2 = any_fluid * v2;
    out.fluid_r2 = simd::select(any_fluid != 0.0, r2, T(far_r2));
    return out;
  }
};
