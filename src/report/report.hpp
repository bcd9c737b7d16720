#pragma once
// `tearflow report`: self-contained HTML pages of analysed runs (analysis/metrics.json and the
// CSV per landmark written by `tearflow analyze`). The figures are drawn in the browser by
// Chart.js (npm, installed by scripts/setup into report/node_modules), inlined into the page
// with the run's data and report/report.js, so that the page needs no network and no other
// file. Headless Chromium renders a page to check it and to save each figure as PNG.
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace tearflow::report {

/// `s` with <, >, &, " and ' as entities, for text and attribute values (either quote) in an
/// HTML page or an XML file.
std::string escape_html(const std::string& s);

/// One analysed run as the page sees it: {name, metrics, series: {landmark: {column: [...]}}}.
/// InputError naming the file when metrics.json or a landmark's CSV is missing or malformed.
nlohmann::json report_run_data(const std::filesystem::path& run_dir,
                               const std::filesystem::path& analysis_dir);

/// The HTML page of one run (runs.size() == 1) or of several compared; with `mri`
/// (report_mri_data, report_mri.hpp) also the section of the simulation against 4D-flow MRI.
std::string report_html(const std::vector<nlohmann::json>& runs,
                        const nlohmann::json& mri = nullptr);

/// What headless Chromium made of a page.
struct RenderedPage {
  int figures = 0;                   ///< figures drawn (body[data-rendered])
  std::string script_errors;         ///< empty when none
  std::vector<std::string> names;    ///< per figure
  std::vector<std::string> png_data; ///< per figure, the PNG bytes
};

/// Renders `page` with `chromium` (headless) and reads the figures back. InputError when the
/// browser cannot be run or the page did not finish drawing.
RenderedPage render_in_chromium(const std::filesystem::path& page,
                                const std::string& chromium = "chromium");

} // namespace tearflow::report
