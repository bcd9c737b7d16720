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

/// One column of the section: a run's pictures of its first frame, or the pictures of the
/// scan `tearflow pictures --mri` drew beside them (the run's file names with "mri_" ahead).
struct Column {
  std::string title;
  std::filesystem::path folder;
  std::string prefix; ///< ahead of the run's file name: "" or "mri_"
  std::vector<std::string> files;
};

/// A run's picture's name in a column with `prefix`: the prefix before the file's own name
/// ("../streamlines_flap_animation.png" -> "../mri_streamlines_flap_animation.png").
std::string prefixed(const std::string& prefix, const std::string& file) {
  const std::size_t slash = file.rfind('/');
  const std::size_t at = slash == std::string::npos ? 0 : slash + 1;
  return file.substr(0, at) + prefix + file.substr(at);
}

std::vector<std::string> files_of(const json& frame) {
  std::vector<std::string> files;
  for (const json& picture : frame.value("pictures", json::array()))
    files.push_back(picture.value("file", ""));
  return files;
}

/// The run's column, and the scan's when it has pictures; none without pictures.json.
std::vector<Column> run_columns(const std::filesystem::path& run_dir, const std::string& name) {
  const std::filesystem::path record = flow_pictures_dir(run_dir) / "pictures.json";
  std::ifstream in(record);
  if (!in)
    return {};
  const json j = json::parse(in, nullptr, false);
  if (j.is_discarded() || !j.contains("frames") || !j["frames"].is_array())
    input_error("'{}': not a record of `tearflow pictures` (no 'frames' list)", record.string());
  if (j["frames"].empty())
    return {};
  const json& f = j["frames"][0];
  Column run{fmt::format("{}: {} (t = {} s)", name, f.value("event", ""), f.value("time_s", 0.0)),
             record.parent_path() / f.value("folder", ""), "", files_of(f)};
  // The model's picture and the animation over the cycle (`--animate`) lie beside the
  // frames' folders: the model first, the geometry the flow is read against.
  if (j.contains("model") && j["model"].is_object() && j["model"]["file"].is_string())
    run.files.insert(run.files.begin(), "../" + j["model"]["file"].get<std::string>());
  if (j.contains("animation") && j["animation"].is_object())
    run.files.push_back("../" + j["animation"].value("file", ""));
  std::vector<Column> columns = {run};
  if (f.contains("scan") && f["scan"].is_object() && f["scan"].contains("pictures")) {
    Column scan{fmt::format("{}: 4D-flow MRI, scan frame {} ({} s after the trigger)", name,
                            f["scan"].value("frame", 0),
                            f["scan"].value("time_after_trigger_s", 0.0)),
                run.folder, "mri_", files_of(f["scan"])};
    // The scan's animation, from the run's seeds, beside the run's (`--animate --mri`).
    if (j.contains("scan_animation") && j["scan_animation"].is_object())
      scan.files.push_back("../" + j["scan_animation"].value("file", ""));
    columns.push_back(scan);
  }
  return columns;
}

} // namespace

std::filesystem::path flow_pictures_dir(const std::filesystem::path& run_dir) {
  return RunFiles{run_dir}.analysis_dir() / "figures" / "flow";
}

std::string flow_patterns_section(const std::vector<std::filesystem::path>& run_dirs,
                                  const std::vector<std::string>& names) {
  std::vector<Column> columns;
  std::vector<std::string> order; // the first run's pictures, then any the others add
  for (std::size_t i = 0; i < run_dirs.size(); ++i) {
    std::vector<Column> run = run_columns(run_dirs[i], names[i]);
    if (run.empty())
      columns.push_back({names[i] + ": no pictures", {}, "", {}});
    for (Column& c : run) {
      if (c.prefix.empty())
        for (const std::string& file : c.files)
          if (std::find(order.begin(), order.end(), file) == order.end())
            order.push_back(file);
      columns.push_back(std::move(c));
    }
  }
  if (order.empty())
    return "";
  std::string html = "<section id='flow-patterns'><h2>Flow patterns</h2>\n<p>From `tearflow "
                     "pictures` (docs/analysis.md, \"Flow pictures\"): streamlines coloured by "
                     "speed, and per landmark plane the through-plane velocity with the in-plane "
                     "flow as arrows, on the colour scales each picture states. A 4D-flow scan "
                     "given with --mri stands beside its run, drawn from the same seeds and "
                     "views on the same scales.</p>\n"
                     "<table class='flow-patterns'><tr>";
  for (const Column& c : columns)
    html += fmt::format("<th>{}</th>", escape_html(c.title));
  html += "</tr>\n";
  const std::string width = fmt::format("{}%", 100 / columns.size());
  for (const std::string& file : order) {
    html += "<tr>";
    for (const Column& c : columns) {
      html += "<td style='width:" + width + "'>";
      const std::string name = prefixed(c.prefix, file);
      if (std::find(c.files.begin(), c.files.end(), name) != c.files.end()) {
        const std::string bytes = read_bytes(c.folder / name);
        if (!bytes.empty())
          html += "<img class='flow-picture' style='width:100%;max-width:560px' alt='" +
                  escape_html(name) + "' src='data:image/png;base64," + base64(bytes) + "'>";
        else // listed in pictures.json but gone or empty: said on the page, not skipped
          html += "<p class='missing-picture'>missing: '" +
                  escape_html((c.folder / name).string()) + "' (run `tearflow pictures` again)</p>";
      }
      html += "</td>";
    }
    html += "</tr>\n";
  }
  return html + "</table></section>\n";
}

std::size_t copy_flow_pictures(const std::vector<std::filesystem::path>& run_dirs,
                               const std::vector<std::string>& names,
                               const std::filesystem::path& figures) {
  namespace fs = std::filesystem;
  std::size_t copied = 0;
  for (std::size_t i = 0; i < run_dirs.size(); ++i) {
    const fs::path from = flow_pictures_dir(run_dirs[i]);
    if (!fs::exists(from / "pictures.json"))
      continue;
    std::string folder = names[i];
    std::replace(folder.begin(), folder.end(), ' ', '_'); // "OR rigid" -> OR_rigid
    for (const fs::directory_entry& e : fs::recursive_directory_iterator(from)) {
      if (!e.is_regular_file() || e.path().extension() != ".png" ||
          e.path().parent_path().filename() == "animation") // the animation's own frames
        continue;
      const fs::path to = figures / "flow" / folder / fs::relative(e.path(), from);
      std::error_code ec;
      fs::create_directories(to.parent_path(), ec);
      if (!ec)
        fs::copy_file(e.path(), to, fs::copy_options::overwrite_existing, ec);
      if (ec)
        input_error("cannot copy the picture '{}' to '{}': {}", e.path().string(), to.string(),
                    ec.message());
      ++copied;
    }
  }
  return copied;
}

} // namespace tearflow::report
