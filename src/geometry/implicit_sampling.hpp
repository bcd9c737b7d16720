#pragma once
// The half of the implicit mesher (implicit_mesher.cpp) that needs no CGAL, kept apart so that
// it compiles in seconds: the labels CGAL meshes (the caps applied), the caps' rims traced on
// their planes, and surface seeds from the labels sampled on a grid.
#include <functional>
#include <string>
#include <vector>

#include "geometry/implicit_mesher.hpp"

namespace tearflow::geometry::implicit {

constexpr int kOutside = 0, kFluid = 1, kWall = 2, kFirstCap = 3;

/// 0 and the labels beyond the caps: both outside the domain.
inline bool is_outside(int label) {
  return label == kOutside || label >= kFirstCap;
}

/// The labels that CGAL meshes: the user's, 0 outside the bounding sphere, and kFirstCap + i
/// beyond cap i within its reach. Beyond a cap is outside, as 0 is, but a label of its own
/// makes the cap's facets surface patches of their own, so that each rim is a curve between
/// patches, as Mesh_3's features are. Keeps references to its arguments.
class Labels {
public:
  Labels(const ImplicitDomain& d, const std::string& src) : d_(d), src_(src) {}
  int operator()(const Vec3& x) const { return eval(x, false); }
  /// Also refuses labels other than 0, 1, 2 (InputError): on the sampling grid only, since
  /// CGAL's calls must not throw; there the others count as outside.
  int checked(const Vec3& x) const { return eval(x, true); }

private:
  int eval(const Vec3& x, bool check) const;
  const ImplicitDomain& d_;
  const std::string& src_;
};

/// A closed polyline [m]: its first point repeated at the end.
using Polyline = std::vector<Vec3>;

/// The rims on a cap's plane: the loops around the fluid (fluid|wall) and around the fluid
/// and the wall (wall|outside), traced by marching squares with spacing `h` over the cap's
/// disc, their points bisected onto the label change to `tol`. InputError when the disc's rim
/// is not outside (the cap does not cut the vessel off whole) or the disc holds no fluid;
/// `src` names the domain.
std::vector<Polyline> cap_rims(const Labels& labels, const ImplicitCap& cap, double h, double tol,
                               const std::string& src);

/// A point on the surface between labels a < b.
struct Seed {
  Vec3 point;
  int a, b;
};

struct Sampling {
  std::vector<Seed> seeds;
  double fluid_volume = 0, wall_volume = 0; ///< [m^3], counted on the grid
  double vertices = 0;                      ///< the integral of size^-3 over the domain
};

/// Samples the labels every `h` over the bounding sphere and keeps, per cube of
/// `element_size` and pair of labels, one point on the surface between them (bisected to
/// `tol`), at least half an element from the others on the same surface. `size` is the local
/// element size [m]. InputError for a label other than 0, 1, 2, or a grid too large.
Sampling sample(const Labels& labels, const ImplicitDomain& d,
                const std::function<double(const Vec3&)>& size, double element_size, double h,
                double tol, const std::string& src);

} // namespace tearflow::geometry::implicit
