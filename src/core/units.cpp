#include "core/units.hpp"

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

} // namespace tearflow::units
