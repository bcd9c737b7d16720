#pragma once
// Element size that resolves the dissected lumina across their thickness. The default TBAD's
// true lumen narrows to a circular segment about 4 mm high (TL3..TL5); at a uniform 3 mm it
// was one element thick, every node lay on the no-slip interface, the P1 velocity there was
// zero and no flow passed (docs/geometry.md, "Resolving the true lumen"). Within the flap's
// segment the size is the local TL thickness over `TbadSpec::lumen_elements` in the true
// lumen, in the tears and in a band beside the flap in the false lumen, and grows linearly
// away from there to the global element size. Pure geometry: the builder passes it to Gmsh
// as a size callback (Gmsh takes the smaller of it and its own fields), tests can query it.
#include <vector>

#include "core/types.hpp"
#include "geometry/tbad_model.hpp"

namespace tearflow::geometry {

class LumenSizing {
public:
  /// Growth of the size per unit distance away from the refined zone: from 1.3 mm to 3 mm
  /// over about 4 mm, gentle enough for Delaunay to keep well-shaped tets in between.
  static constexpr double kGrading = 0.4;

  explicit LumenSizing(const TbadModel& model);

  /// Target element size at point p [m] (the global element size where nothing is refined).
  double size(const Vec3& p) const;
  bool enabled() const { return !samples_.empty(); }

private:
  struct Sample {
    double s = 0;
    Frame frame;
    double radius = 0, offset = 0, fine = 0;
  };
  std::vector<Sample> samples_; // along the dissected segment and its grading reach
  double global_ = 0, h_ = 0, s0_ = 0, s1_ = 0;
  int elements_ = 0;
};

} // namespace tearflow::geometry
