// Landmark-plane flow from 4D-flow data (plane_flow.hpp for the method).
#include "mri/plane_flow.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>

#include <fmt/format.h>

#include "analysis/landmark_sections.hpp"
#include "core/error.hpp"
#include "core/units.hpp"
#include "mri/non_finite.hpp"
#include "mri/pixel_regions.hpp"

namespace tearflow::mri {

namespace {

Vec3 unit(const Vec3& v) {
  return (1.0 / std::sqrt(dot(v, v))) * v;
}

/// Two unit vectors spanning the plane normal to n.
std::pair<Vec3, Vec3> plane_axes(const Vec3& n) {
  const Vec3 helper = std::abs(n[0]) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
  const Vec3 e1 = unit(cross(n, helper));
  return {e1, cross(n, e1)};
}

/// The reformatted plane: per pixel magnitude and through-plane velocity of one frame.
struct Reformat {
  int side = 0;
  double pixel = 0.0;
  std::vector<Trilinear> weights; ///< per pixel (voxel < 0 weight: outside the image)
  std::vector<char> inside;
};

Reformat make_reformat(const ImageGrid& g, const geometry::Landmark& lm, const PlaneOptions& o) {
  Reformat r;
  r.pixel = o.pixel > 0 ? o.pixel : 0.5 * std::min({g.spacing[0], g.spacing[1], g.spacing[2]});
  r.side = 2 * static_cast<int>(std::ceil(o.half_width / r.pixel)) + 1;
  const Vec3 n = unit(lm.normal);
  const auto [e1, e2] = plane_axes(n);
  const int h = r.side / 2;
  r.weights.resize(static_cast<std::size_t>(r.side) * r.side);
  r.inside.resize(r.weights.size());
  for (int b = 0; b < r.side; ++b)
    for (int a = 0; a < r.side; ++a) {
      const Vec3 p = lm.origin + ((a - h) * r.pixel) * e1 + ((b - h) * r.pixel) * e2;
      const std::size_t px = static_cast<std::size_t>(b) * r.side + a;
      r.inside[px] = r.weights[px].locate(g, g.index(p));
    }
  return r;
}

/// The pixel of a patient point on the plane (projected), or -1 outside the square.
long pixel_of(const Reformat& r, const geometry::Landmark& lm, const Vec3& p) {
  const Vec3 n = unit(lm.normal);
  const auto [e1, e2] = plane_axes(n);
  const int h = r.side / 2;
  const int a = static_cast<int>(std::lround(dot(p - lm.origin, e1) / r.pixel)) + h;
  const int b = static_cast<int>(std::lround(dot(p - lm.origin, e2) / r.pixel)) + h;
  if (a < 0 || b < 0 || a >= r.side || b >= r.side)
    return -1;
  return static_cast<long>(b) * r.side + a;
}

/// The voxels that the pixels `used(p)` of the plane read (those of weight > 0), once each.
template <typename Used> std::vector<std::size_t> voxels_read(const Reformat& r, Used&& used) {
  std::vector<std::size_t> voxels;
  for (std::size_t p = 0; p < r.weights.size(); ++p)
    if (r.inside[p] && used(p))
      for (int c = 0; c < 8; ++c)
        if (r.weights[p].weight[c] != 0.0)
          voxels.push_back(r.weights[p].voxel[c]);
  std::sort(voxels.begin(), voxels.end());
  voxels.erase(std::unique(voxels.begin(), voxels.end()), voxels.end());
  return voxels;
}

} // namespace

std::vector<PlaneSeries> measure_planes(const Flow4D& data, const geometry::Landmarks& landmarks,
                                        const PlaneOptions& o) {
  const ImageGrid& g = data.grid;
  std::vector<PlaneSeries> out;
  // Frame 0's lumen region and lumen point per landmark, to check that a station's TL and FL
  // planes picked two different regions.
  std::vector<Pixels> first_region;
  std::vector<long> seeds;
  for (const geometry::Landmark& lm : landmarks.planes) {
    const Reformat r = make_reformat(g, lm, o);
    const Vec3 n = unit(lm.normal);
    const double dA = r.pixel * r.pixel;
    double voxel = 0.0; // the largest spacing along an axis with more than one voxel
    for (int a = 0; a < 3; ++a)
      if (g.size[a] > 1)
        voxel = std::max(voxel, g.spacing[a]);
    const double margin = o.flow_margin >= 0 ? o.flow_margin : 0.5 * voxel;
    const int grow = static_cast<int>(std::lround(margin / r.pixel));
    long seed = pixel_of(r, lm, lm.point.value_or(lm.origin));
    if (seed < 0 || !r.inside[seed])
      input_error("landmark '{}': its lumen point lies outside the image", lm.name);
    PlaneSeries s;
    s.name = lm.name;
    const std::size_t npx = r.weights.size();
    std::vector<double> mag(npx), vn(npx);
    Pixels mask(npx);
    for (std::size_t f = 0; f < data.frames.size(); ++f) {
      const Frame& fr = data.frames[f];
      for (std::size_t p = 0; p < npx; ++p) {
        if (!r.inside[p]) {
          mag[p] = vn[p] = 0.0;
          continue;
        }
        const Trilinear& w = r.weights[p];
        mag[p] = w(fr.magnitude);
        vn[p] = w(fr.velocity[0]) * n[0] + w(fr.velocity[1]) * n[1] + w(fr.velocity[2]) * n[2];
      }
      // The lumen point's magnitude: median of its 3 x 3 pixels (robust to noise).
      std::vector<double> around;
      const int sa = static_cast<int>(seed % r.side), sb = static_cast<int>(seed / r.side);
      for (int db = -1; db <= 1; ++db)
        for (int da = -1; da <= 1; ++da) {
          const int x = sa + da, y = sb + db;
          if (x >= 0 && y >= 0 && x < r.side && y < r.side)
            around.push_back(mag[static_cast<std::size_t>(y) * r.side + x]);
        }
      if (std::any_of(around.begin(), around.end(), [](double m) { return !std::isfinite(m); })) {
        refuse_non_finite(data, f,
                          voxels_read(r,
                                      [&](std::size_t p) {
                                        const long a = static_cast<long>(p % r.side) - sa;
                                        const long b = static_cast<long>(p / r.side) - sb;
                                        return std::abs(a) <= 1 && std::abs(b) <= 1;
                                      }),
                          0, 0, fmt::format("landmark '{}'", lm.name),
                          "its lumen point's magnitude", "its lumen cannot be found");
        input_error("landmark '{}', frame {} (t = {:.4g} s): the magnitude at its lumen point is "
                    "not a number",
                    lm.name, f, fr.time); // not reached: a sample is NaN through a voxel only
      }
      std::nth_element(around.begin(), around.begin() + around.size() / 2, around.end());
      const double threshold = o.lumen_fraction * around[around.size() / 2];
      if (!(threshold > 0))
        input_error("landmark '{}', frame {}: no signal at the lumen point", lm.name, f);
      for (std::size_t p = 0; p < npx; ++p)
        mask[p] = r.inside[p] && mag[p] >= threshold;
      mask[seed] = 1; // the point is in its lumen by definition
      const Pixels lumen = region_of(mask, {r.side, r.side}, static_cast<std::size_t>(seed));
      if (const double share = border_share(lumen, {r.side, r.side}, &r.inside);
          share > kFloodedBorderShare)
        input_error("landmark '{}', frame {} (t = {:.4g} s): its lumen region reaches the edge "
                    "of the {:.0f} mm square around the plane or of the image along {:.0f} % of "
                    "its outline: the lumen point is not in a vessel (a seed in tissue floods "
                    "it), or the image cuts the vessel",
                    lm.name, f, fr.time, 2 * o.half_width * 1e3, 100 * share);
      if (f == 0) {
        first_region.push_back(lumen);
        seeds.push_back(seed);
      }
      const Pixels flow_region = grown(lumen, {r.side, r.side}, grow);
      if (o.track)
        seed = static_cast<long>(deepest_pixel(lumen, {r.side, r.side}));
      // A NaN in the section would make the flow NaN or, through the magnitude mask, cut a
      // hole in the lumen: either changes the result, so it is refused, naming the images
      // (their files) and the frame. Values elsewhere in the plane change nothing.
      const auto in_section = [&](std::size_t p) { return flow_region[p] && r.inside[p]; };
      std::size_t not_numbers = 0;
      for (std::size_t p = 0; p < npx; ++p)
        if (in_section(p) && !(std::isfinite(vn[p]) && std::isfinite(mag[p])))
          ++not_numbers;
      if (not_numbers > 0) {
        refuse_non_finite(data, f, voxels_read(r, in_section), 0, 3,
                          fmt::format("landmark '{}'", lm.name), "its lumen's section",
                          "the flow would be wrong");
        input_error("landmark '{}', frame {} (t = {:.4g} s): {} pixel(s) of its lumen's section "
                    "are not numbers",
                    lm.name, f, fr.time, not_numbers); // not reached (above)
      }
      double area = 0.0, flow = 0.0, peak = -1e300;
      for (std::size_t p = 0; p < npx; ++p) {
        if (lumen[p]) {
          area += dA;
          peak = std::max(peak, vn[p]);
        }
        if (flow_region[p] && r.inside[p])
          flow += vn[p] * dA;
      }
      s.flow.push_back(flow);
      s.area.push_back(area);
      s.peak_velocity.push_back(peak);
    }
    out.push_back(std::move(s));
  }
  const auto& planes = landmarks.planes;
  for (std::size_t a = 0; a < planes.size(); ++a)
    for (std::size_t b = 0; b < planes.size(); ++b) {
      const int k = analysis::station_of(planes[a]);
      const Vec3 d = planes[a].origin - planes[b].origin;
      const bool same_plane =
          dot(d, d) < 1e-18 && dot(unit(planes[a].normal), unit(planes[b].normal)) > 1 - 1e-12;
      if (a != b && k > 0 && planes[a].lumen == "TL" && planes[b].lumen == "FL" &&
          analysis::station_of(planes[b]) == k && same_plane && first_region[a][seeds[b]])
        input_error("landmarks '{}' and '{}': their lumen points fall in one connected lumen "
                    "region (frame 0): the flap between them is not resolved at this voxel "
                    "size, or the lumen threshold is too low (raise --lumen-fraction)",
                    planes[a].name, planes[b].name);
    }
  return out;
}

void write_measured_tables(const Flow4D& data, const std::vector<PlaneSeries>& series,
                           const std::filesystem::path& dir) {
  std::filesystem::create_directories(dir);
  auto write = [&](const char* name, const char* suffix, double scale,
                   std::vector<double> PlaneSeries::*field) {
    const std::filesystem::path file = dir / name;
    std::ofstream out(file);
    if (!out)
      input_error("cannot write '{}'", file.string());
    out << "time_s";
    for (const PlaneSeries& s : series)
      out << ',' << s.name << suffix;
    out << '\n';
    for (std::size_t f = 0; f < data.frames.size(); ++f) {
      out << fmt::format("{:.6g}", data.frames[f].time);
      for (const PlaneSeries& s : series)
        out << ',' << fmt::format("{:.8g}", (s.*field)[f] / scale);
      out << '\n';
    }
  };
  write("flow.csv", "_mL_per_s", units::mL, &PlaneSeries::flow);
  write("area.csv", "_mm2", units::mm * units::mm, &PlaneSeries::area);
  write("velocity.csv", "_peak_m_per_s", 1.0, &PlaneSeries::peak_velocity);
}

} // namespace tearflow::mri
