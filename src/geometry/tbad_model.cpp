// Layout of the parametric TBAD: centreline by integration of its tangent, lumen radius and
// flap offset by monotone cubic interpolation between stations where they are solved from
// the requested TL and FL areas.
#include "geometry/tbad_model.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "core/error.hpp"

namespace tearflow::geometry {

namespace {

constexpr double pi = std::numbers::pi;
constexpr double kStep = 0.1e-3; // centreline sampling step [m]: 0.1 mm, far below any radius

Vec3 normalized(const Vec3& v) {
  return (1.0 / std::sqrt(dot(v, v))) * v;
}

// Smooth step 3t^2 - 2t^3 and its derivative: the arch's turning angle follows it, so the
// curvature rises and falls continuously; its peak slope is 1.5.
double smoothstep(double t) {
  t = std::clamp(t, 0.0, 1.0);
  return t * t * (3 - 2 * t);
}

// Monotone cubic (Fritsch-Carlson) through knots (x, y): no overshoot between knots, and
// flat between equal values, so the flap stays flat around the tears.
double monotone_cubic(const std::vector<std::array<double, 2>>& k, double x) {
  const std::size_t n = k.size();
  if (x <= k.front()[0])
    return k.front()[1];
  if (x >= k.back()[0])
    return k.back()[1];
  std::vector<double> d(n - 1), m(n);
  for (std::size_t i = 0; i + 1 < n; ++i)
    d[i] = (k[i + 1][1] - k[i][1]) / (k[i + 1][0] - k[i][0]);
  m[0] = d[0];
  m[n - 1] = d[n - 2];
  for (std::size_t i = 1; i + 1 < n; ++i)
    m[i] = d[i - 1] * d[i] <= 0 ? 0.0 : 2.0 / (1.0 / d[i - 1] + 1.0 / d[i]);
  std::size_t i = 0;
  while (x > k[i + 1][0])
    ++i;
  const double h = k[i + 1][0] - k[i][0], t = (x - k[i][0]) / h;
  const double h00 = (1 + 2 * t) * (1 - t) * (1 - t), h10 = t * (1 - t) * (1 - t);
  const double h01 = t * t * (3 - 2 * t), h11 = t * t * (t - 1);
  return h00 * k[i][1] + h10 * h * m[i] + h01 * k[i + 1][1] + h11 * h * m[i + 1];
}

// Radius R and flap offset e of a circular lumen split by a flap of thickness h into a true
// lumen of area tl (beyond the flap's face at e + h/2) and a false lumen of area fl (beyond
// e - h/2 on the other side). For fixed R the TL area fixes e; the FL area then grows with
// R, so bisection on R.
std::array<double, 2> split_circle(double tl, double fl, double h) {
  auto chord_for_tl = [&](double r) { // d = e + h/2 with segment(r, d) = tl, or NaN
    double lo = h - r, hi = r;
    if (!(circular_segment_area(r, lo) > tl))
      return std::nan("");
    for (int it = 0; it < 200; ++it) {
      const double mid = 0.5 * (lo + hi);
      (circular_segment_area(r, mid) > tl ? lo : hi) = mid;
    }
    return 0.5 * (lo + hi);
  };
  double lo = std::sqrt((tl + fl) / pi), hi = 10 * lo + 10 * h;
  for (int it = 0; it < 200; ++it) {
    const double r = 0.5 * (lo + hi), d = chord_for_tl(r);
    const bool too_small = std::isnan(d) || circular_segment_area(r, h - d) < fl;
    (too_small ? lo : hi) = r;
  }
  const double r = 0.5 * (lo + hi);
  return {r, chord_for_tl(r) - 0.5 * h};
}

// Radius of a circular lumen whose false lumen, beyond a flap of thickness h, is `depth`
// deep (flap to wall) and whose true lumen has area tl: the TL is the circle less a segment
// of height depth + h, so its area grows with the radius; bisection.
double radius_with_true_lumen(double tl, double depth, double h) {
  double lo = depth + h, hi = depth + h + std::sqrt(tl / pi) + 1.0;
  for (int it = 0; it < 200; ++it) {
    const double r = 0.5 * (lo + hi);
    (circular_segment_area(r, depth + h - r) < tl ? lo : hi) = r;
  }
  return 0.5 * (lo + hi);
}

} // namespace

double circular_segment_area(double r, double d) {
  d = std::clamp(d, -r, r);
  return r * r * std::acos(d / r) - d * std::sqrt(r * r - d * d);
}

double TearGeometry::area() const {
  return pi * axial * across;
}

TbadModel::TbadModel(const TbadSpec& spec) : spec_(spec) {
  validate(spec_);
  spec_.exit_tear.position = resolved_exit_tear_position(spec_);
  const TbadSpec& s = spec_;
  const double h = s.wall_thickness;

  // Arclength layout, proximal to distal.
  s_arch0_ = s.inlet_extension + s.ascending_length;
  arch_length_ = 1.5 * pi * s.arch_radius; // peak turn rate 1.5 pi / L = 1 / arch_radius
  const BranchSpec& lsa = s.branches[2];
  const double s_lsa = s_arch0_ + lsa.arch_position * arch_length_;

  // Centreline angles: theta turns in the arch plane (y, z), phi tilts out of it (x).
  auto theta = [&](double x) {
    double t = pi * smoothstep((x - s_arch0_) / arch_length_);
    if (x > s_bend0_ && x < s_bend1_) {
      const double q = std::sin(pi * (x - s_bend0_) / (s_bend1_ - s_bend0_));
      t -= s.descending_bend * q * q; // bends in the arch plane: the flap stays flat
    }
    return t;
  };
  auto phi = [&](double x) {
    if (x <= s.inlet_extension || x >= s_arch0_)
      return 0.0;
    const double q = std::sin(pi * (x - s.inlet_extension) / s.ascending_length);
    return bow_angle_ * q * q;
  };
  // The bow: the ascending aorta leaves the inlet at ascending_bow from the arch plane; the
  // angle for it by bisection on the integral of sin(phi) over the ascending aorta.
  {
    double lo = 0, hi = 1.2;
    for (int it = 0; it < 60; ++it) {
      bow_angle_ = 0.5 * (lo + hi);
      double offset = 0;
      for (double x = s.inlet_extension; x < s_arch0_; x += kStep)
        offset += std::sin(phi(x + 0.5 * kStep)) * kStep;
      (offset < s.ascending_bow ? lo : hi) = bow_angle_;
    }
  }

  // Branches: from the centreline, between straight up and the arch's outward normal.
  for (int i = 0; i < 3; ++i) {
    const BranchSpec& b = s.branches[i];
    branches_[i].name = b.name;
    branches_[i].radius = b.radius;
    branches_[i].length = b.length;
  }

  // The flap starts distal to the LSA's footprint on the aortic wall (half its outer width
  // over the sine of its angle to the aorta, plus its lean along the aorta).
  {
    const double th = theta(s_lsa);
    const Vec3 t{0, std::sin(th), std::cos(th)}, out{0, -std::cos(th), std::sin(th)};
    const Vec3 d = normalized(Vec3{0, 0, 1} + out);
    const double c = dot(d, t), sn = std::sqrt(1 - c * c);
    const double r_outer = s.arch_distal_radius + h;
    s_flap0_ = s_lsa + (lsa.radius + h) / sn + std::max(0.0, r_outer * c / sn) + s.flap_start_gap;
  }
  s_taper0_ = s_flap0_ + s.flap_length;
  s_flap1_ = s_taper0_ + s.taper_length;
  const double s_entry = s_flap0_ + s.entry_tear.position;
  const double s_exit = s_taper0_ - s.exit_tear.position;
  s_outlet_ = s_flap1_ + s.outlet_distance;
  s_bend0_ = s_arch0_ + arch_length_;
  s_bend1_ = s_exit - 30e-3; // straight from 30 mm above the exit tear to the outlet
  if (!(s_bend1_ > s_bend0_ + 20e-3))
    input_error("tbad: flap length {} mm is too short: the exit tear must lie at least 50 mm "
                "distal to the arch; lengthen the flap",
                s.flap_length * 1e3);

  // Integrate the tangent.
  const std::size_t n = static_cast<std::size_t>(std::ceil(s_outlet_ / kStep)) + 2;
  ds_ = s_outlet_ / static_cast<double>(n - 1);
  points_.resize(n);
  tangents_.resize(n);
  auto tangent = [&](double x) {
    const double th = theta(x), ph = phi(x);
    return Vec3{std::sin(ph), std::cos(ph) * std::sin(th), std::cos(ph) * std::cos(th)};
  };
  points_[0] = {-s.ascending_bow, 0, 0}; // arch and descending aorta in the plane x = 0
  tangents_[0] = tangent(0);
  for (std::size_t i = 1; i < n; ++i) {
    const double x = static_cast<double>(i) * ds_;
    tangents_[i] = tangent(x);
    // Simpson's rule on each step.
    points_[i] = points_[i - 1] +
                 (ds_ / 6.0) * (tangents_[i - 1] + 4.0 * tangent(x - 0.5 * ds_) + tangents_[i]);
  }

  for (int i = 0; i < 3; ++i) {
    const double sb = s_arch0_ + s.branches[i].arch_position * arch_length_;
    const double th = theta(sb);
    const Vec3 out{0, -std::cos(th), std::sin(th)};
    branches_[i].base = frame(sb).origin;
    branches_[i].direction = normalized(Vec3{0, 0, 1} + out);
  }

  lay_out_stations();
  solve_dissected_profile();

  // Radius knots. The aorta tapers over the arch, widens after the LSA to the dissected
  // segment's size, keeps TL5's past the exit tear to the flap's taper, narrows over the
  // taper as the false lumen closes, and reaches DAo_dist's distal to the FL's end cap.
  const double r_aao = std::sqrt(s.aao_area / pi), r_dist = std::sqrt(s.dao_dist_area / pi);
  double s_dist = 0;
  for (const Station& st : stations_)
    if (st.name == "DAo_dist")
      s_dist = st.s;
  radius_knots_ = {
      {0, r_aao}, {s_arch0_, r_aao}, {s_lsa, s.arch_distal_radius}, {s_flap0_, station_radius_[0]}};
  offset_knots_ = {{s_flap0_, station_offset_[0]}, {s_entry, station_offset_[0]}};
  for (int k = 0; k < 5; ++k) {
    radius_knots_.push_back({paired_station(k + 1), station_radius_[k]});
    offset_knots_.push_back({paired_station(k + 1), station_offset_[k]});
  }
  // The distal re-attachment (docs/geometry.md, "The flap's distal taper"). All the false
  // lumen's flow leaves it through the exit tear and then passes the true lumen beside and
  // distal to the tear: a TL of TL5's size there was a stenosis of the model. So from TL5
  // the flap moves to the vessel's centre (or stays where it is if already on the FL's side),
  // is flat across the exit tear (its hole is cut and measured in a flat flap) to the taper's
  // start, and over the taper moves on to the FL's side, the FL closing to fl_end_depth at
  // its end cap. The radius narrows over the taper to the one whose TL there has DAo_dist's
  // area; the TL thus widens from the tear on and never falls below its size at the tear.
  const double e_tear = std::min(0.0, station_offset_[4]);
  const double r_end = radius_with_true_lumen(s.dao_dist_area, s.fl_end_depth, h);
  const double e_end = s.fl_end_depth + 0.5 * h - r_end;
  const double fl_depth_at_tear = station_radius_[4] + e_tear - 0.5 * h;
  if (!(s.fl_end_depth < fl_depth_at_tear - h))
    input_error("tbad: false lumen end depth {} mm must be less than its depth at the exit tear "
                "({:.1f} mm) less one wall thickness: the flap's taper closes the false lumen",
                s.fl_end_depth * 1e3, fl_depth_at_tear * 1e3);
  const double exit_axial = std::sqrt(s.exit_tear.area * s.exit_tear.aspect / pi);
  // The proximal rim; a tear reaching TL5 is refused by check_fit, with a clamped knot here.
  const double rim = std::max(s_exit - exit_axial, paired_station(5) + 0.5 * h);
  offset_knots_.push_back({rim, e_tear});
  offset_knots_.push_back({s_taper0_, e_tear});
  offset_knots_.push_back({s_flap1_, e_end});
  offset_knots_.push_back({s_flap1_ + h, e_end}); // flat at the end cap
  radius_knots_.push_back({s_taper0_, station_radius_[4]});
  radius_knots_.push_back({s_flap1_, r_end});
  radius_knots_.push_back({s_flap1_ + h, r_end}); // flat at the end cap, as the flap
  radius_knots_.push_back({s_dist - 3e-3, r_dist});
  radius_knots_.push_back({s_outlet_, r_dist});
  for (std::size_t i = 1; i < radius_knots_.size(); ++i)
    if (!(radius_knots_[i][0] > radius_knots_[i - 1][0]))
      input_error("tbad: the landmarks overlap (flap {} mm, station offset {} mm, outlet distance "
                  "{} mm): lengthen the flap or the outlet distance",
                  s.flap_length * 1e3, s.station_offset * 1e3, s.outlet_distance * 1e3);

  // Tears: on the flap's mid-surface, elongated along the vessel.
  for (int i = 0; i < 2; ++i) {
    const TearSpec& t = i == 0 ? s.entry_tear : s.exit_tear;
    const double st = i == 0 ? s_entry : s_exit;
    const Frame f = frame(st);
    TearGeometry& g = tears_[i];
    g.name = i == 0 ? "entry" : "exit";
    g.centre = f.origin + flap_offset(st) * f.normal;
    g.normal = f.normal;
    g.axis = f.tangent;
    g.axial = std::sqrt(t.area * t.aspect / pi);
    g.across = std::sqrt(t.area / (pi * t.aspect));
  }
  check_fit();
}

void TbadModel::lay_out_stations() {
  const TbadSpec& s = spec_;
  const double s_entry = s_flap0_ + s.entry_tear.position;
  const double s_exit = s_taper0_ - s.exit_tear.position;
  const double first = s_entry + s.station_offset, last = s_exit - s.station_offset;
  if (!(last > first + 20e-3))
    input_error("tbad: flap length {} mm leaves no room for the five TL/FL stations between the "
                "tears (each {} mm from its tear); lengthen the flap",
                s.flap_length * 1e3, s.station_offset * 1e3);
  const double flap_end_wall = s_flap1_ + s.wall_thickness;
  // The inlet and outlet planes sit 1 mm inside the caps: a plane on a cap would cut the
  // fluid only in its boundary, and sections there are undefined.
  stations_ = {{"inlet", 1e-3},
               {"AAo", s.inlet_extension + 0.5 * s.ascending_length},
               {"DAo_prox", s_entry}};
  for (int k = 0; k < 5; ++k)
    stations_.push_back({std::to_string(k + 1), first + k * (last - first) / 4.0});
  if (!(s_outlet_ > flap_end_wall + 10e-3))
    input_error("tbad: outlet distance {} mm ends the domain within 10 mm of the flap's distal "
                "end cap ({} mm thick); increase the outlet distance",
                s.outlet_distance * 1e3, s.wall_thickness * 1e3);
  stations_.push_back({"DAo_dist", 0.5 * (flap_end_wall + s_outlet_) + 2e-3});
  stations_.push_back({"outlet", s_outlet_ - 1e-3});
}

void TbadModel::solve_dissected_profile() {
  for (int k = 0; k < 5; ++k) {
    const auto [r, e] = split_circle(spec_.tl_areas[k], spec_.fl_areas[k], spec_.wall_thickness);
    station_radius_[k] = r;
    station_offset_[k] = e;
  }
}

void TbadModel::check_fit() const {
  const TbadSpec& s = spec_;
  const double h = s.wall_thickness;
  // A tear must leave at least one wall thickness of flap around it (to the wall, to the
  // flap's end or taper, and to the nearest TL/FL plane), or the flap tears through there.
  const double ligament = h;
  for (int i = 0; i < 2; ++i) {
    const TearGeometry& g = tears_[i];
    const TearSpec& t = i == 0 ? s.entry_tear : s.exit_tear;
    const double st = i == 0 ? s_flap0_ + t.position : s_taper0_ - t.position;
    const double r = radius(st), e = flap_offset(st);
    const double half_width = std::sqrt(std::max(0.0, r * r - std::pow(std::abs(e) + h / 2, 2)));
    const double max_across = half_width - ligament;
    const double max_axial = std::min(t.position - ligament, s.station_offset - ligament);
    // 1 nm: the default exit tear sits exactly one ligament from the flap end (rounding).
    if (g.axial <= max_axial + 1e-9 && g.across <= max_across)
      continue;
    const double a = std::min(max_axial, t.aspect * max_across);
    const double largest = a > 0 ? pi * a * a / t.aspect : 0.0;
    input_error("tbad: {} tear area {:.1f} mm^2 is larger than the flap can hold: with aspect "
                "{} its semi-axes are {:.2f} mm along the vessel and {:.2f} mm across, but the "
                "flap leaves room for {:.2f} mm along (tear position {} mm, station offset {} "
                "mm) and {:.2f} mm across (flap {:.2f} mm wide), keeping {} mm of flap around "
                "it; the largest {} tear that fits is {:.1f} mm^2",
                g.name, t.area * 1e6, t.aspect, g.axial * 1e3, g.across * 1e3, max_axial * 1e3,
                t.position * 1e3, s.station_offset * 1e3, max_across * 1e3, 2 * half_width * 1e3,
                ligament * 1e3, g.name, largest * 1e6);
  }
  // The swept sections must not overlap: the centreline may bend no tighter than the outer
  // wall's radius, and within the flap no tighter than the flap's cutting box (radius + 6 mm).
  for (double x = 0; x < s_outlet_; x += 1e-3) {
    const bool flap = x > s_flap0_ - 2 * h && x < s_flap1_ + 2 * h;
    const double need = radius(x) + (flap ? 6e-3 + h : h);
    const double rc = min_curvature_radius(x, std::min(x + 1e-3, s_outlet_));
    if (rc < need)
      input_error("tbad: the centreline bends with radius {:.1f} mm at {:.0f} mm from the inlet, "
                  "tighter than the vessel there ({:.1f} mm); increase the arch radius",
                  rc * 1e3, x * 1e3, need * 1e3);
  }
}

Frame TbadModel::frame(double s) const {
  // Beyond the ends the centreline continues straight (the builder's lofts overrun them).
  const double beyond = s < 0 ? s : s > s_outlet_ ? s - s_outlet_ : 0.0;
  s = std::clamp(s, 0.0, s_outlet_);
  const double x = s / ds_;
  const std::size_t i = std::min(static_cast<std::size_t>(x), points_.size() - 2);
  const double w = x - static_cast<double>(i);
  Frame f;
  f.origin = (1 - w) * points_[i] + w * points_[i + 1];
  f.tangent = normalized((1 - w) * tangents_[i] + w * tangents_[i + 1]);
  // The arch plane's normal (x) projected normal to the tangent; the tangent tilts out of
  // the plane only in the ascending aorta, by less than 60 degrees (bow_angle_ <= 1.2 rad).
  const Vec3 ex{1, 0, 0};
  f.normal = normalized(ex - dot(ex, f.tangent) * f.tangent);
  f.across = cross(f.normal, f.tangent);
  f.origin = f.origin + beyond * f.tangent;
  return f;
}

double TbadModel::radius(double s) const {
  return monotone_cubic(radius_knots_, s);
}

double TbadModel::flap_offset(double s) const {
  return monotone_cubic(offset_knots_, s);
}

double TbadModel::flap_half_thickness(double s) const {
  // Central difference over 0.1 mm: the offset changes over millimetres.
  constexpr double d = 0.1e-3;
  const double slope = (flap_offset(s + d) - flap_offset(s - d)) / (2 * d);
  return 0.5 * spec_.wall_thickness * std::sqrt(1 + slope * slope);
}

double TbadModel::true_lumen_thickness(double s) const {
  return radius(s) - flap_offset(s) - 0.5 * spec_.wall_thickness;
}

double TbadModel::paired_station(int k) const {
  for (const Station& st : stations_)
    if (st.name == std::to_string(k))
      return st.s;
  input_error("tbad: no station {}", k);
}

Vec3 TbadModel::true_lumen_point(double s) const {
  const Frame f = frame(s);
  const double face = flap_offset(s) + 0.5 * spec_.wall_thickness;
  return f.origin + (0.5 * (face + radius(s))) * f.normal;
}

Vec3 TbadModel::false_lumen_point(double s) const {
  const Frame f = frame(s);
  const double face = flap_offset(s) - 0.5 * spec_.wall_thickness;
  return f.origin + (0.5 * (face - radius(s))) * f.normal;
}

double TbadModel::min_curvature_radius(double s0, double s1) const {
  double kappa = 0;
  const std::size_t i0 = static_cast<std::size_t>(std::max(0.0, s0 / ds_));
  const std::size_t i1 = std::min(points_.size() - 1, static_cast<std::size_t>(s1 / ds_) + 1);
  for (std::size_t i = std::max<std::size_t>(i0, 1); i <= i1; ++i) {
    const Vec3 dt = tangents_[i] - tangents_[i - 1];
    kappa = std::max(kappa, std::sqrt(dot(dt, dt)) / ds_);
  }
  return kappa > 0 ? 1.0 / kappa : 1e30;
}

} // namespace tearflow::geometry
