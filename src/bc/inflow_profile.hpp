#pragma once
// Inlet velocity on a planar face of any orientation and outline: u(x, t) = -U(t) s(x) n,
// n the face's outward normal. The shape s comes from the distance d(x) to the face's rim,
//   s = 1 - (1 - d/R)^2  (parabolic; exact Poiseuille for a circle of radius R)
//   s = 1                (plug; the rim is held by the wall's no-slip)
// with R = max(inscribed radius, sqrt(area/pi)), and U(t) = Q(t) / int_face s dA computed
// with the P1 interpolant of s, so the discrete flux into the domain is exactly Q(t).
// The Womersley option uses the analytic pulsatile profile of a circular pipe instead.
#include <memory>
#include <vector>

#include "bc/face_geometry.hpp"
#include "bc/waveform.hpp"

namespace tearflow::bc {

struct WomersleyFlow;

enum class ProfileShape { Parabolic, Plug, Womersley };

class InflowProfile {
public:
  /// `density`, `viscosity` and `modes` are used by the Womersley shape only.
  InflowProfile(const mesh::Mesh& mesh, const mesh::Face& face, Waveform flow, ProfileShape shape,
                double density, double viscosity, int modes);
  ~InflowProfile();
  InflowProfile(InflowProfile&&) noexcept;
  InflowProfile& operator=(InflowProfile&&) noexcept;

  const std::vector<Index>& nodes() const { return geometry_.nodes; } ///< mesh node numbers
  /// Velocity at nodes()[k] at time t [m/s].
  Vec3 velocity(size_t k, double t) const;
  const Waveform& flow() const { return flow_; }
  const FaceGeometry& geometry() const { return geometry_; }

private:
  FaceGeometry geometry_;
  Waveform flow_;
  ProfileShape shape_;
  std::vector<double> shape_value_; ///< s at each node
  double shape_integral_ = 0.0;     ///< int_face s dA [m^2]
  double radius_ = 0.0;             ///< R [m]
  std::unique_ptr<WomersleyFlow> womersley_;
};

} // namespace tearflow::bc
