#include "report/report.hpp"

#include <algorithm>
#include <cstdio>
#include <fstream>
#include <sstream>

#include <fmt/format.h>
#include <vtkBase64Utilities.h>

#include "analysis/hemodynamics.hpp"
#include "core/error.hpp"
#include "core/file_layout.hpp"
#include "core/units.hpp"
#include "report/report_mri.hpp"
#include "tuning/targets.hpp"

namespace tearflow::report {

namespace {

using nlohmann::json;

const std::filesystem::path kAssets = std::filesystem::path(TEARFLOW_SOURCE_DIR) / "report";

std::string read_text(const std::filesystem::path& file, const std::string& what) {
  std::ifstream in(file, std::ios::binary);
  if (!in)
    input_error("cannot read '{}' ({})", file.string(), what);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

/// Text for an inline <script>: "</script" would close it early ("<\/" means "</" in JS).
std::string inline_script(std::string text) {
  for (std::size_t at = 0; (at = text.find("</", at)) != std::string::npos; at += 3)
    text.replace(at, 2, "<\\/");
  return text;
}

/// A landmark's CSV as {column: [values]}.
json read_series(const std::filesystem::path& csv) {
  const analysis::LandmarkTable t = analysis::read_landmark_table(csv);
  json out = json::object();
  for (const std::string& c : t.names)
    out[c] = t.columns.at(c);
  return out;
}

double number(const json& j, const std::vector<std::string>& path) {
  const json* at = &j;
  for (const std::string& key : path) {
    if (!at->is_object() || !at->contains(key))
      return std::nan("");
    at = &(*at)[key];
  }
  return at->is_number() ? at->get<double>() : std::nan("");
}

/// The headline table: one row per quantity, one column per run.
std::string headline_table(const std::vector<json>& runs) {
  struct Row {
    std::string label;
    std::vector<std::string> path;
    double scale = 1.0;
    const char* format = "{:.2f}";
  };
  std::vector<Row> rows{
      {"peak systole [s]", {"peak_systole_time_s"}, 1.0, "{:.3f}"},
      {"inlet net flow volume [mL]", {"landmarks", "inlet", "net_flow_volume_mL"}},
      {"AAo min-to-max dilation [%]", {"AAo_min_to_max_dilation_percent"}}};
  for (int k = 1; k <= 5; ++k)
    rows.push_back(
        {fmt::format("FR_FL station {} [%]", k), {"stations", std::to_string(k), "FR_FL_percent"}});
  for (int k = 1; k <= 5; ++k)
    rows.push_back({fmt::format("dP station {} peak systole [mmHg]", k),
                    {"stations", std::to_string(k), "dP_TL_minus_FL_peak_systole_mmHg"}});
  for (int k = 1; k <= 5; ++k)
    rows.push_back({fmt::format("dP station {} end diastole [mmHg]", k),
                    {"stations", std::to_string(k), "dP_TL_minus_FL_end_diastole_mmHg"}});
  for (const auto& [key, text] : {std::pair{"entry_tear_inlet_to_FL1", "entry tear (inlet - FL1)"},
                                  {"exit_tear_FL5_to_outlet", "exit tear (FL5 - outlet)"},
                                  {"inlet_to_outlet", "inlet - outlet"}})
    rows.push_back({fmt::format("pressure drop {}, peak systole [mmHg]", text),
                    {"pressure_drops", key, "peak_systole_mmHg"}});
  for (int k = 1; k <= 5; ++k)
    rows.push_back(
        {fmt::format("Q_TL + Q_FL vs DAo_dist, station {} [% of peak]", k),
         {"stations", std::to_string(k), "flow_conservation_vs_DAo_dist_relative_to_peak"},
         100.0});
  // Several runs (variants, or a simulation and its measurement): each one's difference from
  // the first beside the values.
  auto name = [&](std::size_t i) { return escape_html(runs[i]["name"].get<std::string>()); };
  // Tuning: the inlet pressures and flow splits the run achieved against its targets.
  for (const char* q : {"systolic", "diastolic", "mean"}) {
    const std::string key = fmt::format("inlet_{}_pressure_mmHg", q);
    rows.push_back({fmt::format("inlet {} pressure, target [mmHg]", q), {"targets", key}});
    rows.push_back({fmt::format("inlet {} pressure, achieved [mmHg]", q), {"achieved", key}});
  }
  std::vector<std::string> outlets;
  for (const json& r : runs)
    for (const char* block : {"targets", "achieved"})
      if (r["metrics"].contains(block) && r["metrics"][block].contains("flow_split_percent"))
        for (const auto& [face, value] : r["metrics"][block]["flow_split_percent"].items())
          if (std::find(outlets.begin(), outlets.end(), face) == outlets.end())
            outlets.push_back(face);
  for (const std::string& face : outlets) {
    rows.push_back(
        {fmt::format("flow split {}, target [%]", face), {"targets", "flow_split_percent", face}});
    rows.push_back({fmt::format("flow split {}, achieved [%]", face),
                    {"achieved", "flow_split_percent", face}});
  }
  std::string html = "<table><tr><th>quantity</th>";
  for (std::size_t i = 0; i < runs.size(); ++i)
    html += "<th>" + name(i) + "</th>";
  for (std::size_t i = 1; i < runs.size(); ++i)
    html += "<th>" + name(i) + " &minus; " + name(0) + "</th>";
  html += "</tr>\n";
  auto cell = [](double v, const char* format) {
    return "<td>" + (std::isnan(v) ? std::string("-") : fmt::format(fmt::runtime(format), v)) +
           "</td>";
  };
  for (const Row& row : rows) {
    std::string cells;
    bool any = false;
    std::vector<double> values;
    for (const json& r : runs) {
      values.push_back(number(r["metrics"], row.path) * row.scale);
      any = any || !std::isnan(values.back());
      cells += cell(values.back(), row.format);
    }
    for (std::size_t i = 1; i < runs.size(); ++i)
      cells += cell(values[i] - values[0], row.format);
    if (any)
      html += "<tr><td>" + escape_html(row.label) + "</td>" + cells + "</tr>\n";
  }
  return html + "</table>\n";
}

/// The text between `open` and the next `close` after `from`; empty when there is none.
std::string between(const std::string& text, std::size_t from, const std::string& open,
                    const std::string& close) {
  const std::size_t a = text.find(open, from);
  if (a == std::string::npos)
    return {};
  const std::size_t b = text.find(close, a + open.size());
  return b == std::string::npos ? std::string() : text.substr(a + open.size(), b - a - open.size());
}

constexpr const char* kStyle = R"(body{font-family:sans-serif;margin:2em;max-width:1100px}
table{border-collapse:collapse}td,th{border:1px solid #ccc;padding:2px 8px;text-align:right}
td:first-child{text-align:left}.figure .canvas{position:relative;height:360px}
#script-errors{color:#b00})";

} // namespace

std::string escape_html(const std::string& s) {
  std::string out;
  for (const char c : s)
    switch (c) {
    case '<':
      out += "&lt;";
      break;
    case '>':
      out += "&gt;";
      break;
    case '&':
      out += "&amp;";
      break;
    case '"':
      out += "&quot;";
      break;
    case '\'':
      out += "&#39;";
      break;
    default:
      out += c;
    }
  return out;
}

json report_run_data(const std::filesystem::path& run_dir,
                     const std::filesystem::path& analysis_dir) {
  const std::filesystem::path metrics_file = analysis_dir / RunFiles::kMetrics;
  if (!std::filesystem::exists(metrics_file))
    input_error("'{}' does not exist: run `tearflow analyze {}` first", metrics_file.string(),
                run_dir.string());
  json metrics;
  try {
    metrics = json::parse(read_text(metrics_file, "metrics"));
  } catch (const json::exception& e) {
    input_error("'{}': not valid JSON: {}", metrics_file.string(), e.what());
  }
  if (!metrics.contains("landmarks") || !metrics["landmarks"].is_object())
    input_error("'{}': no 'landmarks' object (not written by `tearflow analyze`?)",
                metrics_file.string());
  std::filesystem::path where = std::filesystem::absolute(run_dir).lexically_normal();
  if (where.filename().empty())
    where = where.parent_path();
  // A study's runs are VARIANT/run, and VARIANT/rigid for their rigid-wall counterparts
  // (docs/study.md): the variant names them.
  std::string name = where.filename().string();
  if ((name == "run" || name == "rigid") && where.has_parent_path())
    name = where.parent_path().filename().string() + (name == "rigid" ? " rigid" : "");
  json run{{"name", name}, {"metrics", metrics}, {"series", json::object()}};
  for (const auto& [landmark, values] : metrics["landmarks"].items())
    run["series"][landmark] = read_series(analysis_dir / (landmark + ".csv"));
  // The tuning targets of a run made by `tearflow study` (docs/study.md), for the table.
  if (const std::filesystem::path file = run_dir / "targets.yaml"; std::filesystem::exists(file)) {
    const tuning::TuningTargets t = tuning::load_targets(file);
    json& targets = run["metrics"]["targets"];
    targets["inlet_systolic_pressure_mmHg"] = t.pressure.systolic / units::mmHg;
    targets["inlet_diastolic_pressure_mmHg"] = t.pressure.diastolic / units::mmHg;
    targets["inlet_mean_pressure_mmHg"] = t.pressure.mean / units::mmHg;
    for (const tuning::OutletFraction& f : t.splits)
      targets["flow_split_percent"][f.face] = 100.0 * f.fraction;
  }
  return run;
}

std::string report_html(const std::vector<json>& runs, const json& mri) {
  const std::filesystem::path chart_js = kAssets / "node_modules/chart.js/dist/chart.umd.js";
  if (!std::filesystem::exists(chart_js))
    input_error("'{}' does not exist: the report's charting library is installed by "
                "scripts/setup (npm ci in {})",
                chart_js.string(), kAssets.string());
  std::string title = "tearflow report: ";
  for (std::size_t i = 0; i < runs.size(); ++i)
    title += (i ? " vs " : "") + runs[i]["name"].get<std::string>();
  std::string html = "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\n<title>" +
                     escape_html(title) + "</title>\n<style>" + kStyle +
                     "</style></head>\n<body>\n";
  html += "<h1>" + escape_html(title) + "</h1>\n<p>";
  for (const json& r : runs)
    html += fmt::format(
        "{} ({}): {}, {} frames, t = {} to {} s. ", escape_html(r["name"].get<std::string>()),
        escape_html(r["metrics"].value("source", "simulation")),
        escape_html(r["metrics"].value("frames", "")), r["metrics"].value("frame_count", 0),
        r["metrics"].value("t_begin_s", 0.0), r["metrics"].value("t_end_s", 0.0));
  html += "Definitions and units: docs/analysis.md.</p>\n<h2>Headline numbers</h2>\n" +
          headline_table(runs) +
          "<pre id=\"script-errors\"></pre>\n<h2>Figures</h2>\n"
          "<div id=\"figures\"></div>\n";
  if (!mri.is_null())
    html += "<h2>Simulation against 4D-flow MRI</h2>\n<p>From '" +
            escape_html(mri["dir"].get<std::string>()) +
            "' (`tearflow mri compare`; docs/mri.md). Differences are MRI &minus; simulation "
            "on the MRI frames.</p>\n" +
            mri_comparison_table(mri) + "<div id=\"mri-figures\"></div>\n";
  html += "<script>\n" + inline_script(read_text(chart_js, "Chart.js")) + "\n</script>\n";
  html +=
      "<script>window.TEARFLOW_DATA = " + inline_script(json{{"runs", runs}, {"mri", mri}}.dump()) +
      ";</script>\n";
  html += "<script>\n" + inline_script(read_text(kAssets / "report.js", "the report's script")) +
          "\n</script>\n</body></html>\n";
  return html;
}

RenderedPage render_in_chromium(const std::filesystem::path& page, const std::string& chromium) {
  // --virtual-time-budget lets the page's scripts finish before the DOM is dumped; as root
  // (containers) Chromium needs --no-sandbox.
  const std::string command =
      fmt::format("{} --headless --no-sandbox --disable-gpu --virtual-time-budget=10000 "
                  "--dump-dom 'file://{}' 2>/dev/null",
                  chromium, std::filesystem::absolute(page).string());
  FILE* pipe = popen(command.c_str(), "r");
  if (pipe == nullptr)
    input_error("cannot run '{}' to render '{}'", chromium, page.string());
  std::string dom;
  char buffer[65536];
  while (std::size_t n = std::fread(buffer, 1, sizeof buffer, pipe))
    dom.append(buffer, n);
  const int status = pclose(pipe);
  if (status != 0 || dom.empty())
    input_error("'{}' could not render '{}' (is Debian's chromium installed? scripts/setup)",
                chromium, page.string());
  // Plain searches: the DOM holds the PNGs as long base64 strings, which overflow the stack
  // of std::regex's recursive matcher.
  RenderedPage out;
  out.script_errors = between(dom, 0, "<pre id=\"script-errors\">", "</pre>");
  const std::string rendered = between(dom, 0, "data-rendered=\"", "\"");
  if (!rendered.empty())
    out.figures = std::stoi(rendered);
  else if (out.script_errors.empty())
    out.script_errors = "the page's script did not finish (no data-rendered)";
  // Each figure's <img class="figure-png" ... data-name="NAME" src="data:image/png;base64,...">.
  for (std::size_t at = 0; (at = dom.find("<img class=\"figure-png\"", at)) != std::string::npos;
       ++at) {
    const std::size_t end = dom.find('>', at);
    const std::string tag = dom.substr(at, end - at);
    const std::string name = between(tag, 0, "data-name=\"", "\""),
                      encoded = between(tag, 0, "src=\"data:image/png;base64,", "\"");
    if (name.empty() || encoded.empty())
      continue;
    std::string bytes(encoded.size() * 3 / 4 + 3, '\0');
    const std::size_t length = vtkBase64Utilities::DecodeSafely(
        reinterpret_cast<const unsigned char*>(encoded.data()), encoded.size(),
        reinterpret_cast<unsigned char*>(bytes.data()), bytes.size());
    bytes.resize(length);
    out.names.push_back(name);
    out.png_data.push_back(bytes);
  }
  return out;
}

} // namespace tearflow::report
