#pragma once
// The resolved TBAD model: the centreline as a function of arclength, the lumen radius and
// flap offset along it, and where the branches, tears and landmark stations sit. Pure
// geometry, no Gmsh: the builder sweeps its sections, the landmarks come from its frames,
// and tests can ask it what the mesh should look like. SI units throughout.
#include <array>
#include <string>
#include <vector>

#include "core/types.hpp"
#include "geometry/tbad_spec.hpp"

namespace tearflow::geometry {

/// A right-handed frame on the centreline: `tangent` along the flow, `normal` the flap's
/// normal pointing into the true lumen (the arch plane's normal, projected), `across` =
/// normal x tangent, in the flap's plane.
struct Frame {
  Vec3 origin, tangent, normal, across;
};

/// An elliptical tear: centre on the flap's mid-surface, semi-axes along the vessel
/// (`axial`) and across it.
struct TearGeometry {
  std::string name;             ///< "entry" or "exit"
  Vec3 centre, normal, axis;    ///< normal: the flap's, into the TL; axis: the long semi-axis
  double axial = 0, across = 0; ///< semi-axes [m]
  double area() const;
};

struct BranchGeometry {
  std::string name;
  Vec3 base, direction; ///< base on the aortic centreline
  double radius = 0, length = 0;
  Vec3 cap_centre() const { return base + length * direction; }
};

/// A landmark plane station along the centreline.
struct Station {
  std::string name; ///< "inlet", "AAo", "DAo_prox", "1".."5" (paired TL/FL), "DAo_dist", "outlet"
  double s = 0;     ///< arclength [m]
};

/// Lumen area of a circle of radius r cut by a chord at signed distance d from its centre:
/// the part beyond the chord.
double circular_segment_area(double r, double d);

class TbadModel {
public:
  /// Validates `spec` (InputError on bad values) and lays the model out.
  explicit TbadModel(const TbadSpec& spec);

  const TbadSpec& spec() const { return spec_; }
  double length() const { return s_outlet_; }
  Frame frame(double s) const;
  /// Lumen radius R(s) of the whole aorta (both lumina and the flap between them) [m].
  double radius(double s) const;
  /// Signed distance of the flap's mid-surface from the centreline along Frame::normal [m];
  /// positive values narrow the true lumen.
  double flap_offset(double s) const;
  /// Half the flap's thickness along Frame::normal [m]: h/2 sqrt(1 + e'^2) with e' the
  /// offset's slope, so that the flap is h thick perpendicular to itself where it slopes.
  double flap_half_thickness(double s) const;
  /// True lumen thickness at the centre of the section: from the flap's TL face to the
  /// lumen wall along Frame::normal [m] (the TL is a circular segment of this height).
  double true_lumen_thickness(double s) const;

  double arch_start() const { return s_arch0_; }
  double arch_length() const { return arch_length_; }
  double flap_start() const { return s_flap0_; }
  /// Start of the flap's distal taper (re-attachment): flap_start() + flap_length.
  double taper_start() const { return s_taper0_; }
  /// The false lumen's distal end: the proximal face of its end cap, h thick.
  double flap_end() const { return s_flap1_; }
  const std::array<BranchGeometry, 3>& branches() const { return branches_; }
  const std::array<TearGeometry, 2>& tears() const { return tears_; }
  const std::vector<Station>& stations() const { return stations_; }
  /// Arclength of station "1".."5".
  double paired_station(int k) const;
  /// Points inside the true and false lumen on the plane of paired station s.
  Vec3 true_lumen_point(double s) const;
  Vec3 false_lumen_point(double s) const;
  /// Smallest radius of curvature of the centreline over [s0, s1] [m].
  double min_curvature_radius(double s0, double s1) const;

private:
  void lay_out_stations();
  void solve_dissected_profile();
  void check_fit() const;

  TbadSpec spec_;
  // Centreline samples at a fixed arclength step: positions and tangents.
  double ds_ = 0;
  std::vector<Vec3> points_, tangents_;
  double s_arch0_ = 0, arch_length_ = 0, s_bend0_ = 0, s_bend1_ = 0, bow_angle_ = 0;
  double s_flap0_ = 0, s_taper0_ = 0, s_flap1_ = 0, s_outlet_ = 0;
  std::array<BranchGeometry, 3> branches_;
  std::array<TearGeometry, 2> tears_;
  std::vector<Station> stations_;
  // Knots (arclength, value) of the monotone cubic profiles.
  std::vector<std::array<double, 2>> radius_knots_, offset_knots_;
  std::array<double, 5> station_radius_{}, station_offset_{};
};

} // namespace tearflow::geometry
