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
  // air or tissue, are the majority, and theirs varies by noise alone). A voxel whose
  // magnitude is not a number in some frame has no SD: it is left out, and has no signal
  // (ordering NaNs would also break nth_element's ordering).
  const std::size_t n = data.grid.count();
  const double nf = static_cast<double>(data.frames.size());
  std::vector<float> mean(n), sd;
  sd.reserve(n);
  std::vector<char> finite(n, 0);
  for (std::size_t v = 0; v < n; ++v) {
    double s1 = 0, s2 = 0;
    for (const Frame& f : data.frames)
      s1 += f.magnitude[v], s2 += double(f.magnitude[v]) * f.magnitude[v];
    mean[v] = static_cast<float>(s1 / nf);
    finite[v] = std::isfinite(s1) && std::isfinite(s2);
    if (finite[v])
      sd.push_back(static_cast<float>(std::sqrt(std::max(0.0, s2 / nf - (s1 / nf) * (s1 / nf)))));
  }
  std::vector<char> mask(n, 0);
  if (sd.empty())
    return mask;
  std::nth_element(sd.begin(), sd.begin() + sd.size() / 2, sd.end());
  const double threshold = noise_multiple * sd[sd.size() / 2];
  for (std::size_t v = 0; v < n; ++v)
    mask[v] = finite[v] && mean[v] > threshold && mean[v] > 0;
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
  std::vector<char> with_signal = signal_mask(data, options.noise_multiple);

  // Time mean and temporal SD (largest over the components) per voxel with signal. A
  // component that is not a number in some frame of a voxel has neither: that voxel stays
  // out of the component's fit, and out of the fit altogether when no component is a number
  // throughout (a scan whose vz is all NaN still has its vx and vy corrected; the
  // measurement then refuses vz). The offset is subtracted from every voxel alike.
  std::array<std::vector<float>, 3> mean;
  std::array<std::vector<char>, 3> finite;
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
    finite[c].assign(n, 0);
    for (std::size_t v = 0; v < n; ++v) {
      mean[c][v] = static_cast<float>(s1[v] / nf);
      finite[c][v] = std::isfinite(s1[v]) && std::isfinite(s2[v]);
      const double var = std::max(0.0, s2[v] / nf - (s1[v] / nf) * (s1[v] / nf));
      if (finite[c][v])
        sd[v] = std::max(sd[v], static_cast<float>(std::sqrt(var)));
    }
  }
  for (std::size_t v = 0; v < n; ++v)
    if (!finite[0][v] && !finite[1][v] && !finite[2][v])
      with_signal[v] = 0;
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

  // Least squares on the static voxels, per component over those where it is a number:
  // normal equations (10 x 10 at most), solved by LDLT; then robust refits: a voxel whose
  // time mean lies more than 3 robust SDs (1.4826 x the median absolute residual) from the
  // fit in any component is dropped, which removes slow blood that passed the SD test (it
  // would bias the fit by its mean flow). A component with too few such voxels (none: all
  // NaN) gets no offset.
  std::vector<std::size_t> fit_voxels;
  for (std::size_t v = 0; v < n; ++v)
    if (with_signal[v] && !flowing[v] && sd[v] <= sd_limit)
      fit_voxels.push_back(v);
  std::vector<double> mono;
  monomials({0, 0, 0}, options.order, mono);
  const int nt = static_cast<int>(mono.size());
  const std::size_t needed = static_cast<std::size_t>(3 * nt);
  auto position = [&](std::size_t v) {
    const int i = static_cast<int>(v % g.size[0]);
    const int j = static_cast<int>((v / g.size[0]) % g.size[1]);
    const int k = static_cast<int>(v / (static_cast<std::size_t>(g.size[0]) * g.size[1]));
    return normalized_position(g, i, j, k);
  };
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(nt, 3);
  for (int pass = 0; pass < 4; ++pass) {
    if (fit_voxels.size() < needed)
      throw SolverError(fmt::format("background correction: {} static voxels, fewer than the "
                                    "{} needed for an order-{} fit",
                                    fit_voxels.size(), needed, options.order));
    for (int c = 0; c < 3; ++c) {
      Eigen::MatrixXd ata = Eigen::MatrixXd::Zero(nt, nt);
      Eigen::VectorXd atb = Eigen::VectorXd::Zero(nt);
      std::size_t used = 0;
      for (std::size_t v : fit_voxels) {
        if (!finite[c][v])
          continue;
        monomials(position(v), options.order, mono);
        const Eigen::Map<const Eigen::VectorXd> m(mono.data(), nt);
        ata.noalias() += m * m.transpose();
        atb += mean[c][v] * m;
        ++used;
      }
      a.col(c) =
          used >= needed ? Eigen::VectorXd(ata.ldlt().solve(atb)) : Eigen::VectorXd::Zero(nt);
    }
    if (pass == 3)
      break;
    std::array<std::vector<float>, 3> residual; // 0 where the component is not a number
    for (std::size_t v : fit_voxels) {
      monomials(position(v), options.order, mono);
      const Eigen::Map<const Eigen::VectorXd> m(mono.data(), nt);
      for (int c = 0; c < 3; ++c)
        residual[c].push_back(finite[c][v] ? static_cast<float>(mean[c][v] - m.dot(a.col(c)))
                                           : 0.0f);
    }
    std::array<double, 3> limit{};
    for (int c = 0; c < 3; ++c) {
      std::vector<float> absolute;
      for (std::size_t l = 0; l < fit_voxels.size(); ++l)
        if (finite[c][fit_voxels[l]])
          absolute.push_back(std::abs(residual[c][l]));
      if (absolute.empty()) {
        limit[c] = 0.0; // its residuals are all 0
        continue;
      }
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
  std::array<std::size_t, 3> count{};
  for (std::size_t v : fit_voxels) {
    fitted[v] = 1;
    for (int c = 0; c < 3; ++c)
      if (finite[c][v]) {
        sum2[c] += double(mean[c][v]) * mean[c][v];
        ++count[c];
      }
  }
  for (int c = 0; c < 3; ++c) {
    report.coefficients[c].assign(a.col(c).data(), a.col(c).data() + nt);
    report.rms_before[c] = count[c] > 0 ? std::sqrt(sum2[c] / count[c]) : 0.0;
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
          if (fitted[v] && finite[c][v])
            res2[c] += (mean[c][v] - b) * (mean[c][v] - b);
        }
      }
  for (int c = 0; c < 3; ++c)
    report.rms_after[c] = count[c] > 0 ? std::sqrt(res2[c] / count[c]) : 0.0;
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
        if (!std::isfinite(x) || !std::isfinite(previous)) { // see the 4D loop below
          previous = std::isfinite(x) ? x : previous;
          continue;
        }
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
        // A value that is not a number stays as it is (a measurement reading it refuses) and
        // is no reference: the next number is unwrapped against the last one before it, and
        // the first number after leading NaNs is the reference, as frame 0 would be. (A NaN
        // as reference made every later frame NaN: NaN jumps are not zero.)
        if (!std::isfinite(x) || !std::isfinite(previous)) {
          previous = std::isfinite(x) ? double(x) : previous;
          continue;
        }
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
