#pragma once
// The analytic 4D-flow scans of the MRI tests: Womersley flow in a pipe of blood (radius 6 mm:
// alpha 8.7 at 75 beats per minute, 8 voxels of 1.5 mm across; 9 mm: the descending aorta's
// size, 12 across), and its one landmark plane across the pipe.
#include <algorithm>
#include <cmath>
#include <string>

#include <gtest/gtest.h>

#include "core/error.hpp"

#include "geometry/landmarks.hpp"
#include "mri/alignment.hpp"
#include "mri/plane_flow.hpp"
#include "mri/synthetic.hpp"

namespace tearflow::testing {

/// The expected substring in the InputError that `f` throws.
template <typename F> void expect_input_error(F f, const std::string& part) {
  try {
    f();
    ADD_FAILURE() << "no error; expected one saying '" << part << "'";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(part), std::string::npos) << e.what();
  }
}

/// mri::pulsatile_pipe_flow: Q0 = 0.35 m/s x pi R^2, swing 0.3: 0.65 to 1.35 Q0, so that an
/// error relative to each frame's flow means something; peak centre-line velocity ~0.7 m/s.
inline bc::WomersleyFlow test_pipe_flow(double radius = 6e-3, double swing = 0.3) {
  return mri::pulsatile_pipe_flow(radius, 0.35, swing);
}

/// The scan: a grid of `voxel` voxels centred on the pipe, its axes rotated by `degrees`
/// about (1, 1, 0) from the patient axes (0: axis-aligned).
inline mri::PipeScan test_pipe_scan(double degrees = 0.0, double snr = 0.0, double radius = 6e-3,
                                    double voxel = 1.5e-3) {
  mri::PipeScan s;
  s.flow = test_pipe_flow(radius);
  s.axis_point = {0.01, -0.02, 0.05};
  s.axis = {0, 0, 1};
  s.frames = 20;
  s.venc = 1.0;
  s.snr = snr;
  const int n = static_cast<int>(std::ceil(5 * radius / voxel)) + 1; // tissue to 2 R, and air
  s.grid = mri::centred_grid(s.axis_point, mri::rotation({1, 1, 0}, degrees), {n, n, 12},
                             {voxel, voxel, voxel});
  return s;
}

/// The plane across the pipe through its axis point.
inline geometry::Landmarks test_pipe_landmarks(const mri::PipeScan& s) {
  geometry::Landmarks l;
  geometry::Landmark p;
  p.name = "AAo";
  p.origin = s.axis_point;
  p.normal = s.axis;
  p.point = s.axis_point;
  l.planes.push_back(p);
  return l;
}

/// Largest |Q - Q_exact| / Q_exact over the frames at that plane (Q_exact the frame window's
/// mean flow).
inline double worst_flow_error(const mri::PipeScan& scan, const mri::Flow4D& data) {
  const auto planes = mri::measure_planes(data, test_pipe_landmarks(scan));
  double worst = 0.0;
  for (int k = 0; k < scan.frames; ++k) {
    const double exact = mri::exact_frame_flow(scan, k);
    worst = std::max(worst, std::abs(planes[0].flow[k] - exact) / exact);
  }
  return worst;
}

/// `data` in a patient frame moved by `t` (x_mri = R x_model + t): its grid's origin and axes
/// moved, its velocities rotated with them, as a scanner in that frame would record them.
inline mri::Flow4D moved_scan(const mri::Flow4D& data, const mri::RigidTransform& t) {
  mri::Flow4D moved = data;
  moved.grid.origin = t.apply(data.grid.origin);
  for (int a = 0; a < 3; ++a)
    moved.grid.direction[a] = t.rotate(data.grid.direction[a]);
  for (mri::Frame& f : moved.frames)
    for (std::size_t v = 0; v < f.magnitude.size(); ++v) {
      const Vec3 u = t.rotate({f.velocity[0][v], f.velocity[1][v], f.velocity[2][v]});
      for (int a = 0; a < 3; ++a)
        f.velocity[a][v] = static_cast<float>(u[a]);
    }
  return moved;
}

} // namespace tearflow::testing
