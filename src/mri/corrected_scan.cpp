// Reading and correcting a scan (corrected_scan.hpp).
#include "mri/corrected_scan.hpp"

#include <chrono>

#include <spdlog/spdlog.h>

#include "mri/corrections.hpp"
#include "mri/image_io.hpp"
#include "mri/non_finite.hpp"

namespace tearflow::mri {

namespace {
double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}
} // namespace

Flow4D read_corrected(const std::filesystem::path& input, const CorrectionChoice& choice,
                      nlohmann::json& report) {
  auto t0 = std::chrono::steady_clock::now();
  Flow4D data = read_flow_data(input, {choice.venc});
  report["read_s"] = seconds_since(t0);
  report["encoding"] = encoding_name(data.encoding);
  report["grid"] = {
      {"size", data.grid.size},
      {"spacing_mm",
       {data.grid.spacing[0] * 1e3, data.grid.spacing[1] * 1e3, data.grid.spacing[2] * 1e3}},
      {"frames", data.frames.size()},
      {"venc_m_per_s", data.venc}};
  // Values that are not numbers, said once here for every command and recorded with the
  // reading; a measurement that reads one refuses (non_finite.hpp), so a command that ends
  // well did not use them.
  report["non_finite"] = non_finite_json(data);
  for (const std::string& line : describe_non_finite(data))
    spdlog::warn("{}", line);
  if (data.encoding == Encoding::magnitude)
    return data; // no phase to correct
  t0 = std::chrono::steady_clock::now();
  if (!choice.unwrap)
    report["unwrap"] = "off";
  else if (!(data.venc > 0))
    report["unwrap"] = "skipped: the data has no venc (give --venc)";
  else
    report["unwrap"] = unwrap_temporal(data).to_json();
  report["unwrap_s"] = seconds_since(t0);
  t0 = std::chrono::steady_clock::now();
  if (!choice.background) {
    report["background"] = "off";
  } else {
    BackgroundOptions bo;
    bo.order = choice.background_order;
    report["background"] = correct_background(data, bo).to_json();
  }
  report["background_s"] = seconds_since(t0);
  return data;
}

} // namespace tearflow::mri
