// Simulation against MRI flow waveforms (compare.hpp for the definitions).
#include "mri/compare.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>

#include <fmt/format.h>

#include "core/error.hpp"
#include "core/units.hpp"
#include "mri/non_finite.hpp"

namespace tearflow::mri {

namespace {

/// f(t) from samples (ts, fs), linear, held at the ends.
double interpolate(const std::vector<double>& ts, const std::vector<double>& fs, double t) {
  if (t <= ts.front())
    return fs.front();
  if (t >= ts.back())
    return fs.back();
  const auto it = std::upper_bound(ts.begin(), ts.end(), t);
  const std::size_t i = static_cast<std::size_t>(it - ts.begin()) - 1;
  const double w = (t - ts[i]) / (ts[i + 1] - ts[i]);
  return (1 - w) * fs[i] + w * fs[i + 1];
}

double trapezoid(const std::vector<double>& t, const std::vector<double>& f) {
  double v = 0.0;
  for (std::size_t i = 1; i < t.size(); ++i)
    v += 0.5 * (f[i] + f[i - 1]) * (t[i] - t[i - 1]);
  return v;
}

std::vector<double> flows(const analysis::LandmarkSeries& s) {
  std::vector<double> q;
  for (const auto& v : s.samples)
    q.push_back(v.flow);
  return q;
}

} // namespace

Comparison compare_flows(const analysis::Analysis& sim, const analysis::Analysis& mri) {
  Comparison c;
  std::vector<double> ts;
  for (double t : sim.time)
    ts.push_back(t - sim.time.front());
  for (const analysis::LandmarkSeries& m : mri.series) {
    const analysis::LandmarkSeries* s = sim.find(m.landmark.name);
    const std::vector<double> qm = flows(m);
    if (!s || std::any_of(qm.begin(), qm.end(), [](double q) { return std::isnan(q); }))
      continue;
    const std::vector<double> qs_all = flows(*s);
    if (std::any_of(qs_all.begin(), qs_all.end(), [](double q) { return std::isnan(q); }))
      continue;
    WaveformComparison w;
    w.landmark = m.landmark.name;
    for (std::size_t k = 0; k < mri.time.size(); ++k) {
      const double t = mri.time[k] - mri.time.front();
      w.time.push_back(t);
      w.mri.push_back(qm[k]);
      w.simulation.push_back(interpolate(ts, qs_all, t));
    }
    const double span = w.time.back() - w.time.front();
    w.volume_sim = trapezoid(w.time, w.simulation);
    w.volume_mri = trapezoid(w.time, w.mri);
    w.mean_sim = span > 0 ? w.volume_sim / span : w.simulation.front();
    w.mean_mri = span > 0 ? w.volume_mri / span : w.mri.front();
    w.peak_sim = *std::max_element(w.simulation.begin(), w.simulation.end());
    w.peak_mri = *std::max_element(w.mri.begin(), w.mri.end());
    const std::size_t n = w.time.size();
    double sd = 0, ss = 0, sm = 0, sss = 0, smm = 0, ssm = 0;
    for (std::size_t k = 0; k < n; ++k) {
      const double d = w.mri[k] - w.simulation[k];
      w.bias += d / n;
      ss += w.simulation[k] / n;
      sm += w.mri[k] / n;
    }
    for (std::size_t k = 0; k < n; ++k) {
      const double d = w.mri[k] - w.simulation[k] - w.bias;
      const double a = w.simulation[k] - ss, b = w.mri[k] - sm;
      sd += d * d, sss += a * a, smm += b * b, ssm += a * b;
    }
    w.sd = n > 1 ? std::sqrt(sd / (n - 1)) : 0.0;
    w.correlation = sss > 0 && smm > 0 ? ssm / std::sqrt(sss * smm) : 0.0;
    c.landmarks.push_back(std::move(w));
  }
  if (c.landmarks.empty())
    input_error("mri compare: the simulation and the MRI share no landmark with a flow");
  return c;
}

VoxelComparison compare_voxels(const Flow4D& sim, const Flow4D& mri) {
  if (!sim.grid.same_as(mri.grid) || sim.frames.size() != mri.frames.size())
    input_error("voxel comparison: the simulated scan must share the MRI's grid and frames");
  VoxelComparison c;
  c.scan_non_finite = non_finite_json(mri);
  const std::size_t n = sim.grid.count();
  double s1 = 0, s2 = 0, a1 = 0;
  std::vector<double> angles;
  for (std::size_t f = 0; f < sim.frames.size(); ++f) {
    const Frame &fs = sim.frames[f], &fm = mri.frames[f];
    auto vec = [](const Frame& fr, std::size_t v) {
      return Vec3{fr.velocity[0][v], fr.velocity[1][v], fr.velocity[2][v]};
    };
    double largest = 0;
    std::vector<std::size_t> lumen;
    for (std::size_t v = 0; v < n; ++v)
      if (fs.magnitude[v] >= 0.6f) { // fluid fraction >= 1/2
        largest = std::max(largest, std::sqrt(dot(vec(fs, v), vec(fs, v))));
        lumen.push_back(v);
      }
    refuse_non_finite(mri, f, lumen, 1, 3, "mri compare --scan", "the lumen's voxels",
                      "the speed and angle differences would be wrong");
    for (std::size_t v = 0; v < n; ++v) {
      if (fs.magnitude[v] < 0.6f)
        continue;
      const Vec3 a = vec(fs, v), b = vec(fm, v);
      const double sa = std::sqrt(dot(a, a)), sb = std::sqrt(dot(b, b));
      ++c.voxel_frames;
      s1 += sb - sa, s2 += (sb - sa) * (sb - sa);
      if (sa >= 0.1 * largest && sa > 0 && sb > 0) {
        const double angle =
            std::acos(std::clamp(dot(a, b) / (sa * sb), -1.0, 1.0)) * 180.0 / 3.14159265358979;
        angles.push_back(angle);
        a1 += angle;
      }
    }
  }
  if (c.voxel_frames == 0)
    input_error("voxel comparison: no lumen voxel in the simulated scan");
  const double m = static_cast<double>(c.voxel_frames);
  c.speed_difference_mean = s1 / m;
  c.speed_difference_sd = m > 1 ? std::sqrt(std::max(0.0, (s2 - s1 * s1 / m) / (m - 1))) : 0.0;
  c.angle_voxel_frames = angles.size();
  if (!angles.empty()) {
    c.angle_mean_deg = a1 / angles.size();
    std::nth_element(angles.begin(), angles.begin() + angles.size() / 2, angles.end());
    c.angle_median_deg = angles[angles.size() / 2];
  }
  return c;
}

nlohmann::json VoxelComparison::to_json() const {
  return {{"lumen_voxel_frames", voxel_frames},
          {"speed_difference_mean_m_per_s", speed_difference_mean},
          {"speed_difference_sd_m_per_s", speed_difference_sd},
          {"angle_voxel_frames", angle_voxel_frames},
          {"angle_mean_deg", angle_mean_deg},
          {"angle_median_deg", angle_median_deg},
          {"scan_non_finite", scan_non_finite}};
}

nlohmann::json Comparison::to_json() const {
  nlohmann::json j;
  if (voxels)
    j["voxels"] = voxels->to_json();
  const double mL = units::mL;
  for (const WaveformComparison& w : landmarks) {
    j["landmarks"][w.landmark] = {{"frames", w.time.size()},
                                  {"mean_flow_simulation_mL_per_s", w.mean_sim / mL},
                                  {"mean_flow_mri_mL_per_s", w.mean_mri / mL},
                                  {"net_volume_simulation_mL", w.volume_sim / mL},
                                  {"net_volume_mri_mL", w.volume_mri / mL},
                                  {"peak_flow_simulation_mL_per_s", w.peak_sim / mL},
                                  {"peak_flow_mri_mL_per_s", w.peak_mri / mL},
                                  {"difference_mean_mL_per_s", w.bias / mL},
                                  {"difference_sd_mL_per_s", w.sd / mL},
                                  {"limits_of_agreement_mL_per_s",
                                   {(w.bias - 1.96 * w.sd) / mL, (w.bias + 1.96 * w.sd) / mL}},
                                  {"correlation", w.correlation}};
  }
  // FL flow ratios of the paired stations present on both sides.
  for (int k = 1; k <= 9; ++k) {
    const auto tl = std::find_if(landmarks.begin(), landmarks.end(), [&](const auto& w) {
      return w.landmark == fmt::format("TL{}", k);
    });
    const auto fl = std::find_if(landmarks.begin(), landmarks.end(), [&](const auto& w) {
      return w.landmark == fmt::format("FL{}", k);
    });
    if (tl == landmarks.end() || fl == landmarks.end())
      continue;
    auto ratio = [](double f, double t) { return 100.0 * f / (f + t); };
    j["fl_flow_ratio_percent"][fmt::format("{}", k)] = {
        {"simulation", ratio(fl->mean_sim, tl->mean_sim)},
        {"mri", ratio(fl->mean_mri, tl->mean_mri)}};
  }
  return j;
}

void write_comparison(const Comparison& c, const std::filesystem::path& dir) {
  std::filesystem::create_directories(dir);
  {
    std::ofstream out(dir / "compare.json");
    if (!out)
      input_error("cannot write '{}'", (dir / "compare.json").string());
    out << c.to_json().dump(2) << '\n';
  }
  std::ofstream out(dir / "flow_comparison.csv");
  out << "landmark,time_s,simulation_mL_per_s,mri_mL_per_s,difference_mL_per_s,mean_mL_per_s\n";
  for (const WaveformComparison& w : c.landmarks)
    for (std::size_t k = 0; k < w.time.size(); ++k)
      out << fmt::format("{},{:.6g},{:.8g},{:.8g},{:.8g},{:.8g}\n", w.landmark, w.time[k],
                         w.simulation[k] / units::mL, w.mri[k] / units::mL,
                         (w.mri[k] - w.simulation[k]) / units::mL,
                         0.5 * (w.mri[k] + w.simulation[k]) / units::mL);
}

} // namespace tearflow::mri
