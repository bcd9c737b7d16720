#pragma once
// A periodic scalar time series Q(t) or P(t): samples over one period, repeated, with smooth
// (C2 periodic cubic spline) interpolation; or a constant.
#include <complex>
#include <filesystem>
#include <string>
#include <vector>

namespace tearflow::bc {

class Waveform {
public:
  /// A constant value (no period).
  static Waveform constant(double value);
  /// Samples (t_i, v_i) over one period, t strictly increasing. When t_last equals
  /// t_first + period the last sample closes the period and is dropped (its value should
  /// repeat the first). Throws InputError naming `where` on non-monotone time, fewer than
  /// three samples, or a period shorter than the sampled span.
  static Waveform periodic(std::vector<double> t, std::vector<double> v, double period,
                           const std::string& where);

  double operator()(double t) const;        ///< value at time t (periodic repetition)
  double derivative(double t) const;        ///< dv/dt at time t
  double period() const { return period_; } ///< 0 for a constant
  bool is_constant() const { return t_.empty(); }
  double mean() const; ///< mean over one period (exact for the spline)
  /// Complex Fourier coefficients c_n, n = 0..modes-1, of the interpolant over one period:
  /// v(t) = Re( c_0 + 2 sum_{n>=1} c_n exp(i n w t) ), w = 2 pi / period.
  std::vector<std::complex<double>> fourier(int modes) const;
  /// How far the spline swings beyond the samples' range [low, high]: the largest excess as a
  /// fraction of that range, and the time and value where it is (0 for a constant).
  struct Overshoot {
    double fraction = 0.0, time = 0.0, value = 0.0, low = 0.0, high = 0.0;
  };
  Overshoot overshoot() const;
  /// The waveform multiplied by s (for unit conversion and sign flips).
  Waveform scaled(double s) const;

private:
  /// A warning naming `where` when the spline swings beyond the samples' range by more than
  /// 10 % of it.
  void check_overshoot(const std::string& where) const;

  std::vector<double> t_, v_, m_; // knots, values, spline second derivatives
  double period_ = 0.0;
  double constant_ = 0.0;
};

/// Reads a two-column CSV (time, value; optional header line; '#' comments) and converts
/// with time_scale [s per unit] and value_scale [SI per unit]. Errors name the file and line.
Waveform read_waveform_csv(const std::filesystem::path& file, double time_scale, double value_scale,
                           double period);

/// Reads SimVascular's `.flow` format: first line "nsamples nmodes", then "time flow" lines
/// in the file's units; the last sample closes the period. value_scale converts flow to SI.
Waveform read_simvascular_flow(const std::filesystem::path& file, double value_scale);

/// A waveform as what a run sees of it: its value, or its period and a digest of its values
/// at 97 times over the period (whatever samples and interpolation gave it). For a run's
/// fingerprint.
std::string describe(const Waveform& w);

} // namespace tearflow::bc
