#pragma once
// What the reduced-order model knows of a dissected aorta's shape, measured once from a model
// directory (mesh.msh with a fluid region and named faces, landmarks.json): nodes at the
// landmarks, at the arch's branches and at the tears; segments between them with their
// length and the integrals of their sampled section areas A(s); the tears' areas; the wall's
// thickness. Saved as rom/geometry.json in the model directory with the mesh's digest.
//
// How it is measured:
//   - the aorta's path: inlet -> AAo -> the arch -> DAo_prox. The arch's centreline is tracked
//     from AAo: steps of a fifth of the radius, each section normal to the path, its centroid
//     (of the part within 1.3 radii, so that ostia and the arch's other limb do not pull it)
//     the next point; the sections' areas (ostia left out) give the arch's integrals;
//   - a branch (a planar fluid face other than inlet and outlet) leaves from the arch point
//     nearest its centroid; its segment (the cap's area) runs from there to its cap;
//   - the true lumen: DAo_prox -> TL1 .. TL5 -> DAo_dist -> outlet through the stations'
//     lumen points; the false lumen: FL1 .. FL5;
//   - a tear lies between the two stations whose planes it falls between (signed distances);
//     its TL and FL nodes are put there (on a station when within 2 mm of it), the FL chain
//     extended beyond FL1 or FL5 when the tear lies outside them;
//   - segment integrals int ds / A^2 (viscous resistance), int ds / A (inertance) and int A ds
//     (volume) by the trapezoidal rule over the ends and three interior sections (a section
//     that merges the lumen with the other one is left out).
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/types.hpp"
#include "geometry/landmarks.hpp"
#include "mesh/mesh.hpp"

namespace tearflow::rom {

struct GeometryNode {
  std::string name;        ///< a landmark's, arch_<face>, TL_<tear>, FL_<tear>, or a cap's
  std::string lumen;       ///< aorta, TL, FL or branch
  Vec3 position{};         ///< [m]
  double area = 0.0;       ///< unloaded lumen area there [m^2]
  std::string partner;     ///< a TL node's FL node at the same station, and back
  double total_area = 0.0; ///< TL + FL at a paired station, else `area` [m^2]
};

struct GeometrySegment {
  std::string from, to, lumen;
  double length = 0.0;               ///< [m]
  double inverse_area_squared = 0.0; ///< int ds / A^2 [1/m^3]
  double inverse_area = 0.0;         ///< int ds / A [1/m]
  double friction_integral = 0.0;    ///< int ds / (D A^2), D = 2 sqrt(A / pi) [1/m^4]
  double volume = 0.0;               ///< int A ds [m^3]
  int samples = 0;                   ///< sections used, the ends included
};

struct GeometryTear {
  std::string name, tl_node, fl_node;
  double area = 0.0; ///< [m^2], as the landmarks give it
  /// The true lumen's area beside the tear, where the through-flow passes it (the mean of its
  /// sections at the tear's rims) [m^2]. At an entry fed by the undivided aorta this is the
  /// junction's flow area, not its TL node's (a landmark plane that also cuts the false
  /// lumen's blind end above the tear).
  double channel_area = 0.0;
};

struct DissectionGeometry {
  std::vector<GeometryNode> nodes;
  std::vector<GeometrySegment> segments;
  std::vector<GeometryTear> tears;
  double wall_thickness = 0.0; ///< 2 V_wall / (A_outer + A_interface) [m]; 0 without a wall
  std::string mesh_digest;     ///< of mesh.msh and landmarks.json, to know when to re-measure

  int node(const std::string& name) const; ///< -1 if none
};

/// Measures the geometry (file comment). InputError naming the landmark or face when a
/// required landmark is missing, a plane misses the fluid, or a tear lies outside the
/// dissected length.
DissectionGeometry measure_dissection(const mesh::Mesh& mesh, const geometry::Landmarks& landmarks);

nlohmann::json to_json(const DissectionGeometry& g);
/// InputError naming `source` and the key for anything missing or malformed.
DissectionGeometry geometry_from_json(const nlohmann::json& j, const std::string& source);

/// The digest of a model directory's mesh.msh and landmarks.json (hex).
std::string model_digest(const std::filesystem::path& model_dir);

/// The model directory's geometry: rom/geometry.json when its digest matches, else measured
/// from the mesh and saved there. `progress` prints what it does.
DissectionGeometry model_geometry(const std::filesystem::path& model_dir, bool progress);

} // namespace tearflow::rom
