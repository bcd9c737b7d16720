#pragma once
// Results as ParaView reads them: one VTU per saved step and a `.pvd` collection with the
// time values, rewritten atomically after every frame so that an interrupted run leaves a
// valid series. Rank 0 writes; fields come in the input mesh's node order.
#include "io/durable_file.hpp" // write_file_atomically, for the series' callers
#include <filesystem>
#include <string>
#include <vector>

#include <vtkSmartPointer.h>

#include "mesh/mesh.hpp"

class vtkUnstructuredGrid;

namespace tearflow::io {

/// Cell array of a multi-region mesh's VTU: each tet's index into the field-data string
/// array kRegionNamesArray (Mesh::regions).
inline constexpr const char* kRegionArray = "region";
inline constexpr const char* kRegionNamesArray = "region_names";

struct PointField {
  std::string name; ///< bare name (ParaView shows it); units are listed in docs/outputs.md
  int components = 1;
  std::vector<double> values; ///< node-major, components per node
};

class VtuSeries {
public:
  /// `stem` names the files: DIR/STEM_000012.vtu and DIR/STEM.pvd.
  VtuSeries(const mesh::Mesh& mesh, std::filesystem::path directory, std::string stem);
  ~VtuSeries();

  void write(int step, double time, const std::vector<PointField>& fields);
  /// Forgets frames after `time` (restart) and rewrites the .pvd.
  void truncate_after(double time);
  /// Re-reads an existing .pvd (restart) so new frames are appended to it. The frames on
  /// disk decide: a frame file the .pvd does not list (a .pvd lost to a full disk or a kill)
  /// is listed again at its step's time, step x `time_step`; a listed frame whose file is
  /// gone is dropped.
  void load_existing(double time_step);

private:
  void write_pvd() const;
  vtkSmartPointer<vtkUnstructuredGrid> grid_;
  std::filesystem::path directory_;
  std::string stem_;
  std::vector<std::pair<double, std::string>> frames_;
};

} // namespace tearflow::io
