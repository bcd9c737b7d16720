#include "geometry/lumen_sizing.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace tearflow::geometry {

namespace {
// Spacing of the precomputed sections [m]: the radius and flap offset change by well under
// 0.1 mm over 1 mm, so the nearest section describes a point's surroundings.
constexpr double kSampleSpacing = 1e-3;
} // namespace

LumenSizing::LumenSizing(const TbadModel& model) {
  const TbadSpec& spec = model.spec();
  global_ = spec.element_size;
  h_ = spec.wall_thickness;
  elements_ = spec.lumen_elements;
  if (elements_ <= 0)
    return;
  // The refined zone spans the flap with the false lumen's end caps.
  s0_ = model.flap_start() - h_;
  s1_ = model.flap_end() + h_;
  // Beyond the zone the size grows from the finest by kGrading per unit distance; sample far
  // enough for it to reach the global size.
  double finest = global_;
  for (double s = s0_; s <= s1_; s += kSampleSpacing)
    finest = std::min(finest, std::max(0.1 * global_, model.true_lumen_thickness(s) / elements_));
  const double reach = (global_ - finest) / kGrading + kSampleSpacing;
  const double first = std::max(0.0, s0_ - reach), last = std::min(model.length(), s1_ + reach);
  const int n = static_cast<int>(std::ceil((last - first) / kSampleSpacing)) + 1;
  samples_.reserve(n);
  for (int i = 0; i < n; ++i) {
    Sample x;
    x.s = first + (last - first) * i / std::max(1, n - 1);
    x.frame = model.frame(x.s);
    x.radius = model.radius(x.s);
    x.offset = model.flap_offset(x.s);
    const double clamped = std::clamp(x.s, model.flap_start(), model.flap_end());
    // Floored at a tenth of the global size, so that a very thin TL (small --tl-areas)
    // cannot drive the size towards zero and the tet count without bound.
    x.fine = std::clamp(model.true_lumen_thickness(clamped) / spec.lumen_elements, 0.1 * global_,
                        global_);
    samples_.push_back(x);
  }
}

double LumenSizing::size(const Vec3& p) const {
  if (samples_.empty())
    return global_;
  // The nearest section (brute force: a few hundred samples, a few million queries).
  const Sample* near = nullptr;
  double best = std::numeric_limits<double>::max();
  for (const Sample& x : samples_) {
    const Vec3 d = p - x.frame.origin;
    const double dd = dot(d, d);
    if (dd < best)
      best = dd, near = &x;
  }
  const Frame& f = near->frame;
  const Vec3 d = p - f.origin;
  const double s = near->s + dot(d, f.tangent);
  const double y = dot(d, f.normal), x = dot(d, f.across);
  const double r = std::sqrt(x * x + y * y);
  if (r > near->radius + h_ + global_)
    return global_; // another part of the aorta, or a branch
  // The refined zone: the true lumen (beyond the flap's TL face at offset + h/2), the flap
  // with its tears, and a band of half the TL thickness beside the flap's FL face, within
  // the lumen. Outside it the size grows with the distance from it along the vessel, across
  // the flap and out of the lumen.
  const double band = 0.5 * near->fine * elements_;
  const double along = std::max({0.0, s0_ - s, s - s1_});
  const double across = std::max(0.0, near->offset - 0.5 * h_ - band - y);
  const double out = std::max(0.0, r - near->radius);
  const double distance = std::sqrt(along * along + across * across + out * out);
  return std::min(global_, near->fine + kGrading * distance);
}

} // namespace tearflow::geometry
