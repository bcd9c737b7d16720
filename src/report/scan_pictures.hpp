#pragma once
// The 4D-flow scan beside a run's pictures (issue 30, `tearflow pictures RUN --mri SCAN`): the
// scan read and corrected as `mri flow` reads it (mri/corrected_scan.hpp), moved into the
// model's coordinates (mri/lumen_field.hpp) so that the run's landmarks, seeds and cameras
// serve it unchanged, and its frames of the cycle's events found by the run's own rule
// (analysis::cycle_events) on the scan's flow through the reference landmark.
#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <vtkSmartPointer.h>

#include "geometry/landmarks.hpp"
#include "mri/alignment.hpp"
#include "mri/flow_dataset.hpp"
#include "mri/lumen_field.hpp"

class vtkUnstructuredGrid;

namespace tearflow::report {

struct ScanOptions {
  std::string scan;  ///< DICOM folder or volume folder (`mri flow`'s input)
  std::string align; ///< paired model / MRI points (JSON, mri/alignment.hpp); empty: none
  /// Fit the scan's lumen surface to the run's mesh (ICP, mri/surface_alignment.hpp), started
  /// from `align` when given; neither: the scan is in the model's coordinates already.
  bool align_surface = false;
  double lumen_fraction = 0.6; ///< lumen: time-mean magnitude >= this x its 99th percentile
  double venc = 0.0;           ///< [m/s]; > 0 overrides (or supplies) the files' velocity encoding
};

class ScanPictures {
public:
  /// Reads and corrects the scan, aligns it, finds its events; InputError naming the scan,
  /// the alignment file or the landmark when one cannot be had.
  ScanPictures(const ScanOptions& options, const std::filesystem::path& run_dir,
               const geometry::Landmarks& landmarks);

  /// The scan's frame of "peak systole" or "mid-diastole"; none for another event or when the
  /// scan's flow has no such frame.
  std::optional<std::size_t> frame_of(const std::string& event) const;
  std::size_t frames() const { return data_.frames.size(); }
  double time_of(std::size_t frame) const { return data_.frames.at(frame).time; }
  /// The frame as a fluid grid in model coordinates (mri::lumen_field).
  vtkSmartPointer<vtkUnstructuredGrid> field(std::size_t frame) const;
  /// What was read and how it was placed: the scan, the grid, the corrections, the transform,
  /// the lumen level, the reference landmark's flow per frame and the events' frames.
  const nlohmann::json& record() const { return record_; }

private:
  mri::Flow4D data_;
  mri::RigidTransform model_to_scan_;
  mri::LumenLevel lumen_;
  std::optional<std::size_t> peak_, mid_;
  nlohmann::json record_;
};

} // namespace tearflow::report
