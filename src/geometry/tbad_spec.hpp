#pragma once
// Parameters of the built-in type B aortic dissection (TBAD): a thoracic aorta (ascending
// aorta, arch with BCT, LCC and LSA, descending aorta) whose descending part is split by a
// dissection flap into a true lumen (TL) and a false lumen (FL) that communicate through an
// entry and an exit tear. Defaults reproduce the reference study's patient (Zimmermann,
// Baeumler et al. 2023, ../shared/reference/tbad-study.md): lumen areas at its landmarks,
// tear areas 228 / 227 mm^2, wall and flap 2 mm. Distal to the exit tear the flap re-attaches
// to the wall over a taper, and the domain ends past the false lumen's end.
// Everything is in SI units (m, m^2); the command line converts from mm.
#include <array>
#include <string>
#include <string_view>

namespace tearflow::geometry {

/// An arch branch: a straight tube leaving the arch at a fraction of the arch's length.
struct BranchSpec {
  std::string name;
  double radius = 0;        ///< lumen radius [m]
  double length = 0;        ///< from the aortic centreline to the outlet cap [m]
  double arch_position = 0; ///< where it leaves the arch, as a fraction of the arch length (0..1)
};

/// A tear: an elliptical hole through the flap, elongated along the vessel as real tears are.
struct TearSpec {
  double area = 0; ///< hole area in the flap's mid-surface [m^2]
  /// Centre's distance along the centreline from its end of the flap [m]: the entry tear's
  /// from the flap's proximal end, the exit tear's from the start of the flap's distal taper.
  /// 0 (the exit tear's default): at the taper's start, the tear's axial semi-axis plus
  /// max(2 mm, wall thickness) of flap (`resolved_exit_tear_position`).
  double position = 0;
  double aspect = 1.8; ///< axial over circumferential semi-axis, >= 1
};

struct TbadSpec {
  // Centreline. It runs up the inlet extension and the ascending aorta, turns through the
  // arch (the turn rate follows a smooth step, so curvature is continuous), descends with a
  // gentle bend, and ends straight. The ascending aorta bows out of the arch's plane, which
  // makes the centreline 3D; arch and descending aorta stay in one plane, so the flap, whose
  // normal is that plane's normal, is flat where the tears are.
  double inlet_extension = 20e-3;  ///< straight flow extension before the ascending aorta [m]
  double ascending_length = 50e-3; ///< [m]
  double ascending_bow = 8e-3;     ///< out-of-plane bow of the ascending aorta [m]
  double arch_radius = 25e-3;      ///< smallest centreline radius of curvature in the arch [m]
  double descending_bend = 0.12;   ///< in-plane bend of the descending aorta [rad]

  // Lumen size outside the dissection.
  double aao_area = 492.6e-6;          ///< ascending aorta lumen area [m^2]
  double arch_distal_radius = 11.0e-3; ///< lumen radius at the LSA [m]
  double dao_dist_area = 365.5e-6;     ///< lumen area distal to the dissection [m^2]

  // Dissection: the flap starts `flap_start_gap` distal to the LSA's outer wall and runs
  // `flap_length` to the start of its distal taper, where it re-attaches to the outer wall
  // (from TL5 to the exit tear it moves to the vessel's centre, so that the TL beside the
  // tear is as wide as the FL): over `taper_length` it moves on to the FL's side, narrowing it to
  // `fl_end_depth` at its end cap and the TL widening to about DAo_dist's area. The false
  // lumen is closed (a blind sac) at both ends: the lumina communicate only through the tears.
  double flap_start_gap = 6e-3; ///< [m]
  double flap_length = 200e-3;  ///< flap's start to its distal taper's start [m]
  double taper_length = 25e-3;  ///< the distal taper (re-attachment), to the FL's end cap [m]
  double fl_end_depth = 4e-3;   ///< FL depth (flap to wall) at its end cap [m]
  double wall_thickness = 2e-3; ///< h: outer wall and flap [m]
  /// TL and FL areas at the five stations TL1..TL5 / FL1..FL5, proximal to distal [m^2].
  std::array<double, 5> tl_areas{235.6e-6, 149.2e-6, 67.6e-6, 58.4e-6, 56.6e-6};
  std::array<double, 5> fl_areas{476.3e-6, 436.3e-6, 475.0e-6, 458.7e-6, 429.3e-6};
  /// Distance of station 1 (5) distal (proximal) to the entry (exit) tear's centre [m]; the
  /// other stations are evenly spaced in between. Fixed, not derived from the tear sizes, so
  /// that the variants share their landmarks relative to the tears (EX's smaller exit tear
  /// sits nearer the flap's taper by default, and its stations with it).
  double station_offset = 24e-3;
  TearSpec entry_tear{228e-6, 15e-3, 1.8}; ///< position from the flap's proximal end
  /// Position from the start of the flap's distal taper; 0: just proximal to it (the
  /// re-entry tear through which the false lumen empties into the widening true lumen),
  /// 13.4 mm for 227 mm^2.
  TearSpec exit_tear{227e-6, 0, 1.8};
  /// Outlet cap distal to the false lumen's end (the taper's end) [m]. From there, not from
  /// the exit tear, so that all variants share the undivided distal aorta.
  double outlet_distance = 21.6e-3;

  std::array<BranchSpec, 3> branches{BranchSpec{"BCT", 6.0e-3, 45e-3, 0.36},
                                     BranchSpec{"LCC", 3.5e-3, 45e-3, 0.5},
                                     BranchSpec{"LSA", 4.5e-3, 45e-3, 0.64}};

  // Meshing.
  double element_size = 3e-3;   ///< target tetrahedron edge length [m]
  double tear_element_size = 0; ///< near the tears [m]; 0: from the tear size (see builder)
  /// Elements across the true lumen's thickness: in the dissected segment the size in the
  /// TL, through the flap's tears and beside the flap in the FL is at most the local TL
  /// thickness over this (lumen_sizing.hpp). 0 turns it off (uniform `element_size`).
  int lumen_elements = 3;
};

/// Sets the reference study's tear areas: OR (228 / 227 mm^2), EN (entry 62 mm^2) or EX
/// (exit 61 mm^2). Throws InputError naming the variants for anything else.
void apply_variant(TbadSpec& spec, std::string_view variant);

/// The exit tear centre's distance from the start of the flap's distal taper [m]:
/// `exit_tear.position`, or when that is 0 the tear's axial semi-axis plus max(2 mm, wall
/// thickness), which puts the tear just proximal to the taper with one ligament of flat flap
/// distal to it.
double resolved_exit_tear_position(const TbadSpec& spec);

/// Checks every value (positive, finite, in range). Throws InputError saying which value is
/// wrong and its value in mm. TbadModel calls it, then checks that the tears fit the flap.
void validate(const TbadSpec& spec);

} // namespace tearflow::geometry
