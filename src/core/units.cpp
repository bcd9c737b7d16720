#include "core/units.hpp"

#include <regex>
#include <string>

#include "core/error.hpp"

namespace tearflow::units {

double length_scale(std::string_view unit, std::string_view where) {
  if (unit == "m")
    return 1.0;
  if (unit == "cm")
    return cm;
  if (unit == "mm")
    return mm;
  input_error("{}: unknown length unit '{}' (expected m, cm or mm)", where, unit);
}

double flow_scale(std::string_view unit, std::string_view where) {
  if (unit == "m3/s")
    return 1.0;
  if (unit == "mL/s" || unit == "ml/s" || unit == "cm3/s")
    return mL;
  if (unit == "L/min" || unit == "l/min")
    return 1e-3 / 60.0;
  input_error("{}: unknown flow unit '{}' (expected m3/s, mL/s, cm3/s or L/min)", where, unit);
}

double pressure_scale(std::string_view unit, std::string_view where) {
  if (unit == "Pa")
    return 1.0;
  if (unit == "mmHg")
    return mmHg;
  if (unit == "dyn/cm2")
    return 0.1;
  input_error("{}: unknown pressure unit '{}' (expected Pa, mmHg or dyn/cm2)", where, unit);
}

double quantity(std::string_view text, std::string_view where, Dimension dimension) {
  static const std::regex re(R"(\s*([-+0-9.eE]+)\s*([a-zA-Z/]*)\s*)");
  const bool velocity = dimension == Dimension::velocity;
  const std::string s(text);
  std::smatch m;
  if (!std::regex_match(s, m, re))
    input_error("{} '{}': a number with a unit is expected (e.g. {})", where, text,
                velocity ? "1.5m/s" : "1.5mm");
  double value = 0;
  std::size_t used = 0;
  try {
    value = std::stod(m[1], &used);
  } catch (...) {
    input_error("{} '{}': not a number", where, text);
  }
  if (used != static_cast<std::size_t>(m[1].length())) // "1.2.3mm" is not 1.2 mm
    input_error("{} '{}': not a number", where, text);
  std::string unit = m[2];
  if (velocity) {
    if (unit.size() < 2 || unit.substr(unit.size() - 2) != "/s")
      input_error("{} '{}': a velocity in m/s, cm/s or mm/s is expected", where, text);
    unit = unit.substr(0, unit.size() - 2);
  }
  return value * length_scale(unit, where);
}

} // namespace tearflow::units
