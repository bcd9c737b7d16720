#include "analysis/measured_data.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>

#include <fmt/format.h>

#include "core/error.hpp"
#include "core/units.hpp"

namespace tearflow::analysis {

namespace {

/// One measurement table: a time column and one column per landmark, converted to SI.
struct Table {
  std::filesystem::path file;
  std::vector<double> time;
  std::map<std::string, std::vector<double>> columns; // landmark -> values
  std::vector<std::string> order;                     // landmarks in column order
};

struct Quantity {
  const char* file;
  std::vector<std::pair<const char*, double>> units; // column suffix -> factor to SI
};

const Quantity kFlow{"flow.csv", {{"_mL_per_s", units::mL}, {"_m3_per_s", 1.0}}};
const Quantity kArea{"area.csv", {{"_mm2", units::mm* units::mm}, {"_m2", 1.0}}};
const Quantity kPressure{"pressure.csv", {{"_mmHg", units::mmHg}, {"_Pa", 1.0}}};

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> cells;
  std::string cell;
  for (std::istringstream in(line); std::getline(in, cell, ',');) {
    while (!cell.empty() && (cell.back() == '\r' || cell.back() == ' '))
      cell.pop_back();
    while (!cell.empty() && cell.front() == ' ')
      cell.erase(cell.begin());
    cells.push_back(cell);
  }
  return cells;
}

std::optional<Table> read_table(const std::filesystem::path& dir, const Quantity& q) {
  const std::filesystem::path file = dir / q.file;
  std::ifstream in(file);
  if (!in)
    return std::nullopt;
  Table t{file, {}, {}, {}};
  std::string line;
  if (!std::getline(in, line))
    input_error("'{}': empty (a header 'time_s,<landmark>_<unit>,...' is expected)", file.string());
  const std::vector<std::string> header = split(line);
  if (header.empty() || header.front() != "time_s")
    input_error("'{}' line 1: the first column must be 'time_s'", file.string());
  std::vector<double> factor;
  for (std::size_t c = 1; c < header.size(); ++c) {
    const std::string& name = header[c];
    std::string landmark;
    for (const auto& [suffix, f] : q.units) {
      const std::string s(suffix);
      if (name.size() > s.size() && name.ends_with(s)) {
        landmark = name.substr(0, name.size() - s.size());
        factor.push_back(f);
        break;
      }
    }
    if (landmark.empty()) {
      std::string expected;
      for (const auto& [suffix, f] : q.units)
        expected += fmt::format("{}<landmark>{}", expected.empty() ? "" : " or ", suffix);
      input_error("'{}' line 1, column {} '{}': expected {}", file.string(), c + 1, name, expected);
    }
    if (t.columns.count(landmark))
      input_error("'{}' line 1: landmark '{}' is given twice", file.string(), landmark);
    t.columns[landmark] = {};
    t.order.push_back(landmark);
  }
  for (int row = 2; std::getline(in, line); ++row) {
    if (line.find_first_not_of(" \r") == std::string::npos)
      continue;
    const std::vector<std::string> cells = split(line);
    if (cells.size() != header.size())
      input_error("'{}' line {}: {} columns, the header has {}", file.string(), row, cells.size(),
                  header.size());
    std::vector<double> v;
    for (std::size_t c = 0; c < cells.size(); ++c) {
      std::size_t used = 0;
      double x = 0;
      try {
        x = std::stod(cells[c], &used);
      } catch (const std::exception&) {
        used = 0;
      }
      if (used == 0 || used != cells[c].size() || !std::isfinite(x))
        input_error("'{}' line {}, column '{}': '{}' is not a number", file.string(), row,
                    header[c], cells[c]);
      v.push_back(x);
    }
    if (!t.time.empty() && v[0] <= t.time.back())
      input_error("'{}' line {}: time {} s does not increase (previous {} s)", file.string(), row,
                  v[0], t.time.back());
    t.time.push_back(v[0]);
    for (std::size_t c = 1; c < v.size(); ++c)
      t.columns[t.order[c - 1]].push_back(v[c] * factor[c - 1]);
  }
  if (t.time.size() < 2)
    input_error("'{}': {} data row(s); the analysis needs at least two", file.string(),
                t.time.size());
  return t;
}

geometry::Landmark landmark_named(const std::string& name) {
  geometry::Landmark l;
  l.name = name;
  if (station_of(l) > 0)
    l.lumen = name.substr(0, 2); // "TL" or "FL"
  return l;
}

} // namespace

bool is_measurement_folder(const std::filesystem::path& dir) {
  for (const Quantity* q : {&kFlow, &kArea, &kPressure})
    if (std::filesystem::exists(dir / q->file))
      return true;
  return false;
}

Analysis read_measured(const std::filesystem::path& dir) {
  const std::optional<Table> flow = read_table(dir, kFlow), area = read_table(dir, kArea),
                             pressure = read_table(dir, kPressure);
  const Table* base = flow ? &*flow : area ? &*area : pressure ? &*pressure : nullptr;
  if (base == nullptr)
    input_error("'{}' holds no measurement table (flow.csv, area.csv or pressure.csv; "
                "docs/analysis.md) and no simulation output (flow.pvd)",
                dir.string());
  Analysis a;
  a.source = "measured";
  a.frames = fmt::format("measured ({})", base->file.filename().string());
  a.time = base->time;
  // The landmarks in the order the tables name them, flow's first.
  std::vector<std::string> names;
  for (const std::optional<Table>* t : {&flow, &area, &pressure})
    if (*t)
      for (const std::string& n : (*t)->order)
        if (std::find(names.begin(), names.end(), n) == names.end())
          names.push_back(n);
  const double nan = std::nan("");
  auto value = [&](const std::optional<Table>& t, const std::string& name, double at) {
    if (!t || !t->columns.count(name))
      return nan;
    return interpolate(t->time, t->columns.at(name), at);
  };
  for (const std::string& name : names) {
    LandmarkSeries s{landmark_named(name), {}};
    for (double at : a.time) {
      SectionValues v;
      v.flow = value(flow, name, at);
      v.area = value(area, name, at);
      v.pressure = value(pressure, name, at);
      v.max_velocity = nan; // not in the tables
      v.wall_displacement = nan;
      s.samples.push_back(v);
    }
    a.series.push_back(std::move(s));
  }
  mark_cycle_events(a);
  return a;
}

} // namespace tearflow::analysis
