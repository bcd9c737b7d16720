// Background phase offset and temporal phase unwrapping (corrections.hpp for the method).
#include "mri/corrections.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Dense>

#include "core/error.hpp"

namespace tearflow::mri {

Vec3 normalized_position(const ImageGrid& g, int i, int j, int k) {
  auto s = [](int x, int n) { return n > 1 ? 2.0 * x / (n - 1) - 1.0 : 0.0; };
  return {s(i, g.size[0]), s(j, g.size[1]), s(k, g.size[2])};
}

void monomials(const Vec3& x, int order, std::vector<double>& out) {
  out.clear();
  out.push_back(1.0);
  if (order >= 1)
    out.insert(out.end(), {x[0], x[1], x[2]});
  if (order >= 2)
    out.insert(out.end(),
               {x[0] * x[0], x[1] * x[1], x[2] * x[2], x[0] * x[1], x[0] * x[2], x[1] * x[2]});
}

std::vector<char> signal_mask(const Flow4D& data, double noise_multiple) {
  // The noise: the median over the voxels of the magnitude's temporal SD (static voxels,
  // air or tissue, are the majority, and theirs varies by noise alone).
  const std::size_t n = data.grid.count();
  const double nf = static_cast<double>(data.frames.size());
  std::vector<float> mean(n), sd(n);
  for (std::size_t v = 0; v < n; ++v) {
    double s1 = 0, s2 = 0;
    for (const Frame& f : data.frames)
      s1 += f.magnitude[v], s2 += double(f.magnitude[v]) * f.magnitude[v];
    mean[v] = static_cast<float>(s1 / nf);
    sd[v] = static_cast<float>(std::sqrt(std::max(0.0, s2 / nf - (s1 / nf) * (s1 / nf))));
  }
  std::nth_element(sd.begin(), sd.begin() + n / 2, sd.end());
  const double threshold = noise_multiple * sd[n / 2];
  std::vector<char> mask(n);
  for (std::size_t v = 0; v < n; ++v)
    mask[v] = mean[v] > threshold && mean[v] > 0;
  return mask;
}

nlohmann::json BackgroundReport::to_json() const {
  nlohmann::json j;
  j["static_voxels"] = static_voxels;
  j["flow_region_voxels"] = flow_region_voxels;
  const char* names[] = {"x", "y", "z"};
  for (int c = 0; c < 3; ++c) {
    j["coefficients_m_per_s"][names[c]] = coefficients[c];
    j["static_rms_before_m_per_s"][names[c]] = rms_before[c];
    j["static_rms_after_m_per_s"][names[c]] = rms_after[c];
  }
  return j;
}

nlohmann::json UnwrapReport::to_json() const {
  return {{"values_unwrapped", values_unwrapped}, {"voxels", voxels}};
}

namespace {

/// The flowing blood and the rim around it: the voxels with signal whose SD x magnitude
/// exceeds `threshold`, dilated by `margin` voxels along each grid axis (a cube).
std::vector<char> flow_region(const ImageGrid& g, const std::vector<char>& with_signal,
                              const std::vector<float>& sd_magnitude, double threshold,
                              int margin) {
  const std::size_t n = g.count();
  std::vector<char> region(n, 0);
  const int nx = g.size[0], ny = g.size[1], nz = g.size[2];
  for (std::size_t v = 0; v < n; ++v) {
    if (!with_signal[v] || sd_magnitude[v] <= threshold)
      continue;
    const int i = static_cast<int>(v % nx), j = static_cast<int>((v / nx) % ny),
              k = static_cast<int>(v / (static_cast<std::size_t>(nx) * ny));
    for (int c = std::max(0, k - margin); c <= std::min(nz - 1, k + margin); ++c)
      for (int b = std::max(0, j - margin); b <= std::min(ny - 1, j + margin); ++b)
        for (int a = std::max(0, i - margin); a <= std::min(nx - 1, i + margin); ++a)
          region[(static_cast<std::size_t>(c) * ny + b) * nx + a] = 1;
  }
  return region;
}

} // namespace

BackgroundReport correct_background(Flow4D& data, const BackgroundOptions& options) {
  const ImageGrid& g = data.grid;
  const std::size_t n = g.count();
  const std::size_t nf = data.frames.size();
  const std::vector<char> with_signal = signal_mask(data, options.noise_multiple);

  // Time mean and temporal SD (largest over the components) per voxel with signal.
  std::array<std::vector<float>, 3> mean;
  for (auto& m : mean)
    m.assign(n, 0.0f);
  std::vector<float> sd(n, 0.0f);
  for (int c = 0; c < 3; ++c) {
    std::vector<double> s1(n, 0.0), s2(n, 0.0);
    for (const Frame& f : data.frames)
      for (std::size_t v = 0; v < n; ++v) {
        const double x = f.velocity[c][v];
        s1[v] += x, s2[v] += x * x;
      }
    for (std::size_t v = 0; v < n; ++v) {
      mean[c][v] = static_cast<float>(s1[v] / nf);
      const double var = std::max(0.0, s2[v] / nf - (s1[v] / nf) * (s1[v] / nf));
      sd[v] = std::max(sd[v], static_cast<float>(std::sqrt(var)));
    }
  }
  // Phase noise scales as 1 / magnitude, so SD x magnitude is the same for all static voxels
  // (the noise level) and larger for flowing blood, however dim the tissue.
  std::vector<float> mean_magnitude(n, 0.0f);
  for (const Frame& f : data.frames)
    for (std::size_t v = 0; v < n; ++v)
      mean_magnitude[v] += f.magnitude[v] / static_cast<float>(nf);
  for (std::size_t v = 0; v < n; ++v)
    sd[v] *= mean_magnitude[v];
  std::vector<float> sds;
  for (std::size_t v = 0; v < n; ++v)
    if (with_signal[v])
      sds.push_back(sd[v]);
  BackgroundReport report;
  if (sds.empty())
    throw SolverError("background correction: no voxel with signal");
  const std::size_t cut = static_cast<std::size_t>(options.static_percentile * (sds.size() - 1));
  std::nth_element(sds.begin(), sds.begin() + cut, sds.end());
  const float sd_limit = sds[cut];
  // The noise level: a low quantile of SD x magnitude over the voxels with signal, static
  // tissue's as long as a quarter of them are static (a small field of view around a large
  // vessel has far more blood than the median assumed).
  const std::size_t at = static_cast<std::size_t>(options.noise_quantile * (sds.size() - 1));
  std::nth_element(sds.begin(), sds.begin() + at, sds.end());
  const std::vector<char> flowing =
      flow_region(g, with_signal, sd, options.flow_factor * sds[at], options.flow_margin);
  report.flow_region_voxels =
      static_cast<std::size_t>(std::count(flowing.begin(), flowing.end(), char(1)));

  // Least squares on the static voxels: normal equations (10 x 10 at most), solved by LDLT;
  // then robust refits: a voxel whose time mean lies more than 3 robust SDs (1.4826 x the
  // median absolute residual) from the fit in any component is dropped, which removes slow
  // blood that passed the SD test (it would bias the fit by its mean flow).
  std::vector<std::size_t> fit_voxels;
  for (std::size_t v = 0; v < n; ++v)
    if (with_signal[v] && !flowing[v] && sd[v] <= sd_limit)
      fit_voxels.push_back(v);
  std::vector<double> mono;
  monomials({0, 0, 0}, options.order, mono);
  const int nt = static_cast<int>(mono.size());
  auto position = [&](std::size_t v) {
    const int i = static_cast<int>(v % g.size[0]);
    const int j = static_cast<int>((v / g.size[0]) % g.size[1]);
    const int k = static_cast<int>(v / (static_cast<std::size_t>(g.size[0]) * g.size[1]));
    return normalized_position(g, i, j, k);
  };
  Eigen::MatrixXd a;
  for (int pass = 0; pass < 4; ++pass) {
    if (fit_voxels.size() < static_cast<std::size_t>(3 * nt))
      throw SolverError(fmt::format("background correction: {} static voxels, fewer than the "
                                    "{} needed for an order-{} fit",
                                    fit_voxels.size(), 3 * nt, options.order));
    Eigen::MatrixXd ata = Eigen::MatrixXd::Zero(nt, nt);
    Eigen::MatrixXd atb = Eigen::MatrixXd::Zero(nt, 3);
    for (std::size_t v : fit_voxels) {
      monomials(position(v), options.order, mono);
      const Eigen::Map<const Eigen::VectorXd> m(mono.data(), nt);
      ata.noalias() += m * m.transpose();
      for (int c = 0; c < 3; ++c)
        atb.col(c) += mean[c][v] * m;
    }
    a = ata.ldlt().solve(atb);
    if (pass == 3)
      break;
    std::array<std::vector<float>, 3> residual;
    for (std::size_t v : fit_voxels) {
      monomials(position(v), options.order, mono);
      const Eigen::Map<const Eigen::VectorXd> m(mono.data(), nt);
      for (int c = 0; c < 3; ++c)
        residual[c].push_back(static_cast<float>(mean[c][v] - m.dot(a.col(c))));
    }
    std::array<double, 3> limit{};
    for (int c = 0; c < 3; ++c) {
      std::vector<float> absolute(residual[c].size());
      std::transform(residual[c].begin(), residual[c].end(), absolute.begin(),
                     [](float r) { return std::abs(r); });
      std::nth_element(absolute.begin(), absolute.begin() + absolute.size() / 2, absolute.end());
      limit[c] = 3.0 * 1.4826 * absolute[absolute.size() / 2];
    }
    std::vector<std::size_t> kept;
    for (std::size_t l = 0; l < fit_voxels.size(); ++l)
      if (std::abs(residual[0][l]) <= limit[0] && std::abs(residual[1][l]) <= limit[1] &&
          std::abs(residual[2][l]) <= limit[2])
        kept.push_back(fit_voxels[l]);
    fit_voxels.swap(kept);
  }
  report.static_voxels = fit_voxels.size();
  std::vector<char> fitted(n, 0);
  std::array<double, 3> sum2{};
  for (std::size_t v : fit_voxels) {
    fitted[v] = 1;
    for (int c = 0; c < 3; ++c)
      sum2[c] += double(mean[c][v]) * mean[c][v];
  }
  for (int c = 0; c < 3; ++c) {
    report.coefficients[c].assign(a.col(c).data(), a.col(c).data() + nt);
    report.rms_before[c] = std::sqrt(sum2[c] / report.static_voxels);
  }

  // Subtract from every frame; the residual on the fitted voxels for the report.
  std::array<double, 3> res2{};
  for (int k = 0; k < g.size[2]; ++k)
    for (int j = 0; j < g.size[1]; ++j)
      for (int i = 0; i < g.size[0]; ++i) {
        monomials(normalized_position(g, i, j, k), options.order, mono);
        const Eigen::Map<const Eigen::VectorXd> m(mono.data(), nt);
        const std::size_t v = g.linear(i, j, k);
        for (int c = 0; c < 3; ++c) {
          const double b = m.dot(a.col(c));
          for (Frame& f : data.frames)
            f.velocity[c][v] -= static_cast<float>(b);
          if (fitted[v])
            res2[c] += (mean[c][v] - b) * (mean[c][v] - b);
        }
      }
  for (int c = 0; c < 3; ++c)
    report.rms_after[c] = std::sqrt(res2[c] / report.static_voxels);
  return report;
}

UnwrapReport unwrap_temporal(Flow4D& data, double noise_multiple) {
  if (!(data.venc > 0.0))
    input_error("phase unwrapping needs the velocity encoding (venc), which the data lacks; "
                "switch unwrapping off or give --venc");
  const std::vector<char> with_signal = signal_mask(data, noise_multiple);
  const double period = 2.0 * data.venc;
  UnwrapReport report;
  const std::size_t n = data.grid.count();
  if (data.encoding == Encoding::through_plane) {
    // One measured value, v . n (stored as v_n n): a wrap moves it by 2 venc, each stored
    // component by 2 venc n_c only, so the scalar is unwrapped and written back.
    const Vec3& normal = data.grid.direction[2];
    for (std::size_t v = 0; v < n; ++v) {
      if (!with_signal[v])
        continue;
      bool moved = false;
      double previous = along(data.frames[0], v, normal);
      for (std::size_t f = 1; f < data.frames.size(); ++f) {
        double x = along(data.frames[f], v, normal);
        const double jumps = std::round((previous - x) / period);
        if (jumps != 0.0) {
          x += jumps * period;
          for (int c = 0; c < 3; ++c)
            data.frames[f].velocity[c][v] = static_cast<float>(x * normal[c]);
          ++report.values_unwrapped;
          moved = true;
        }
        previous = x;
      }
      report.voxels += moved;
    }
    return report;
  }
  if (data.encoding != Encoding::velocity_3d)
    return report; // cine: no phase
  for (std::size_t v = 0; v < n; ++v) {
    if (!with_signal[v])
      continue;
    bool moved = false;
    for (int c = 0; c < 3; ++c) {
      double previous = data.frames[0].velocity[c][v];
      for (std::size_t f = 1; f < data.frames.size(); ++f) {
        float& x = data.frames[f].velocity[c][v];
        const double jumps = std::round((previous - x) / period);
        if (jumps != 0.0) {
          x = static_cast<float>(x + jumps * period);
          ++report.values_unwrapped;
          moved = true;
        }
        previous = x;
      }
    }
    report.voxels += moved;
  }
  return report;
}

} // namespace tearflow::mri
