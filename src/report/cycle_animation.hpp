#pragma once
// The cycle's streamlines as an animated PNG: a run's saved frames, or a 4D-flow scan's frames
// traced from the run's seeds beside it (`tearflow pictures --animate [--mri SCAN]`;
// docs/analysis.md, "Animation").

#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>

#include "analysis/flow_features.hpp"
#include "geometry/landmarks.hpp"
#include "report/flow_pictures.hpp"
#include "report/pictures_command.hpp"
#include "report/scan_pictures.hpp"

namespace tearflow::report {

/// Streamlines already traced through one frame's file (the pictures' first frame).
struct TracedFrame {
  std::filesystem::path file;
  vtkSmartPointer<vtkPolyData> lines;
};

/// The view an animation is seen from: the flap's when there is one, else the first.
const View& animation_view(const std::vector<View>& views);

/// The streamlines from `seed` of every frame of the run's cycle, seen from `view`: each
/// frame's PNG in `out`/animation/, joined into `out`/streamlines_<view>_animation.png. A frame
/// `traced` holds is not traced again. Returns the record pictures.json keeps.
nlohmann::json animate_run(const analysis::CycleFrames& cycle, const geometry::Landmark& seed,
                           const View& view, const PicturesOptions& o, const TracedFrame& traced,
                           const std::filesystem::path& out);

/// The same for every frame of the scan, from the run's `seeds` in the run's camera (`bounds`
/// its lumen's), so that the two animations stand side by side: mri_streamlines_<view>_... .
nlohmann::json animate_scan(const ScanPictures& scan, vtkPolyData* seeds, const double* bounds,
                            const View& view, const PicturesOptions& o,
                            const std::filesystem::path& out);

} // namespace tearflow::report
