// A vessel's flow from a 2D phase-contrast scan (vessel_flow.hpp for the method).
#include "mri/vessel_flow.hpp"

#include <cmath>
#include <numbers>
#include <numeric>

#include <fmt/format.h>

#include "core/error.hpp"

namespace tearflow::mri {

namespace {

/// The landmark plane lying in the slice nearest its centre: its lumen point (or origin)
/// projected onto the slice, and +-1 for its normal's side of the slice normal.
std::optional<std::pair<const geometry::Landmark*, Vec3>>
landmark_in_slice(const ImageGrid& g, const geometry::Landmarks& landmarks) {
  const Vec3& n = g.direction[2];
  const Vec3 centre = g.point({0.5 * (g.size[0] - 1), 0.5 * (g.size[1] - 1), 0.0});
  const double reach = slice_reach(g);
  std::optional<std::pair<const geometry::Landmark*, Vec3>> best;
  double best_distance = 1e300;
  for (const geometry::Landmark& l : landmarks.planes) {
    const double len = std::sqrt(dot(l.normal, l.normal));
    if (!(len > 0) || std::abs(dot(l.normal, n)) / len < std::cos(std::numbers::pi / 6))
      continue;
    const Vec3 p = l.point.value_or(l.origin);
    const double off = dot(p - centre, n);
    const Vec3 on_slice = p - off * n;
    const Vec3 index = g.index(on_slice);
    const bool inside =
        index[0] >= 0 && index[1] >= 0 && index[0] <= g.size[0] - 1 && index[1] <= g.size[1] - 1;
    if (!inside || std::abs(off) > reach)
      continue;
    const Vec3 d = on_slice - centre;
    const double distance = std::abs(off) + std::sqrt(dot(d, d));
    if (distance < best_distance) {
      best_distance = distance;
      best = std::pair{&l, on_slice};
    }
  }
  return best;
}

} // namespace

double VesselFlow::mean_flow() const {
  return flow.empty() ? 0.0 : std::accumulate(flow.begin(), flow.end(), 0.0) / flow.size();
}

bc::Waveform VesselFlow::waveform() const {
  return bc::Waveform::periodic(time, flow, period, fmt::format("the flow of scan '{}'", name));
}

VesselFlow measure_vessel(const Flow4D& scan, const std::string& name, const VesselSeed& seed,
                          PlaneOptions options) {
  scan.require(Encoding::through_plane, fmt::format("scan '{}'", name));
  const ImageGrid& g = scan.grid;
  const Vec3& n = g.direction[2];
  VesselFlow out;
  out.name = name;
  std::optional<int> landmark_sign;
  if (seed.point) {
    scan.check_in_slice(*seed.point, fmt::format("scan '{}': the seed point", name));
    out.seed = *seed.point - dot(*seed.point - g.origin, n) * n;
    out.seed_from = "given";
    const Vec3 index = g.index(out.seed);
    if (!(index[0] >= -0.5 && index[1] >= -0.5 && index[0] <= g.size[0] - 0.5 &&
          index[1] <= g.size[1] - 0.5))
      input_error("scan '{}': the seed point ({:.1f}, {:.1f}, {:.1f}) mm lies outside the slice's "
                  "field of view",
                  name, (*seed.point)[0] * 1e3, (*seed.point)[1] * 1e3, (*seed.point)[2] * 1e3);
  } else if (auto found = seed.landmarks ? landmark_in_slice(g, *seed.landmarks) : std::nullopt) {
    out.seed = found->second;
    out.seed_from = "landmark " + found->first->name;
    landmark_sign = dot(found->first->normal, n) >= 0 ? 1 : -1;
  } else {
    out.seed = g.point({0.5 * (g.size[0] - 1), 0.5 * (g.size[1] - 1), 0.0});
    out.seed_from = "slice centre";
  }
  // The slice's own plane with the lumen point at the seed, the lumen followed.
  geometry::Landmark plane{name, out.seed, n, "aorta", out.seed};
  options.track = true;
  if (!(options.pixel > 0))
    options.pixel = 0.5 * std::min(g.spacing[0], g.spacing[1]);
  geometry::Landmarks one;
  one.planes.push_back(plane);
  PlaneSeries series = std::move(measure_planes(scan, one, options).front());
  for (const Frame& f : scan.frames)
    out.time.push_back(f.time);
  out.area = std::move(series.area);
  const double mean = std::accumulate(series.flow.begin(), series.flow.end(), 0.0);
  out.sign = landmark_sign.value_or(mean >= 0 ? 1 : -1);
  for (double q : series.flow)
    out.flow.push_back(out.sign * q);
  out.period = scan.cycle(fmt::format("scan '{}'", name));
  return out;
}

} // namespace tearflow::mri
