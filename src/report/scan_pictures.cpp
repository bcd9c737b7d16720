#include "report/scan_pictures.hpp"

#include <algorithm>

#include <vtkUnstructuredGrid.h>

#include "analysis/flow_features.hpp"
#include "core/error.hpp"
#include "mri/corrected_scan.hpp"
#include "mri/plane_flow.hpp"
#include "mri/surface_alignment.hpp"

namespace tearflow::report {

namespace {

/// The landmarks the scan's cycle is read at, in the order tried: the run's reference
/// (inlet, as analysis::cycle_frames takes it), then AAo, then the rest.
std::vector<geometry::Landmark> reference_order(const geometry::Landmarks& landmarks) {
  std::vector<geometry::Landmark> order;
  for (const char* name : {"inlet", "AAo"})
    for (const geometry::Landmark& l : landmarks.planes)
      if (l.name == name)
        order.push_back(l);
  for (const geometry::Landmark& l : landmarks.planes)
    if (l.name != "inlet" && l.name != "AAo")
      order.push_back(l);
  return order;
}

} // namespace

ScanPictures::ScanPictures(const ScanOptions& o, const std::filesystem::path& run_dir,
                           const geometry::Landmarks& landmarks) {
  if (!(o.lumen_fraction > 0 && o.lumen_fraction < 1))
    input_error("pictures: --mri-lumen-fraction must lie in (0, 1) (got {})", o.lumen_fraction);
  nlohmann::json corrections;
  mri::CorrectionChoice choice; // as `mri flow` corrects by default
  choice.venc = o.venc;
  data_ = mri::read_corrected(o.scan, choice, corrections);
  data_.require(mri::Encoding::velocity_3d, fmt::format("pictures: --mri '{}'", o.scan));
  record_ = {{"scan", o.scan}, {"corrections", corrections}};
  model_to_scan_ =
      mri::place_scan(data_, o.align, o.align_surface ? run_dir : std::filesystem::path(),
                      o.lumen_fraction, record_)
          .transform;
  if (!record_.contains("alignment"))
    record_["alignment"] = "none: the scan is in the model's coordinates";
  lumen_ = mri::lumen_level(data_, o.lumen_fraction);
  record_["lumen_level"] = {{"fraction_of_p99_mean_magnitude", o.lumen_fraction},
                            {"magnitude", lumen_.level}};

  // The events by the run's rule, on the flow `mri flow` measures at the first reference
  // plane the scan holds.
  std::string why;
  for (const geometry::Landmark& l : reference_order(landmarks)) {
    geometry::Landmarks one;
    one.planes = {l};
    std::vector<mri::PlaneSeries> series;
    try {
      series = mri::measure_planes(data_, mri::transformed(one, model_to_scan_));
    } catch (const InputError& e) {
      why += fmt::format("\n  {}: {}", l.name, e.what());
      continue;
    }
    std::vector<double> time;
    for (const mri::Frame& f : data_.frames)
      time.push_back(f.time);
    const analysis::CycleEvents e = analysis::cycle_events(time, series[0].flow);
    peak_ = e.peak_systole;
    mid_ = e.mid_diastole;
    record_["reference_landmark"] = l.name;
    record_["reference_flow_m3_per_s"] = series[0].flow;
    record_["frame_times_s"] = time;
    record_["peak_systole_frame"] = *peak_;
    record_["mid_diastole_frame"] = mid_ ? nlohmann::json(*mid_) : nlohmann::json();
    return;
  }
  input_error("pictures: --mri '{}': no landmark plane to find the scan's peak systole by:{}",
              o.scan, why);
}

std::optional<std::size_t> ScanPictures::frame_of(const std::string& event) const {
  if (event == "peak systole")
    return peak_;
  if (event == "mid-diastole")
    return mid_;
  return std::nullopt;
}

vtkSmartPointer<vtkUnstructuredGrid> ScanPictures::field(std::size_t frame) const {
  return mri::lumen_field(data_, frame, lumen_, model_to_scan_);
}

} // namespace tearflow::report
