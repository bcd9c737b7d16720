#pragma once
// `tearflow geometry labels`: a patient's dissection from a segmented scan (docs/geometry.md,
// "From a label map"). The label map's lumina become distance fields (labelled_dissection),
// the flap is rebuilt between them with the wall's thickness, the tears are found where they
// touch (and resized on request), the vessel's ends are capped perpendicular to its
// centreline and named, the study's landmark planes are placed along the centreline, and the
// fluid and the wall are meshed together (implicit_mesher): the layout `geometry tbad` writes.
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "geometry/labelled_dissection.hpp"
#include "geometry/landmarks.hpp"
#include "mesh/mesh.hpp"

namespace tearflow::geometry {

struct LabelModelOptions {
  DissectionOptions dissection;
  double element_size = 3e-3; ///< [m]
  /// Tear areas asked for, by name ("entry", "exit", "tear_3", ...) [m^2].
  std::vector<std::pair<std::string, double>> tear_areas;
  /// Cap renames (old, new): the caps are named inlet, outlet and, for three branches, BCT,
  /// LCC, LSA (else branch_1, branch_2, ... from the inlet on).
  std::vector<std::pair<std::string, std::string>> rename_faces;
  double station_offset = 24e-3;   ///< TL1/FL1 (TL5/FL5) distal (proximal) to the entry (exit) tear
  double min_branch = 10e-3;       ///< a vessel end counts if it leaves the tree by this much
  std::filesystem::path landmarks; ///< planes (and tears) from this file instead (optional)
  bool verbose = false;
};

/// One capped vessel end.
struct LabelCap {
  std::string name;
  Vec3 centre{}, normal{}; ///< normal out of the domain
  double area = 0;         ///< lumen section on the cap plane [m^2]
  double reach = 0;        ///< radius of the cut [m]
};

struct LabelModel {
  mesh::Mesh mesh;
  Landmarks landmarks;
  std::vector<LabelCap> caps;
  std::vector<LabelTear> tears;
  std::vector<Vec3> centreline; ///< inlet to outlet [m]
  double flap_gap = 0;          ///< the widest gap between the lumina read as flap [m]
  double seconds_fields = 0, seconds_landmarks = 0, seconds_mesh = 0;
};

/// Builds the model from a label map. InputError naming the file and what to do.
LabelModel build_label_model(const LabelMap& map, const LabelModelOptions& options);

/// Reads `scan`, builds the model, checks it and writes DIR/mesh.msh, DIR/landmarks.json and
/// DIR/labels.json (what was found: caps, tears, gap, centreline).
LabelModel geometry_from_labels(const std::filesystem::path& scan, const LabelModelOptions& options,
                                const std::filesystem::path& dir);

} // namespace tearflow::geometry
