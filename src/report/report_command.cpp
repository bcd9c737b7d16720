#include "report/report_command.hpp"

#include <fmt/format.h>

#include "core/error.hpp"
#include "core/file_layout.hpp"
#include "io/vtu_series.hpp"
#include "report/report.hpp"
#include "report/report_mri.hpp"

namespace tearflow::report {

namespace {

/// Writes `html` to `page`; with `png`, renders it in headless Chromium, fails on script
/// errors and saves each figure as `<figures>/<name>.png`.
void write_page(const std::string& html, const std::filesystem::path& page, bool png,
                const std::filesystem::path& figures, const std::string& chromium, bool quiet) {
  io::write_file_atomically(page, html);
  if (!quiet)
    fmt::print("wrote '{}'\n", page.string());
  if (!png)
    return;
  const RenderedPage rendered = render_in_chromium(page, chromium);
  if (!rendered.script_errors.empty())
    input_error("'{}': script errors in Chromium: {}", page.string(), rendered.script_errors);
  std::filesystem::create_directories(figures);
  for (std::size_t i = 0; i < rendered.names.size(); ++i)
    io::write_file_atomically(figures / (rendered.names[i] + ".png"), rendered.png_data[i]);
  if (!quiet)
    fmt::print("wrote {} figures into '{}'\n", rendered.names.size(), figures.string());
}

} // namespace

ReportCommand::ReportCommand(CLI::App& app) {
  command_ = app.add_subcommand("report", "HTML pages of analysed runs: RUN_DIR/analysis/"
                                          "report.html, and a comparison page for several");
  command_->add_option("run_dirs", run_dirs_, "output directories analysed by `tearflow analyze`")
      ->required();
  command_->add_option("-o,--output", comparison_,
                       "comparison page when several runs are given (default comparison.html)");
  command_->add_option("--mri", mri_,
                       "folder written by `tearflow mri compare`: adds the simulation-MRI "
                       "statistics, Bland-Altman plot and flow waveforms to every page");
  command_->add_flag("--png", png_,
                     "render in headless Chromium and save each figure as PNG (analysis/figures/)");
  command_->add_option("--chromium", chromium_, "the browser for --png (default chromium)");
  command_->add_flag("-q,--quiet", quiet_, "no summary lines");
}

int ReportCommand::run() const {
  std::vector<nlohmann::json> runs;
  const nlohmann::json mri = mri_.empty() ? nlohmann::json() : report_mri_data(mri_);
  for (const std::string& dir : run_dirs_) {
    const std::filesystem::path analysis = RunFiles{dir}.analysis_dir();
    runs.push_back(report_run_data(dir, analysis));
    write_page(report_html({runs.back()}, mri), analysis / "report.html", png_,
               analysis / "figures", chromium_, quiet_);
  }
  if (runs.size() > 1) {
    const std::filesystem::path page = comparison_;
    std::filesystem::path figures = page;
    figures.replace_extension("");
    figures += "_figures";
    write_page(report_html(runs, mri), page, png_, figures, chromium_, quiet_);
  }
  return 0;
}

} // namespace tearflow::report
