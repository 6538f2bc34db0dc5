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
// Madsen (1971) removes it with X2(t) = H^2/(32 h) (3 cosh kh / sinh^3 kh - 2 / n) sin(2 omega t),
// n = (1 + 2kh / sinh 2kh) / 2.
#pragma once

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

}  // namespace sluice::waves
