#pragma once
// A dissection read from a label map (docs/geometry.md, "From a label map"): the true and
// false lumen as signed distance fields, the flap rebuilt between them with the wall's
// thickness, its holes (the tears: where the two lumina touch), and the wall around the
// lumen. Everything is a function of the point, so the mesher can ask at any resolution.
//
// With u_T, u_F the signed distances to the true and the false lumen (thrombus counted with
// the false lumen), w = (u_T - u_F) / 2 the distance from the flap's mid-surface and h the
// wall's thickness:
//   aorta (lumina and flap)   E = min(u_T, u_F, max((u_T + u_F - g) / 2, min(u_T, u_F) - 3h/4))
//                             < 0, g the widest gap between the lumina read as flap (filled
//                             only within 3h/4 of a lumen, so that the wall encloses it);
//   flap                      |w| < h/2 inside E, except in a tear;
//   tear k                    sigma(x - w n) + delta_k > 0: sigma the signed distance, in the
//                             flap's mid-surface, from the rim of the labels' contact (> 0
//                             where the lumina touch), delta_k the tear's growth;
//   wall                      the flap, thrombus, and min(u_T, u_F) < h outside E;
//   fluid                     E minus flap and thrombus; the tears' rims rounded over h/4.
#include <string>
#include <vector>

#include "core/image_grid.hpp"
#include "geometry/label_map.hpp"

namespace tearflow::geometry {

/// Which label is what. `thrombus` < 0: none.
struct LabelRoles {
  int true_lumen = 1, false_lumen = 2, thrombus = -1;
};

/// A scalar on a grid's voxel centres, trilinear between them; `outside` beyond the grid.
struct GridField {
  const ImageGrid* grid = nullptr;
  std::vector<float> values;
  float outside = 1.0f;
  double at(const Vec3& x) const;
};

/// A tear as found: its rim's contact region in the flap's mid-surface.
struct LabelTear {
  std::string name;
  Vec3 centroid{}, normal{}, axis{}; ///< normal: the flap's, into the true lumen; axis: long
  double area = 0;                   ///< in the mid-surface [m^2]
  double axial = 0, across = 0;      ///< semi-axes of the ellipse of the same moments [m]
  double found_area = 0;             ///< as in the label map, before any resizing [m^2]
  double growth = 0;                 ///< delta [m]: the rim moved outwards (< 0: inwards)
  double reach = 0;                  ///< radius around the centroid where the tear is [m]
  double inscribed = 0;              ///< largest distance inside it from its rim [m]
};

struct DissectionOptions {
  LabelRoles roles;
  double wall_thickness = 2e-3; ///< h [m]: outer wall and flap
  /// Gaussian sigma of the distance fields beyond 6 mm of the lumina (label_map.hpp) [voxels]
  double smoothing = 0.5;
  /// Contacts smaller than this are not tears [m^2]: a voxel or two where the segmentation's
  /// flap is thin (at 1 mm, 3 mm^2 spots were found on the voxelized built-in model).
  double min_tear_area = 10e-6;
};

class LabelledDissection {
public:
  /// Builds the fields. InputError naming the file: a role's label absent from the map, no
  /// flap (the lumina never come within 3 h of each other), no tear, voxels too coarse for the
  /// flap (spacing above h).
  LabelledDissection(const LabelMap& map, const DissectionOptions& options);

  enum Label : int { outside = 0, fluid = 1, wall = 2 };
  /// What a point [m] is.
  int label(const Vec3& x) const;
  /// < 0 inside the aorta's lumen (both lumina, the flap and thrombus), ~ a distance [m].
  double aorta(const Vec3& x) const;
  double true_lumen(const Vec3& x) const { return tl_.at(x); }
  double false_lumen(const Vec3& x) const { return fl_.at(x); }

  /// The voxel grid of the fields (the label map's, cropped to the aorta and padded).
  const ImageGrid& grid() const { return grid_; }
  /// Per voxel: inside the aorta's lumen (aorta() < 0).
  std::vector<std::uint8_t> aorta_mask() const;
  /// The map's voxels labelled false lumen (without thrombus), on grid().
  const std::vector<std::uint8_t>& false_lumen_mask() const { return fl_mask_; }
  double wall_thickness() const { return h_; }
  /// The widest gap between the lumina read as flap [m].
  double flap_gap() const { return gap_; }

  /// Prepares lumen_half_thickness() for points within `radius` of the lumen's middle.
  void prepare_sizing(double radius);
  /// Half the thickness of the lumen at x (the true or the false lumen's, whichever x lies
  /// in; in the wall the thinner neighbour's): the largest depth in the lumen within the
  /// radius given to prepare_sizing [m]. For the mesher's size.
  double lumen_half_thickness(const Vec3& x) const;

  /// Tears, largest first until named (label_model names them by position).
  std::vector<LabelTear>& tears() { return tears_; }
  const std::vector<LabelTear>& tears() const { return tears_; }
  /// The area of tear k grown by `growth` [m^2], measured in the flap's mid-surface.
  double tear_area(std::size_t k, double growth) const;
  /// Grows or shrinks tear k to `area` [m^2] (its rim moved by a uniform distance).
  /// InputError when the area cannot be reached inside the flap.
  void resize_tear(std::size_t k, double area);

private:
  void find_tears();
  void measure_tear(LabelTear& t) const;
  int tear_at(const Vec3& x) const;
  double aorta_of(double ut, double uf) const;

  std::filesystem::path file_;
  ImageGrid grid_;
  double h_ = 0, round_ = 0, gap_ = 0, spacing_ = 0;
  GridField tl_, fl_, thrombus_, mid_sigma_, w_, tl_depth_, fl_depth_;
  std::vector<std::uint8_t> fl_mask_;
  std::vector<LabelTear> tears_;
  double min_tear_area_ = 0;
};

} // namespace tearflow::geometry
