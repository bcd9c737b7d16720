#pragma once
// Synthetic runs for the landmark analysis (tests/test_analysis*.cpp): straight pipes along z
// (from the built-in pipe generator, shifted side by side for a two-lumen channel) carrying a
// prescribed Poiseuille velocity with a time-varying amplitude and a linear pressure,
//   u = U_j a(t) (1 - rho^2 / r_j^2) e_z,   p = P_j a(t) - G z,
// written as a VTU series + flow.pvd, with cycles.json and a landmarks JSON, laid out as
// `tearflow run` lays out its output.
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <vector>

#include "geometry/landmarks.hpp"
#include "io/vtu_series.hpp"
#include "mesh/pipe_generator.hpp"

namespace tearflow::testing {

/// One lumen of the synthetic channel: a pipe of radius `radius` along z through (x, 0).
struct SyntheticLumen {
  double x = 0.0;        ///< axis position [m]
  double radius = 0.005; ///< [m]
  double u_peak = 0.5;   ///< centreline velocity at amplitude 1 [m/s]
  double p_peak = 1.0e4; ///< pressure at z = 0 at amplitude 1 [Pa]
};

struct SyntheticRun {
  std::vector<SyntheticLumen> lumina;
  double length = 0.005;     ///< [m]
  double element_size = 0.0; ///< [m]; 0: a tenth of the smallest radius
  double gradient = 2.0e4;   ///< G [Pa/m]
  double period = 0.8;       ///< [s]
  int frames = 9;            ///< saved frames over one period, both ends
  bool write_cycles = true;  ///< cycles.json with one complete cycle
  std::function<double(double)> amplitude = [](double t) {
    return 1.0 + 0.5 * std::sin(2.0 * M_PI * t / 0.8);
  };
  /// A moving wall, as an FSI run writes it: each lumen's nodes displaced radially by
  /// dilation(t) x their distance from its axis (point field `displacement`); none if empty.
  std::function<double(double)> dilation;

  double h() const {
    double r = lumina.front().radius;
    for (const SyntheticLumen& l : lumina)
      r = std::min(r, l.radius);
    return element_size > 0 ? element_size : r / 10.0;
  }
  double time(int i) const { return period * i / (frames - 1); }
  /// Exact flow of lumen j at time t: int u dA = pi r^2 U a(t) / 2.
  double flow(std::size_t j, double t) const {
    const SyntheticLumen& l = lumina[j];
    return M_PI * l.radius * l.radius * l.u_peak * amplitude(t) / 2.0;
  }
  /// Exact pressure of lumen j on the plane z at time t.
  double pressure(std::size_t j, double z, double t) const {
    return lumina[j].p_peak * amplitude(t) - gradient * z;
  }
};

/// Edge lengths of the mesh written [m]: the tolerances of the tests follow from them.
struct EdgeLengths {
  double longest = 0.0;
  double rms = 0.0; ///< root mean square over the tetrahedra's edges
};

/// Writes the run into `dir` (flow.pvd, flow_*.vtu, cycles.json).
inline EdgeLengths write_synthetic_run(const SyntheticRun& run, const std::filesystem::path& dir) {
  std::filesystem::create_directories(dir);
  mesh::Mesh channel;
  std::vector<int> owner; // lumen of each node
  for (std::size_t j = 0; j < run.lumina.size(); ++j) {
    const SyntheticLumen& l = run.lumina[j];
    const mesh::Mesh pipe = mesh::make_pipe({l.radius, run.length, run.h(), 0.0});
    const Index base = channel.num_nodes();
    for (const Vec3& p : pipe.points) {
      channel.points.push_back({p[0] + l.x, p[1], p[2]});
      owner.push_back(static_cast<int>(j));
    }
    for (Tet t : pipe.tets) {
      for (Index& n : t)
        n += base;
      channel.tets.push_back(t);
      channel.tet_region.push_back(0);
    }
  }
  channel.regions = {"fluid"};
  EdgeLengths edges;
  for (const Tet& t : channel.tets)
    for (int a = 0; a < 4; ++a)
      for (int b = a + 1; b < 4; ++b) {
        const Vec3 e = channel.points[t[a]] - channel.points[t[b]];
        edges.longest = std::max(edges.longest, std::sqrt(dot(e, e)));
        edges.rms += dot(e, e);
      }
  edges.rms = std::sqrt(edges.rms / (6.0 * channel.tets.size()));
  io::VtuSeries series(channel, dir, "flow");
  for (int i = 0; i < run.frames; ++i) {
    const double t = run.time(i), a = run.amplitude(t);
    io::PointField u{"velocity", 3, {}}, p{"pressure", 1, {}};
    for (std::size_t n = 0; n < channel.points.size(); ++n) {
      const SyntheticLumen& l = run.lumina[owner[n]];
      const Vec3& x = channel.points[n];
      const double rho2 = (x[0] - l.x) * (x[0] - l.x) + x[1] * x[1];
      u.values.insert(u.values.end(),
                      {0.0, 0.0, l.u_peak * a * (1.0 - rho2 / (l.radius * l.radius))});
      p.values.push_back(l.p_peak * a - run.gradient * x[2]);
    }
    if (!run.dilation) {
      series.write(i, t, {u, p});
      continue;
    }
    io::PointField d{"displacement", 3, {}};
    for (std::size_t n = 0; n < channel.points.size(); ++n) {
      const Vec3& x = channel.points[n];
      const double e = run.dilation(t);
      d.values.insert(d.values.end(), {e * (x[0] - run.lumina[owner[n]].x), e * x[1], 0.0});
    }
    series.write(i, t, {u, p, d});
  }
  if (run.write_cycles) {
    std::ofstream(dir / "cycles.json")
        << "{\"period_s\": " << run.period << ", \"cycles\": [{\"cycle\": 1, \"t_begin_s\": 0, "
        << "\"t_end_s\": " << run.period << "}]}\n";
  }
  return edges;
}

/// A landmark plane normal to z at height z. An `aorta` landmark has its origin on lumen j's
/// axis; a TL / FL landmark has the origin of the first lumen's axis (TLk and FLk share one
/// plane, as the parametric model writes them) and its point on lumen j's axis.
inline geometry::Landmark plane_at(const SyntheticRun& run, const std::string& name, double z,
                                   std::size_t j = 0, const std::string& lumen = "aorta") {
  const Vec3 axis{run.lumina[j].x, 0.0, z};
  if (lumen == "aorta")
    return {name, axis, {0.0, 0.0, 1.0}, lumen, std::nullopt};
  return {name, {run.lumina.front().x, 0.0, z}, {0.0, 0.0, 1.0}, lumen, axis};
}

} // namespace tearflow::testing
