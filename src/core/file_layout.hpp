#pragma once
// The files of a run directory and of a geometry folder, named in one place (docs/outputs.md,
// docs/geometry.md): what `run` writes and `analyze`, `tune`, `report`, `study` and `mri`
// read, so that a renamed file is one edit.
#include <filesystem>

namespace tearflow {

/// A geometry folder (`tearflow geometry`): the mesh with named faces and the landmarks.
struct GeometryFiles {
  static constexpr const char* kMesh = "mesh.msh";
  static constexpr const char* kLandmarks = "landmarks.json";
  std::filesystem::path dir;
  std::filesystem::path mesh() const { return dir / kMesh; }
  std::filesystem::path landmarks() const { return dir / kLandmarks; }
};

/// A run directory (`tearflow run`, `output.directory`) and what is made from it.
struct RunFiles {
  static constexpr const char* kMetrics = "metrics.json"; ///< in the analysis folder
  /// The lock a running `tearflow run` holds on its folder, naming it (io/output_lock.hpp).
  static constexpr const char* kLock = ".run.lock";
  std::filesystem::path dir;
  std::filesystem::path flow_pvd() const { return dir / "flow.pvd"; }
  std::filesystem::path checkpoint() const { return dir / "checkpoint.bin"; }
  std::filesystem::path faces_csv() const { return dir / "faces.csv"; }
  /// A wall-alone run's per-face record (its columns are the wall's, not the flow's).
  std::filesystem::path wall_faces_csv() const { return dir / "wall_faces.csv"; }
  std::filesystem::path cycles_json() const { return dir / "cycles.json"; }
  /// A run tuned at its cycle ends (`run --targets`): the tuning's record and restart state,
  /// and the case with the outlets it ended with.
  std::filesystem::path tuning_json() const { return dir / "tuning.json"; }
  std::filesystem::path tuned_case() const { return dir / "tuned.yaml"; }
  /// The geometry the built-in case writes into its run directory (`tearflow run` without a
  /// case); `analyze` and `mri synthesize` look there for landmarks unless told otherwise.
  GeometryFiles geometry() const { return {dir / "geometry"}; }
  /// `tearflow analyze`'s default output and `report`'s page.
  std::filesystem::path analysis_dir() const { return dir / "analysis"; }
  std::filesystem::path metrics_json() const { return analysis_dir() / kMetrics; }
};

} // namespace tearflow
