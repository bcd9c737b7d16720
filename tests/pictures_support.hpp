#pragma once
// The flow pictures' CI-sized run (tests/test_flow_pictures.cpp, tests/test_paraview_state.cpp):
// a two-lumen channel, a true lumen (x = 0, r = 5 mm) and a false lumen beside it (x = 12 mm,
// r = 4 mm), each carrying Poiseuille flow along z with a time-varying amplitude
// (tests/analysis_support.hpp), with landmarks at the inlet, a TL/FL station and the outlet;
// and how much of a picture is drawn.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <string>

#include <vtkDataArray.h>
#include <vtkImageData.h>
#include <vtkPNGReader.h>
#include <vtkPointData.h>
#include <vtkSmartPointer.h>

#include "analysis_support.hpp"
#include "cli_support.hpp"
#include "geometry/landmarks.hpp"

namespace tearflow::testing {

inline constexpr double kTwoLumenLength = 0.03; // [m]

inline SyntheticRun two_lumen_run() {
  SyntheticRun run;
  run.lumina = {SyntheticLumen{0.0, 0.005, 0.6, 1.0e4}, SyntheticLumen{0.012, 0.004, 0.3, 0.9e4}};
  run.length = kTwoLumenLength;
  run.element_size = 0.001; // 1 mm: 20 k tets, and a flow error of 1-2 % at most
  return run;
}

inline geometry::Landmarks two_lumen_landmarks(const SyntheticRun& run) {
  geometry::Landmarks l;
  l.planes = {plane_at(run, "inlet", 0.004), plane_at(run, "TL1", 0.015, 0, "TL"),
              plane_at(run, "FL1", 0.015, 1, "FL"), plane_at(run, "outlet", 0.026)};
  return l;
}

/// A run folder laid out as `tearflow run` writes one, with its landmarks in geometry/.
struct RunFolder {
  SyntheticRun run = two_lumen_run();
  std::filesystem::path dir;
  EdgeLengths edges;
  geometry::Landmarks landmarks;
  /// `change` alters the run before it is written (a moving wall, other amplitudes).
  explicit RunFolder(const std::string& name,
                     const std::function<void(SyntheticRun&)>& change = nullptr)
      : dir(fresh_dir(name)) {
    if (change)
      change(run);
    edges = write_synthetic_run(run, dir);
    landmarks = two_lumen_landmarks(run);
    std::filesystem::create_directories(dir / "geometry");
    geometry::write_landmarks(landmarks, dir / "geometry" / "landmarks.json");
  }
};

/// The share of a PNG's pixels that differ from the white background.
inline double drawn_fraction(const std::filesystem::path& png) {
  auto reader = vtkSmartPointer<vtkPNGReader>::New();
  reader->SetFileName(png.c_str());
  reader->Update();
  vtkImageData* image = reader->GetOutput();
  vtkDataArray* rgb = image->GetPointData()->GetScalars();
  if (rgb == nullptr || rgb->GetNumberOfTuples() == 0)
    return 0.0;
  vtkIdType drawn = 0;
  for (vtkIdType i = 0; i < rgb->GetNumberOfTuples(); ++i)
    for (int c = 0; c < std::min(3, rgb->GetNumberOfComponents()); ++c)
      if (rgb->GetComponent(i, c) < 250) {
        ++drawn;
        break;
      }
  return static_cast<double>(drawn) / static_cast<double>(rgb->GetNumberOfTuples());
}

/// The share of the pixels left of `x_fraction` of a PNG's width that are strongly coloured
/// (largest minus smallest channel >= 100): a colour map's hues, not the grey lumen, the white
/// background, the black caption or (with x_fraction left of it) the colour bar.
inline double coloured_fraction(const std::filesystem::path& png, double x_fraction) {
  auto reader = vtkSmartPointer<vtkPNGReader>::New();
  reader->SetFileName(png.c_str());
  reader->Update();
  vtkImageData* image = reader->GetOutput();
  vtkDataArray* rgb = image->GetPointData()->GetScalars();
  if (rgb == nullptr || rgb->GetNumberOfComponents() < 3)
    return 0.0;
  const int width = image->GetDimensions()[0], height = image->GetDimensions()[1];
  const int columns = static_cast<int>(x_fraction * width);
  vtkIdType coloured = 0;
  for (int j = 0; j < height; ++j)
    for (int i = 0; i < columns; ++i) {
      const vtkIdType p = static_cast<vtkIdType>(j) * width + i;
      const double r = rgb->GetComponent(p, 0), g = rgb->GetComponent(p, 1),
                   b = rgb->GetComponent(p, 2);
      if (std::max({r, g, b}) - std::min({r, g, b}) >= 100)
        ++coloured;
    }
  return columns > 0 ? static_cast<double>(coloured) / (static_cast<double>(columns) * height)
                     : 0.0;
}

/// The number of frames an animated PNG's acTL chunk declares; 0 when it has none.
inline unsigned apng_frame_count(const std::filesystem::path& png) {
  std::ifstream in(png, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::size_t actl = bytes.find("acTL");
  if (actl == std::string::npos || actl + 8 > bytes.size())
    return 0;
  const auto byte = [&](std::size_t k) {
    return static_cast<unsigned>(static_cast<unsigned char>(bytes[k]));
  };
  return (byte(actl + 4) << 24) | (byte(actl + 5) << 16) | (byte(actl + 6) << 8) | byte(actl + 7);
}

} // namespace tearflow::testing
