#include "report/flow_section.hpp"

#include <algorithm>
#include <fstream>
#include <optional>

#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <vtkBase64Utilities.h>

#include "core/error.hpp"
#include "core/file_layout.hpp"
#include "report/report.hpp"

namespace tearflow::report {

namespace {

using nlohmann::json;

std::string base64(const std::string& bytes) {
  // 4 characters per 3 bytes, rounded up, and the terminating zero Encode may write.
  std::string out(4 * ((bytes.size() + 2) / 3) + 1, '\0');
  const unsigned long n =
      vtkBase64Utilities::Encode(reinterpret_cast<const unsigned char*>(bytes.data()), bytes.size(),
                                 reinterpret_cast<unsigned char*>(out.data()));
  out.resize(n);
  return out;
}

std::string read_bytes(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// One run's pictures of its first frame.
struct RunPictures {
  std::filesystem::path folder;
  std::string event;
  double time = 0.0;
  std::vector<std::string> files;
};

std::optional<RunPictures> run_pictures(const std::filesystem::path& run_dir) {
  const std::filesystem::path record = flow_pictures_dir(run_dir) / "pictures.json";
  std::ifstream in(record);
  if (!in)
    return std::nullopt;
  const json j = json::parse(in, nullptr, false);
  if (j.is_discarded() || !j.contains("frames") || !j["frames"].is_array())
    input_error("'{}': not a record of `tearflow pictures` (no 'frames' list)", record.string());
  if (j["frames"].empty())
    return std::nullopt;
  const json& f = j["frames"][0];
  RunPictures p;
  p.folder = record.parent_path() / f.value("folder", "");
  p.event = f.value("event", "");
  p.time = f.value("time_s", 0.0);
  for (const json& picture : f.value("pictures", json::array()))
    p.files.push_back(picture.value("file", ""));
  // The animation over the cycle (`--animate`) lies beside the frames' folders.
  if (j.contains("animation") && j["animation"].is_object())
    p.files.push_back("../" + j["animation"].value("file", ""));
  return p;
}

} // namespace

std::filesystem::path flow_pictures_dir(const std::filesystem::path& run_dir) {
  return RunFiles{run_dir}.analysis_dir() / "figures" / "flow";
}

std::string flow_patterns_section(const std::vector<std::filesystem::path>& run_dirs,
                                  const std::vector<std::string>& names) {
  std::vector<std::optional<RunPictures>> runs;
  std::vector<std::string> order; // the first run's pictures, then any the others add
  for (const std::filesystem::path& dir : run_dirs) {
    runs.push_back(run_pictures(dir));
    if (runs.back())
      for (const std::string& file : runs.back()->files)
        if (std::find(order.begin(), order.end(), file) == order.end())
          order.push_back(file);
  }
  if (order.empty())
    return "";
  std::string html = "<section id='flow-patterns'><h2>Flow patterns</h2>\n<p>From `tearflow "
                     "pictures` (docs/analysis.md, \"Flow pictures\"): streamlines coloured by "
                     "speed, and per landmark plane the through-plane velocity with the in-plane "
                     "flow as arrows, on the colour scales each picture states.</p>\n"
                     "<table class='flow-patterns'><tr>";
  for (std::size_t i = 0; i < runs.size(); ++i)
    html += fmt::format(
        "<th>{}{}</th>", escape_html(names[i]),
        runs[i] ? fmt::format(": {} (t = {} s)", escape_html(runs[i]->event), runs[i]->time)
                : std::string(": no pictures"));
  html += "</tr>\n";
  const std::string width = fmt::format("{}%", 100 / runs.size());
  for (const std::string& file : order) {
    html += "<tr>";
    for (const auto& run : runs) {
      html += "<td style='width:" + width + "'>";
      if (run && std::find(run->files.begin(), run->files.end(), file) != run->files.end()) {
        const std::string bytes = read_bytes(run->folder / file);
        if (!bytes.empty())
          html += "<img class='flow-picture' style='width:100%;max-width:560px' alt='" +
                  escape_html(file) + "' src='data:image/png;base64," + base64(bytes) + "'>";
      }
      html += "</td>";
    }
    html += "</tr>\n";
  }
  return html + "</table></section>\n";
}

} // namespace tearflow::report
