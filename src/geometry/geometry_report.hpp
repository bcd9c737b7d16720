#pragma once
// `tearflow geometry report DIR`: what a geometry directory holds, measured on its mesh:
// element counts and quality, face areas, tear areas, the lumen area at every landmark, and
// a picture of the model.
#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include "geometry/fsi_mesh.hpp"
#include "geometry/landmarks.hpp"
#include "mesh/mesh.hpp"

namespace tearflow::geometry {

struct MeasuredTear {
  std::string name;
  double requested = 0, measured = 0; ///< [m^2]
};

/// Lengths of the distinct edges of one region's tets [m]: how a mesher's "element size"
/// came out (Gmsh's target size is close to the mean; other meshers' sizes are maxima).
struct EdgeLengths {
  std::string region;
  std::size_t edges = 0;
  double mean = 0, median = 0, p95 = 0, max = 0;
};

/// Edge lengths per region of `mesh`.
std::vector<EdgeLengths> edge_lengths(const mesh::Mesh& mesh);

struct GeometryReport {
  MeshReport quality;
  std::vector<EdgeLengths> edges;
  std::size_t nodes = 0;
  std::vector<std::pair<std::string, double>> face_areas; ///< [m^2]
  std::vector<MeasuredTear> tears;
  std::vector<std::pair<std::string, double>> landmark_areas; ///< [m^2]
};

/// Measures `mesh` at `landmarks`.
GeometryReport measure_geometry(const mesh::Mesh& mesh, const Landmarks& landmarks);

/// The report as text (mm, mm^2) and as JSON (SI).
std::string format_report(const GeometryReport& report);
std::string report_json(const GeometryReport& report);

/// Reads DIR/mesh.msh and DIR/landmarks.json, measures them, prints the report, writes
/// DIR/report.json and (unless `png` is empty) the picture to `png`. Returns the report.
GeometryReport report_geometry(const std::filesystem::path& dir, const std::filesystem::path& png,
                               bool print = true);

/// Renders the model (wall translucent, fluid faces, tears and landmark planes) off-screen
/// into a PNG. Without an X display (DISPLAY) it starts a virtual one (core/virtual_display.hpp);
/// InputError when it cannot.
void render_geometry(const mesh::Mesh& mesh, const Landmarks& landmarks,
                     const std::filesystem::path& png);

} // namespace tearflow::geometry
