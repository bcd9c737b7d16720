// The MRI comparison section of a report page (report_mri.hpp).
#include "report/report_mri.hpp"

#include "report/report.hpp"

#include <cmath>
#include <fstream>
#include <sstream>

#include <fmt/format.h>

#include "core/error.hpp"

namespace tearflow::report {

namespace {

using nlohmann::json;

constexpr const char* kColumns[] = {"time_s", "simulation_mL_per_s", "mri_mL_per_s",
                                    "difference_mL_per_s", "mean_mL_per_s"};

/// flow_comparison.csv as {landmark: {column: [...]}} (landmark order kept in `order`).
json read_pairs(const std::filesystem::path& csv, std::vector<std::string>& order) {
  std::ifstream in(csv);
  if (!in)
    input_error("'{}' does not exist: the folder must be written by `tearflow mri compare`",
                csv.string());
  std::string line;
  std::getline(in, line);
  std::string expected = "landmark";
  for (const char* c : kColumns)
    expected += std::string(",") + c;
  if (line != expected)
    input_error("'{}' line 1: expected the header '{}'", csv.string(), expected);
  json pairs = json::object();
  for (int row = 2; std::getline(in, line); ++row) {
    if (line.empty())
      continue;
    std::istringstream r(line);
    std::string landmark, cell;
    std::getline(r, landmark, ',');
    if (!pairs.contains(landmark)) {
      order.push_back(landmark);
      for (const char* c : kColumns)
        pairs[landmark][c] = json::array();
    }
    for (const char* c : kColumns) {
      if (!std::getline(r, cell, ','))
        input_error("'{}' line {}: 6 columns expected", csv.string(), row);
      try {
        pairs[landmark][c].push_back(std::stod(cell));
      } catch (const std::exception&) {
        input_error("'{}' line {}, column {}: '{}' is not a number", csv.string(), row, c, cell);
      }
    }
  }
  if (pairs.empty())
    input_error("'{}': no rows", csv.string());
  return pairs;
}

std::string cell(const json& j, const char* key, const char* format = "{:.2f}") {
  if (!j.contains(key) || !j[key].is_number())
    return "<td>-</td>";
  return "<td>" + fmt::format(fmt::runtime(format), j[key].get<double>()) + "</td>";
}

} // namespace

json report_mri_data(const std::filesystem::path& compare_dir) {
  const std::filesystem::path file = compare_dir / "compare.json";
  std::ifstream in(file);
  if (!in)
    input_error("'{}' does not exist: run `tearflow mri compare SIMULATION MRI -o {}` first",
                file.string(), compare_dir.string());
  json comparison;
  try {
    comparison = json::parse(in);
  } catch (const json::exception& e) {
    input_error("'{}': not valid JSON: {}", file.string(), e.what());
  }
  if (!comparison.contains("landmarks") || !comparison["landmarks"].is_object())
    input_error("'{}': no 'landmarks' object (not written by `tearflow mri compare`?)",
                file.string());
  std::vector<std::string> order;
  json pairs = read_pairs(compare_dir / "flow_comparison.csv", order);
  // Pooled Bland-Altman statistics over every landmark's pairs.
  double sum = 0, sum2 = 0;
  std::size_t n = 0;
  for (const auto& [landmark, p] : pairs.items())
    for (const json& d : p["difference_mL_per_s"]) {
      sum += d.get<double>(), sum2 += d.get<double>() * d.get<double>();
      ++n;
    }
  const double bias = sum / n;
  const double sd = n > 1 ? std::sqrt(std::max(0.0, (sum2 - sum * sum / n) / (n - 1))) : 0.0;
  return {{"dir", compare_dir.string()},
          {"comparison", comparison},
          {"landmarks", order},
          {"pairs", pairs},
          {"pooled",
           {{"pairs", n},
            {"bias_mL_per_s", bias},
            {"sd_mL_per_s", sd},
            {"limits_of_agreement_mL_per_s", {bias - 1.96 * sd, bias + 1.96 * sd}}}}};
}

std::string mri_comparison_table(const json& mri) {
  const json& c = mri["comparison"];
  std::string html =
      "<table><tr><th>landmark</th><th>mean flow sim [mL/s]</th><th>mean flow MRI [mL/s]</th>"
      "<th>net volume sim [mL]</th><th>net volume MRI [mL]</th><th>peak flow sim [mL/s]</th>"
      "<th>peak flow MRI [mL/s]</th><th>MRI &minus; sim, mean &plusmn; SD [mL/s]</th>"
      "<th>limits of agreement [mL/s]</th><th>r</th></tr>\n";
  auto limits = [](const json& l) {
    return l.is_array() && l.size() == 2
               ? fmt::format("<td>{:.2f} to {:.2f}</td>", l[0].get<double>(), l[1].get<double>())
               : std::string("<td>-</td>");
  };
  for (const json& name : mri["landmarks"]) {
    const std::string n = name.get<std::string>();
    if (!c["landmarks"].contains(n))
      continue;
    const json& l = c["landmarks"][n];
    html += "<tr><td>" + escape_html(n) + "</td>" + cell(l, "mean_flow_simulation_mL_per_s") +
            cell(l, "mean_flow_mri_mL_per_s") + cell(l, "net_volume_simulation_mL") +
            cell(l, "net_volume_mri_mL") + cell(l, "peak_flow_simulation_mL_per_s") +
            cell(l, "peak_flow_mri_mL_per_s") +
            fmt::format("<td>{:.2f} &plusmn; {:.2f}</td>",
                        l.value("difference_mean_mL_per_s", std::nan("")),
                        l.value("difference_sd_mL_per_s", std::nan(""))) +
            limits(l.value("limits_of_agreement_mL_per_s", json())) +
            cell(l, "correlation", "{:.4f}") + "</tr>\n";
  }
  const json& p = mri["pooled"];
  html += fmt::format("<tr><td>all ({} pairs)</td><td colspan=\"6\"></td>"
                      "<td>{:.2f} &plusmn; {:.2f}</td>",
                      p["pairs"].get<std::size_t>(), p["bias_mL_per_s"].get<double>(),
                      p["sd_mL_per_s"].get<double>()) +
          limits(p["limits_of_agreement_mL_per_s"]) + "<td></td></tr>\n</table>\n";
  if (c.contains("fl_flow_ratio_percent")) {
    html += "<table><tr><th>station</th><th>FL flow ratio sim [%]</th>"
            "<th>FL flow ratio MRI [%]</th><th>MRI &minus; sim [%]</th></tr>\n";
    for (const auto& [k, r] : c["fl_flow_ratio_percent"].items()) {
      const double s = r.value("simulation", std::nan("")), m = r.value("mri", std::nan(""));
      html += fmt::format("<tr><td>{}</td><td>{:.1f}</td><td>{:.1f}</td><td>{:.1f}</td></tr>\n",
                          escape_html(k), s, m, m - s);
    }
    html += "</table>\n";
  }
  if (c.contains("voxels")) {
    const json& v = c["voxels"];
    html += "<table><tr><th>voxel-wise, lumen</th><th>value</th></tr>\n<tr><td>voxel-frames"
            "</td>" +
            cell(v, "lumen_voxel_frames", "{:.0f}") +
            "</tr>\n<tr><td>|v_MRI| &minus; |v_sim|, mean [m/s]</td>" +
            cell(v, "speed_difference_mean_m_per_s", "{:.4f}") +
            "</tr>\n<tr><td>|v_MRI| &minus; |v_sim|, SD [m/s]</td>" +
            cell(v, "speed_difference_sd_m_per_s", "{:.4f}") +
            "</tr>\n<tr><td>angle, mean [deg]</td>" + cell(v, "angle_mean_deg", "{:.1f}") +
            "</tr>\n<tr><td>angle, median [deg]</td>" + cell(v, "angle_median_deg", "{:.1f}") +
            "</tr>\n</table>\n";
  }
  return html;
}

} // namespace tearflow::report
