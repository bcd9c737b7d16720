#pragma once
// Landmarks: the analysis planes (inlet, AAo, DAo_prox, TL1..TL5, FL1..FL5, DAo_dist,
// outlet) and the tears, as every analysis uses them. Stored as JSON beside the mesh
// (format in docs/geometry.md); held in SI units.
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "core/types.hpp"

namespace tearflow::geometry {

class TbadModel;

/// A plane through the fluid. `lumen` is "aorta" where the plane crosses one lumen, "TL" or
/// "FL" for the paired stations; those carry a `point` inside their lumen on the plane, to
/// pick the plane's section of that lumen.
struct Landmark {
  std::string name;
  Vec3 origin{}, normal{}; ///< normal points downstream
  std::string lumen = "aorta";
  std::optional<Vec3> point;
};

/// A tear: a hole in the flap. The tear region for connectivity checks is the elliptic
/// cylinder with these semi-axes around `centroid`, `axis` along the long one.
struct TearLandmark {
  std::string name; ///< "entry", "exit"
  Vec3 centroid{}, normal{}, axis{};
  double area = 0;              ///< [m^2]
  double axial = 0, across = 0; ///< semi-axes [m]
};

struct Landmarks {
  std::vector<Landmark> planes;
  std::vector<TearLandmark> tears;
  /// The plane called `name`; InputError listing the names otherwise.
  const Landmark& plane(const std::string& name) const;
  const TearLandmark& tear(const std::string& name) const;
};

/// The twelve landmarks the reference study reports areas at, in its order.
const std::vector<std::string>& area_landmark_names();

/// The landmarks of the parametric model.
Landmarks tbad_landmarks(const TbadModel& model);

/// Writes `landmarks` as JSON with lengths in `length_unit` ("m", "cm" or "mm").
void write_landmarks(const Landmarks& landmarks, const std::filesystem::path& file,
                     const std::string& length_unit = "mm");

/// Reads a landmarks JSON file; InputError naming the file and the key for anything missing
/// or malformed (unknown unit, normal of zero length, TL/FL without a point, ...).
Landmarks read_landmarks(const std::filesystem::path& file);

} // namespace tearflow::geometry
