#pragma once
// A vessel's flow from a 2D through-plane phase-contrast scan (docs/mri.md, "2D phase
// contrast"), the reference study's source of the inflow waveform and the outlet splits:
//   1. the scan, corrected as 4D flow is (corrected_scan.hpp): the background polynomial fitted
//      over the slice's static tissue;
//   2. the vessel: the lumen region of plane_flow.hpp on the slice's own plane (no reformat
//      through other slices: the pixels are the slice's, sampled at half a pixel), grown from a
//      seed and followed through the frames (PlaneOptions::track); the seed is given, or the
//      lumen point of the model's landmark plane that lies in the slice (within its thickness,
//      its normal within 30 degrees of the slice's), or the slice's centre;
//   3. the sign: the flow along the vessel's direction, i.e. along the landmark's normal
//      (downstream) when the seed came from a landmark, otherwise the sign that makes the
//      cycle's mean flow positive (the aorta and its branches carry net forward flow; the
//      scanner's through-plane sign is a vendor's convention);
//   4. the cycle: frames at their trigger times after the R wave, the period the R-R interval
//      (NominalInterval) or, without it, frames x their spacing (retrospective gating spreads
//      the frames over the whole interval).
#include <optional>
#include <string>
#include <vector>

#include "bc/waveform.hpp"
#include "geometry/landmarks.hpp"
#include "mri/flow_dataset.hpp"
#include "mri/plane_flow.hpp"

namespace tearflow::mri {

struct VesselSeed {
  std::optional<Vec3> point;                 ///< given [m], patient LPS
  const geometry::Landmarks* landmarks = {}; ///< else the landmark plane in the slice
};

struct VesselFlow {
  std::string name;
  std::string seed_from;                ///< "given", "landmark <name>" or "slice centre"
  Vec3 seed{};                          ///< frame 0's lumen point [m]
  int sign = 1;                         ///< applied to the flow along the slice normal
  double period = 0.0;                  ///< R-R interval [s]
  std::vector<double> time, flow, area; ///< per frame [s], [m^3/s] along the vessel, [m^2]
  double mean_flow() const;             ///< frame mean [m^3/s]
  /// The flow over one R-R interval: periodic C2 cubic spline through the frames at their
  /// trigger times (the case's own interpolation of sampled waveforms), the phase kept.
  bc::Waveform waveform() const;
};

/// Measures a corrected 2D phase-contrast scan (InputError when it is not one, naming `name`).
VesselFlow measure_vessel(const Flow4D& scan, const std::string& name, const VesselSeed& seed,
                          PlaneOptions options = {});

} // namespace tearflow::mri
