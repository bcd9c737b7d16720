#pragma once
// What a case says about one face: a no-slip wall, an inflow, or an outlet with its law
// (outlet.hpp). The case reader parses straight into it (io/case_conditions.cpp); a run
// resolves it against the mesh (fluid_conditions.hpp).
#include <string>
#include <variant>

#include "bc/inflow_profile.hpp"
#include "bc/outlet.hpp"
#include "bc/waveform.hpp"

namespace tearflow::bc {

struct NoSlip {};

struct Inflow {
  Waveform flow = Waveform::constant(0.0); ///< volume flow into the domain [m^3/s]
  ProfileShape profile = ProfileShape::Parabolic;
  int womersley_modes = 16; ///< Fourier modes of the Womersley profile
};

struct Outlet {
  OutletLaw law;
  double backflow_beta = 0.2; ///< Esmaily-Moghadam et al. 2011
};

struct BoundaryCondition {
  std::string face;
  std::variant<NoSlip, Inflow, Outlet> kind;

  const Inflow* inflow() const { return std::get_if<Inflow>(&kind); }
  Inflow* inflow() { return std::get_if<Inflow>(&kind); }
  const Outlet* outlet() const { return std::get_if<Outlet>(&kind); }
  Outlet* outlet() { return std::get_if<Outlet>(&kind); }
};

} // namespace tearflow::bc
