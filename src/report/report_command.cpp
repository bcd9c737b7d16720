#include "report/report_command.hpp"

#include <fstream>

#include <fmt/format.h>

#include "core/error.hpp"
#include "core/file_layout.hpp"
#include "io/vtu_series.hpp"
#include "report/flow_section.hpp"
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

/// The heat maps of a tear-size sweep (`rom sweep`, sweep.html between its markers) as a
/// section of a page; InputError naming the file when it is missing or not a sweep page.
std::string sweep_section(const std::filesystem::path& dir) {
  const std::filesystem::path file = dir / "sweep.html";
  std::ifstream in(file);
  if (!in)
    input_error("--rom-sweep: '{}' does not exist (write it with `tearflow rom sweep`)",
                file.string());
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string begin = "<!-- tearflow-sweep-maps begin -->",
                    end = "<!-- tearflow-sweep-maps end -->";
  const auto b = text.find(begin), e = text.find(end);
  if (b == std::string::npos || e == std::string::npos || e < b)
    input_error("--rom-sweep: '{}' is not a page of `tearflow rom sweep` (no maps in it)",
                file.string());
  return "<section id='rom-sweep'><h2>Tear-size maps (reduced-order model)</h2>\n" +
         text.substr(b + begin.size(), e - b - begin.size()) + "</section>\n";
}

/// The page with `section` before its end.
std::string with_section(std::string html, const std::string& section) {
  if (section.empty())
    return html;
  const auto end = html.rfind("</body>");
  return end == std::string::npos ? html + section : html.insert(end, section);
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
  command_->add_option("--rom-sweep", rom_sweep_,
                       "folder written by `tearflow rom sweep`: adds its tear-size heat maps "
                       "(docs/rom.md)");
  command_->add_flag("--png", png_,
                     "render in headless Chromium and save each figure as PNG (analysis/figures/)");
  command_->add_option("--chromium", chromium_, "the browser for --png (default chromium)");
  command_->add_flag("-q,--quiet", quiet_, "no summary lines");
}

int ReportCommand::run() const {
  std::vector<nlohmann::json> runs;
  const nlohmann::json mri = mri_.empty() ? nlohmann::json() : report_mri_data(mri_);
  const std::string sweep = rom_sweep_.empty() ? std::string() : sweep_section(rom_sweep_);
  std::vector<std::filesystem::path> dirs;
  std::vector<std::string> names;
  for (const std::string& dir : run_dirs_) {
    const std::filesystem::path analysis = RunFiles{dir}.analysis_dir();
    runs.push_back(report_run_data(dir, analysis));
    dirs.push_back(dir);
    names.push_back(runs.back()["name"].get<std::string>());
    // The flow pictures of `tearflow pictures`, when the run has them.
    const std::string flow = flow_patterns_section({dirs.back()}, {names.back()});
    write_page(with_section(report_html({runs.back()}, mri), sweep + flow),
               analysis / "report.html", png_, analysis / "figures", chromium_, quiet_);
  }
  if (runs.size() > 1) {
    const std::string flow = flow_patterns_section(dirs, names);
    const std::filesystem::path page = comparison_;
    std::filesystem::path figures = page;
    figures.replace_extension("");
    figures += "_figures";
    write_page(with_section(report_html(runs, mri), sweep + flow), page, png_, figures, chromium_,
               quiet_);
    // The flow pictures beside the page's figures, so that the figures folder holds every
    // picture the page shows (a run's own page finds them in its analysis/figures/flow/).
    if (const std::size_t n = copy_flow_pictures(dirs, names, figures); n > 0 && !quiet_)
      fmt::print("copied {} flow pictures into '{}'\n", n, (figures / "flow").string());
  }
  return 0;
}

} // namespace tearflow::report
