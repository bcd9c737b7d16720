#pragma once
// The reduced-order model of a dissected aorta: the measured geometry
// (rom/dissection_geometry.hpp) and a case (fluid, inflow, outlets, wall) as a lumped network
// (rom/lumped_network.hpp), and its periodic state as the same Analysis that `analyze` gives
// for a 3D run (metrics.json, a CSV per landmark).
//
// Every segment (length l, section A(s)) is an edge with
//   R = alpha 8 pi mu int ds / A^2           (Poiseuille; alpha >= 1 calibrated),
//   L = rho int ds / A,                       (the blood's inertia)
// and the Bernoulli and expansion terms between its end nodes' areas; a segment of the lumina
// (TL, FL) adds Darcy's loss f rho/2 int ds / (D A^2) q|q| (D = 2 sqrt(A / pi); f calibrated,
// 0 uncalibrated: the developing, pulsatile flow's losses above Poiseuille's). The arch (AAo to
// DAo_prox) adds a loss K_arch rho / (2 A_AAo^2) q|q|, shared over its segments. A tear of
// area A_t in a flap of thickness h, beside the TL's channel of area A_j, is an orifice:
//   R = 8 pi mu h / A_t^2,  L = rho (h + 1.7 sqrt(A_t / pi)) / A_t  (the end corrections of a
//   flanged hole, 0.85 r per side),
//   loss K_t (A_t / A_t0)^gamma rho/2 (1 / A_t^2 + 1 / A_j^2) q|q|,
// with A_t0 the model's own area of that tear (K_t calibrated; gamma only from runs of two
// sizes of a tear, else 0). The flow through a tear passes the channel beside it as well: a
// tear as large as the channel cannot take its flow faster than the channel brings it, so
// the tear and the channel are two openings in series, each losing K_t heads of its own
// velocity (the channel's term is 0.05 of the tear's at 62 mm^2, 0.66 at 228 mm^2). Fitted to
// each TL-resolved 3D run alone (3 mm, six elements across the TL), the entry's K_t at
// 228 mm^2 is 2.62 (OR) and 2.61 (EX), at 62 mm^2 1.88: with the tear's term alone it was
// 4.36 / 4.33 against 1.97, a size dependence one tear size cannot calibrate.
// A tear the undivided aorta feeds (the entry: its TL node ends an aorta segment) makes that
// node a dividing junction, where static pressure is not shared as at other nodes:
//   - the approaching flow q_a arrives in the true lumen's channel beside the tear, of area A_j
//     (GeometryTear::channel_area, the TL at the tear's rims), not in the node's landmark
//     section (DAo_prox also cuts the false lumen's blind end above the tear): the approach
//     segment's Bernoulli term runs to A_j, and the node's pressure is the static pressure
//     beside the tear, lowered by the approaching flow's head rho/2 (q_a / A_j)^2;
//   - the true lumen onward regains that head as its flow slows (total pressure carried
//     through the junction, as 1D network models join vessels): its segment runs from the
//     approach velocity to its own, -rho/2 (q_a^2 - q^2) / A_j^2 beyond its own Bernoulli
//     term (NetworkEdge::regain). The 3D runs show it: at peak systole the TL's static
//     pressure beside the entry is 4.1-4.2 mmHg below TL1's at 2 and 3 mm (2.2 at 4.5 mm);
//   - the entry's landmark (DAo_prox) cuts the channel (A_j) and the false lumen's blind end
//     above the tear (the rest of its section, at the FL's pressure beside the tear): its
//     section pressure, as `analyze` measures it in a 3D run, is their area-weighted mean
//     (network_analysis). In EN (a 62 mm^2 entry) the two differ by ~30 mmHg at peak systole;
//   - the tear's loss does not depend on how the flow divides: fitted to each TL-resolved run
//     alone, the entry's K_t is the same in OR and EX (2.62 / 2.61) although EX sends 1.5
//     times the TL flow past it. (A loss K_x rho/2 v_t |v_a| with the approach velocity, as
//     the network had before, made them 2.11 / 1.60.)
// A tear whose TL node leads on into the undivided aorta (the exit) makes that node a
// combining junction: its pressure is the static pressure in the TL's channel beside the
// tear (A_j), where only the TL's own flow q_r passes, and the combined flow onward starts
// from that flow's head, rho/2 (q_r / A_j)^2, not from its own in the channel (the onward
// segment's regain from the TL's edge, NetworkEdge::regain). The FL's flow through the tear
// joins with its own head lost in the tear. Without it the exit's K_t fitted to OR (227
// mm^2) was 3.1, to EX (61 mm^2) 2.1: the network took the combined flow's head from the
// channel's static pressure, and the fit charged a large exit for it.
// A compliant wall (a case with a solid) gives every node the compliance of its share of the
// wall: over the node's length l_i (half its segments'), with r the equivalent radius of the
// whole aortic section there (TL + FL at a station) and E' = E / (1 - nu^2) (hoop, plane
// strain) and the tissue support k_s,
//   dA/dp = 2 pi r / (E' h / r^2 + k_s),  C_i = l_i dA/dp A_i / A_section,
// and the flap between a TL and its FL node a membrane: a plate strip of width b clamped at
// both edges, b the chord that divides a circle of radius r as the TL and FL divide the
// section (the built model's flap is straight across it; flap_width), whose swept area per
// pressure difference is b^5 / (720 D), D = E h^3 / (12 (1 - nu^2)):
//   C_TL,FL = beta l_i b^5 / (720 D)  (beta calibrated). Rigid walls (a case
// without a solid): no node compliance, no flap; only the outlets' capacitors.
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "analysis/hemodynamics.hpp"
#include "io/case.hpp"
#include "rom/dissection_geometry.hpp"
#include "rom/lumped_network.hpp"

namespace tearflow::rom {

/// The fitted parameters (rom calibrate); the defaults are the uncalibrated model's.
struct RomCoefficients {
  double viscous = 1.0;   ///< alpha
  double friction = 0.0;  ///< f, Darcy's friction factor of the lumina's convective loss
  double arch_loss = 0.0; ///< K_arch
  double flap = 1.0;      ///< beta
  double tear_loss = 2.6; ///< K_t of a tear not listed below: 1 / C_c^2, C_c = 0.62
  std::map<std::string, double> tear; ///< K_t by tear name
  /// gamma by tear name: K_t scales as (A_t / A_t,model)^gamma when the tear is resized. Only
  /// a tear the runs held at two sizes can tell its own; any other is the classical orifice,
  /// gamma 0 (K independent of size).
  std::map<std::string, double> tear_size;
  double size_exponent(const std::string& name) const;
  double tear_coefficient(const std::string& name) const;
};

/// The width of a straight flap across a circular section of radius r that leaves the
/// fraction f of its area on one side: the chord 2 r sin(theta/2) of the circular segment
/// whose area fraction is (theta - sin theta) / (2 pi), theta its central angle. A diameter
/// (2 r) at f = 1/2; 0.76 of it at the built model's station 4 (TL 12 % of the section).
double flap_width(double r, double f);

/// The case's wall as the network sees it.
struct WallProperties {
  double youngs_modulus = 0.0, poisson_ratio = 0.0, thickness = 0.0; ///< [Pa], [-], [m]
  double support_stiffness = 0.0; ///< k_s of the outer wall's Robin support [Pa/m]
};

struct RomInputs {
  double density = 0.0, viscosity = 0.0;
  bc::Waveform inflow = bc::Waveform::constant(0.0);
  std::vector<std::pair<std::string, bc::WindkesselRCR>> outlets; ///< by face
  std::optional<WallProperties> wall;                             ///< none: rigid
};

/// What the case gives the model. The wall's thickness is the geometry's unless
/// `wall_thickness` > 0. InputError naming the case file when it has no periodic inflow, an
/// outlet the model cannot hold (a pressure outlet), or a compliant wall of unknown thickness.
RomInputs rom_inputs(const io::Case& c, const DissectionGeometry& g, double wall_thickness = 0.0);

/// The network. `tear_areas` replaces the geometry's tear areas by name [m^2].
LumpedNetwork build_network(const DissectionGeometry& g, const RomInputs& in,
                            const RomCoefficients& k,
                            const std::map<std::string, double>& tear_areas = {});

/// The periodic state of the network as an analysis: every landmark of `landmarks` that is a
/// node (section values: Q, A(t), P; flap and velocity unknown: NaN), peak systole and end
/// diastole marked, the achieved inlet pressures and splits in `cycle`.
analysis::Analysis network_analysis(const LumpedNetwork& net, const NetworkSolution& s,
                                    const DissectionGeometry& g, const RomInputs& in,
                                    const RomCoefficients& k, const geometry::Landmarks& landmarks);

/// Builds, integrates to the periodic state (the outlets' 0D periodic state as the start) and
/// measures: the model's answer for one variant.
struct Prediction {
  analysis::Analysis analysis;
  NetworkSolution solution;
};
Prediction predict(const DissectionGeometry& g, const RomInputs& in, const RomCoefficients& k,
                   const geometry::Landmarks& landmarks,
                   const std::map<std::string, double>& tear_areas = {},
                   const IntegrationOptions& options = {});

nlohmann::json to_json(const RomCoefficients& k);
/// InputError naming `source` and the key for anything missing, negative or not a number.
RomCoefficients coefficients_from_json(const nlohmann::json& j, const std::string& source);

} // namespace tearflow::rom
