// Synthetic 4D-flow MRI of the Womersley pipe (synthetic.hpp for the model of the scanner).
// Cost: the axial profile u(r, t) is tabulated once per time sample on a fine radial grid
// (Bessel functions are dear), and only voxels that the lumen or the tissue boundary can
// reach are sub-sampled; the others take the value at their centre.
#include "mri/synthetic.hpp"

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>
#include <random>

#include "core/error.hpp"
#include "mri/corrections.hpp"

namespace tearflow::mri {

namespace {

constexpr double kPi = std::numbers::pi;

/// u(r) at one time, tabulated at kTable + 1 radii over [0, R]; linear in between. The
/// table's error, (R / kTable)^2 u'' / 8, is below 1e-6 of the peak velocity.
struct Profile {
  static constexpr int kTable = 2048;
  double radius = 0.0;
  std::vector<double> u;
  Profile(const bc::WomersleyFlow& flow, double t) : radius(flow.radius), u(kTable + 1) {
    for (int i = 0; i <= kTable; ++i)
      u[i] = flow.axial_velocity(radius * i / kTable, t);
  }
  double operator()(double r) const {
    if (r >= radius)
      return 0.0;
    const double x = r / radius * kTable;
    const int i = std::min(static_cast<int>(x), kTable - 1);
    return u[i] + (x - i) * (u[i + 1] - u[i]);
  }
};

double sinc(double x) {
  return std::abs(x) < 1e-8 ? 1.0 : std::sin(x) / x;
}

} // namespace

void encode(Flow4D& data, Encoding e) {
  data.encoding = e;
  if (e == Encoding::velocity_3d)
    return;
  const Vec3& n = data.grid.direction[2];
  for (Frame& fr : data.frames)
    for (std::size_t v = 0; v < fr.magnitude.size(); ++v) {
      const double vn = e == Encoding::magnitude ? 0.0 : along(fr, v, n);
      for (int c = 0; c < 3; ++c)
        fr.velocity[c][v] = static_cast<float>(vn * n[c]);
    }
  data.check("encode");
}

void add_scanner_effects(Flow4D& data, const ScannerEffects& e) {
  std::mt19937_64 rng(e.seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  const double s = e.snr > 0 ? e.lumen_signal / e.snr : 0.0;
  const std::size_t n = data.grid.count();
  // The measured velocities: the three components, or v . n of a through-plane scan.
  const bool through = data.encoding == Encoding::through_plane;
  const int measured = data.encoding == Encoding::velocity_3d ? 3 : (through ? 1 : 0);
  const Vec3& slice_normal = data.grid.direction[2];
  for (Frame& fr : data.frames) {
    for (std::size_t v = 0; v < n; ++v) {
      const double m = fr.magnitude[v];
      for (int c = 0; c < measured; ++c) {
        double vel = through ? along(fr, v, slice_normal) : fr.velocity[c][v];
        if (s > 0) {
          // Phase noise from the magnitude's SNR; where the signal is lost in the noise
          // (below 2 s) the phase is uniform over the whole range.
          if (m < 2 * s)
            vel = e.venc * uniform(rng);
          else
            vel += std::sqrt(2.0) / kPi * e.venc * s / m * normal(rng);
        }
        if (e.wrap)
          vel = wrap_velocity(vel, e.venc);
        if (through)
          for (int d = 0; d < 3; ++d)
            fr.velocity[d][v] = static_cast<float>(vel * slice_normal[d]);
        else
          fr.velocity[c][v] = static_cast<float>(vel);
      }
      if (s > 0)
        fr.magnitude[v] = static_cast<float>(std::abs(m + s * normal(rng)));
    }
  }
}

bc::WomersleyFlow pulsatile_pipe_flow(double radius, double mean_velocity, double swing) {
  bc::WomersleyFlow f;
  f.radius = radius, f.density = 1060, f.viscosity = 4e-3;
  f.omega = 2 * kPi / 0.8;
  const double q0 = mean_velocity * kPi * radius * radius;
  f.modes = {q0, -swing * q0, std::complex<double>(0, -0.1 * q0)};
  return f;
}

double exact_frame_flow(const PipeScan& scan, int k) {
  const double period = 2 * kPi / scan.flow.omega, dt = period / scan.frames, t = k * dt;
  double q = 0.0;
  for (std::size_t n = 0; n < scan.flow.modes.size(); ++n) {
    const double w = n * scan.flow.omega;
    q += std::real(scan.flow.modes[n] * std::polar(1.0, w * t)) * sinc(w * dt / 2);
  }
  return q;
}

Flow4D synthesize_pipe(const PipeScan& scan) {
  if (!(scan.flow.omega > 0.0) || scan.flow.modes.empty())
    input_error("synthetic scan: the pipe flow must be pulsatile (omega > 0, modes given)");
  if (scan.frames < 1 || !(scan.venc > 0.0) || scan.grid.count() == 0 || scan.voxel_samples < 1 ||
      scan.time_samples < 1)
    input_error("synthetic scan: frames, venc, voxel and time samples must be positive and the "
                "grid non-empty");
  const ImageGrid& g = scan.grid;
  const double R = scan.flow.radius;
  const double Rt = scan.tissue_radius > 0 ? scan.tissue_radius : 2 * R;
  const Vec3 axis = (1.0 / std::sqrt(dot(scan.axis, scan.axis))) * scan.axis;
  const double period = 2 * kPi / scan.flow.omega, dt = period / scan.frames;
  const int ns = scan.voxel_samples, nt = scan.time_samples;
  const double half_diagonal =
      0.5 * std::sqrt(dot(g.spacing, g.spacing)); // farthest sub-sample from the centre

  // Sub-sample offsets (in index units) of the midpoint rule inside a voxel.
  std::vector<Vec3> offsets;
  for (int a = 0; a < ns; ++a)
    for (int b = 0; b < ns; ++b)
      for (int c = 0; c < ns; ++c)
        offsets.push_back({(a + 0.5) / ns - 0.5, (b + 0.5) / ns - 0.5, (c + 0.5) / ns - 0.5});
  auto radius_of = [&](const Vec3& p) {
    const Vec3 d = p - scan.axis_point;
    const Vec3 radial = d - dot(d, axis) * axis;
    return std::sqrt(dot(radial, radial));
  };
  auto signal = [&](double r) {
    return r < R ? scan.lumen_signal : (r < Rt ? scan.tissue_signal : 0.0);
  };

  // Per voxel, once: the partial-volume magnitude, and the sub-sample radii of voxels the
  // lumen reaches (those alone carry velocity).
  const std::size_t n = g.count();
  std::vector<float> magnitude(n);
  std::vector<std::size_t> lumen_voxels;
  std::vector<double> lumen_radii; // ns^3 per lumen voxel
  for (int k = 0; k < g.size[2]; ++k)
    for (int j = 0; j < g.size[1]; ++j)
      for (int i = 0; i < g.size[0]; ++i) {
        const std::size_t v = g.linear(i, j, k);
        const Vec3 centre{double(i), double(j), double(k)};
        const double rc = radius_of(g.point(centre));
        const bool near_lumen = rc < R + half_diagonal;
        const bool near_tissue = std::abs(rc - Rt) < half_diagonal;
        if (!near_lumen && !near_tissue) {
          magnitude[v] = static_cast<float>(signal(rc));
          continue;
        }
        double m = 0.0;
        if (near_lumen)
          lumen_voxels.push_back(v);
        for (const Vec3& o : offsets) {
          const double r = radius_of(g.point(centre + o));
          m += signal(r);
          if (near_lumen)
            lumen_radii.push_back(r);
        }
        magnitude[v] = static_cast<float>(m / offsets.size());
      }

  Flow4D out;
  out.grid = g;
  out.venc = scan.venc;
  out.frame_window = dt;
  std::vector<double> speed(lumen_voxels.size());
  for (int f = 0; f < scan.frames; ++f) {
    Frame fr;
    fr.time = f * dt;
    std::fill(speed.begin(), speed.end(), 0.0);
    for (int q = 0; q < nt; ++q) { // the frame's window, midpoint rule
      const Profile u(scan.flow, fr.time + ((q + 0.5) / nt - 0.5) * dt);
      for (std::size_t l = 0; l < lumen_voxels.size(); ++l) {
        double sum = 0.0;
        for (std::size_t o = 0; o < offsets.size(); ++o)
          sum += u(lumen_radii[l * offsets.size() + o]);
        speed[l] += sum / offsets.size() / nt;
      }
    }
    fr.magnitude = magnitude;
    for (auto& c : fr.velocity)
      c.assign(n, 0.0f);
    for (std::size_t l = 0; l < lumen_voxels.size(); ++l)
      for (int c = 0; c < 3; ++c)
        fr.velocity[c][lumen_voxels[l]] = static_cast<float>(speed[l] * axis[c]);
    out.frames.push_back(std::move(fr));
  }
  out.period = period;
  encode(out, scan.encoding);
  add_scanner_effects(out, {scan.venc, scan.snr, scan.wrap, scan.lumen_signal, scan.seed});
  return out;
}

void add_background(Flow4D& data, const std::array<std::vector<double>, 3>& coefficients) {
  const ImageGrid& g = data.grid;
  std::vector<double> mono;
  for (int k = 0; k < g.size[2]; ++k)
    for (int j = 0; j < g.size[1]; ++j)
      for (int i = 0; i < g.size[0]; ++i) {
        monomials(normalized_position(g, i, j, k), 2, mono);
        const std::size_t v = g.linear(i, j, k);
        for (int c = 0; c < 3; ++c) {
          double b = 0.0;
          for (std::size_t t = 0; t < coefficients[c].size() && t < mono.size(); ++t)
            b += coefficients[c][t] * mono[t];
          for (Frame& fr : data.frames)
            fr.velocity[c][v] += static_cast<float>(b);
        }
      }
}

} // namespace tearflow::mri
