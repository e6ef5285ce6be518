#pragma once
// A wavemaker's signal: the paddle's displacement X(t) at the still-water level [m] (a piston's position, a
// flap's excursion at the still-water level; a file may give a flap's angle instead) with its first two time
// derivatives, from linear wave theory (wave_theory.hpp) or a laboratory's time series. Pure: built once at
// setup, evaluated once per step and law (never per particle).
//   regular     X = (S/2) sin(omega t + phase) [+ X2 sin(2 omega t + 2 phase), Madsen 1971, piston only]
//   irregular   X = sum_i (a_i / T_i) sin(omega_i t + phi_i), a_i = sqrt(2 S(f_i) df) (JONSWAP), phi_i from a seed
//   focused     the same components with a_i = A S(f_i) / sum_j S(f_j) and phi_i = k_i x_f - omega_i t_f, so that
//               eta = sum_i a_i cos(omega_i (t - t_f) - k_i (x - x_f)) crests at height A at x_f, t_f
//   table       linear interpolation of (t, X) rows (velocity: the segment's slope; acceleration 0)
// T_i = H/S of component i (piston or flap transfer function). A paddle motion X sin(omega t + phi) makes the
// wave eta = (H/2) cos(omega t + phi - k x) (Dean & Dalrymple 1991, section 6.2).
// Ramp-up over Tr: X_r = r X with r = (1 - cos(pi t / Tr)) / 2 for t < Tr, and its product-rule derivatives.
#include <cstdint>
#include <string>
#include <vector>

namespace varsph::waves {

struct PaddleState {
  double q = 0, dq = 0, ddq = 0;  // value, d/dt, d^2/dt^2
};

struct Component {
  double amplitude = 0, omega = 0, phase = 0;  // q += amplitude sin(omega t + phase)
};

// The paddle's kind and the flume's still water: what turns a wave height into a stroke.
struct PaddleGeometry {
  bool flap = false;
  double depth = 0;          // still-water depth h [m]
  double hinge_height = 0;   // flap: hinge height above the bed [m] (negative: below it)
  double g = 9.81;           // [m/s^2]
  double transfer(double k) const;  // H/S at wave number k
};

struct SpectrumSpec {
  double Hs = 0, Tp = 0, gamma = 3.3;
  int components = 256;
  double f_min = 0, f_max = 0;  // [Hz]; 0: 0.5 fp and 3 fp
  std::uint64_t seed = 1;
};

// Regular waves of height H [m], period T [s]; order 2 adds Madsen's correction (piston only).
std::vector<Component> regular_waves(const PaddleGeometry& p, double H, double T, double phase, int order);
// The spectrum's discrete components: frequencies f_i = f_min + (i + 1/2) df and the wave amplitudes a_i.
void spectrum_bins(const SpectrumSpec& s, std::vector<double>& f, std::vector<double>& a, double& df);
// m0 of the discrete spectrum, sum_i S(f_i) df [m^2].
double discrete_m0(const SpectrumSpec& s);
std::vector<Component> irregular_waves(const PaddleGeometry& p, const SpectrumSpec& s);
std::vector<Component> focused_group(const PaddleGeometry& p, const SpectrumSpec& s, double crest, double x_focus,
                                     double t_focus);

class PaddleSignal {
 public:
  PaddleSignal() = default;
  static PaddleSignal sines(std::vector<Component> c);
  // rows (t_k, q_k); throws std::invalid_argument when a time does not increase or a value is not finite
  static PaddleSignal table(std::vector<double> t, std::vector<double> q);
  // reads a CSV file of (time, value) rows (a header line and '#' comments allowed); errors name the line
  static PaddleSignal read_csv(const std::string& path);
  void set_ramp(double duration) { ramp_ = duration; }
  PaddleState at(double t) const;  // t: time since the motion started [s] (t < 0: at rest at q(0) r(0) = 0)
  double max_abs() const;          // an upper bound of |q(t)| over all t
  double ramp() const { return ramp_; }
  const std::vector<Component>& components() const { return comps_; }

 private:
  std::vector<Component> comps_;
  std::vector<double> tt_, tq_;
  double ramp_ = 0;
};

}  // namespace varsph::waves
