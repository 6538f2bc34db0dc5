// Linear (and the piston's second-order) wave-maker theory for regular waves on water of depth h.
//
// Dispersion: omega^2 = g k tanh(k h), solved for k by Newton's method to machine precision.
// Bi\'esel transfer functions (Dean & Dalrymple, "Water Wave Mechanics for Engineers and Scientists",
// 1991, sec. 6.3): the ratio of the wave height H to the paddle's stroke S at the still-water level,
//   piston:  H/S = 4 sinh^2(kh) / (sinh 2kh + 2kh),
//   flap hinged a height l above the floor, d = h - l of it under water:
//            H/S = 4 sinh(kh) / (sinh 2kh + 2kh) * [sinh(kh) + (cosh(k l) - cosh(kh)) / (k d)],
// from the paddle's displacement profile (uniform; zero below the hinge and growing linearly to S/2
// at the surface). A piston driven by X1(t) = S/2 sin(omega t) also makes a free second harmonic;
// Madsen's (1971) second-order motion removes it. With X positive towards the water it is
//   X2(t) = H^2/(32 h) (2 / n - 3 cosh kh / sinh^3 kh) sin(2 omega t),  n = (1 + 2kh / sinh 2kh) / 2:
// with the bracket's sign the other way, (3 cosh kh / sinh^3 kh - 2 / n), the piston's second
// harmonic adds to the free wave of the first-order motion instead of cancelling it (docs/waves.md,
// "Second-order generation", measured with gauges every 0.15 m).
//
// Irregular waves: a JONSWAP spectrum (Hasselmann et al. 1973) in the form Goda (1988) writes it, in
// the frequency f (Hz) with the peak frequency fp = 1/Tp,
//   S(f) = C f^-5 exp(-1.25 (fp/f)^4) gamma^exp(-(f/fp - 1)^2 / (2 sigma^2)),
//   sigma = 0.07 for f <= fp, 0.09 above,
// with C set so that the discretised spectrum's zeroth moment m0 gives 4 sqrt(m0) = Hs exactly (in
// place of Goda's fitted constant, which holds to about 1 %). It is discretised in equal bins of width
// df = fp / M, M = round(N / 2.5), at the frequencies j df, j = j0 ... j0 + N - 1, j0 = round(M / 2):
// N components from fp/2 to about 3 fp, fp itself one of them. Each has the amplitude
// a_j = sqrt(2 S(f_j) df) (deterministic amplitudes) and a phase drawn from the seed (below); all
// frequencies being multiples of df, the sea repeats exactly every 1/df = M Tp.
#pragma once

#include <cstdint>
#include <vector>

namespace sluice::waves {

inline constexpr double kGravity = 9.81;

// The wavenumber k (rad/m) of a wave of angular frequency omega (rad/s) on depth h (m): the root of
// omega^2 = g k tanh(k h). Throws std::invalid_argument unless omega, h and g are positive.
double wavenumber(double omega, double depth, double g = kGravity);

// H/S of a piston.
double piston_height_per_stroke(double kh);
// H/S of a flap hinged at `hinge` (m above the floor) on depth h, k the wavenumber; hinge = 0 is a
// flap hinged at the floor.
double flap_height_per_stroke(double k, double depth, double hinge);
// The amplitude of Madsen's second-order correction to a piston's motion, X2 above (m), for a wave of
// height H on depth h with wavenumber k.
double madsen_second_order_amplitude(double height, double k, double depth);

// A regular wave's figures, for the set-up's report and its warnings.
struct RegularWave {
  double height = 0.0, period = 0.0, depth = 0.0;
  double k = 0.0, wavelength = 0.0, kh = 0.0, steepness = 0.0;  // steepness H/L
  double celerity = 0.0, group_velocity = 0.0;
  double miche_steepness = 0.0;   // the breaking limit H/L = 0.142 tanh(kh) (Miche 1944)
  double ursell = 0.0;            // H L^2 / h^3
};
RegularWave regular_wave(double height, double period, double depth, double g = kGravity);

// The JONSWAP spectrum's shape at f for the peak frequency fp: S(f) / C above (C = 1), in s^5.
double jonswap_shape(double f, double fp, double gamma);

// One component of an irregular sea: the surface elevation a cos(2 pi f t + phase) at the paddle.
struct WaveComponent {
  double frequency = 0.0;  // Hz
  double amplitude = 0.0;  // m
  double phase = 0.0;      // rad, in [0, 2 pi)
};

// An irregular sea discretised from a spectrum.
struct IrregularSea {
  std::vector<WaveComponent> components;  // in increasing frequency
  double df = 0.0;             // the bins' width (Hz): the sea repeats every 1/df
  double peak_frequency = 0.0;
  double band_share = 0.0;     // the share of the continuous spectrum's m0 (over all f) in the band
                               // [f_first - df/2, f_last + df/2]; the normalisation gives the band the rest
};

// N = `components` components of a JONSWAP sea of significant height Hs (m), peak period Tp (s) and
// peak enhancement gamma, discretised as above. The phases come from the raw output of
// std::mt19937_64 seeded with `seed` (an engine the standard specifies to the bit, unlike its
// distributions): one draw u per component in increasing frequency, phase = 2 pi (u >> 11) 2^-53,
// so that a seed gives the same sea on every platform. Throws std::invalid_argument unless Hs, Tp
// are positive, gamma >= 1 and components >= 1.
IrregularSea jonswap_sea(double significant_height, double peak_period, double gamma, int components,
                         std::uint64_t seed);

// The zeroth moment m0 = sum a^2 / 2 of a sea (m^2): 4 sqrt(m0) is its significant height.
double zeroth_moment(const IrregularSea& sea);

// The share of a sea's m0 in components whose wavelength on depth h is at least `shortest` (m).
double share_longer_than(const IrregularSea& sea, double shortest, double depth, double g = kGravity);

}  // namespace sluice::waves
