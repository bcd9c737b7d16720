#pragma once
// Unit conversion at the edges: inputs may declare mesh units (mm, cm) and clinical units
// (mmHg, mL/s); everything inside is SI (m, kg, s, Pa).
#include <string_view>

namespace tearflow::units {

constexpr double mmHg = 133.322387415; // Pa
constexpr double mL = 1e-6;            // m^3
constexpr double cm = 1e-2;            // m
constexpr double mm = 1e-3;            // m

/// Metres per one length unit named in a case file ("m", "cm", "mm"); throws InputError
/// naming `where` for anything else.
double length_scale(std::string_view unit, std::string_view where);

/// m^3/s per one flow unit ("m3/s", "mL/s", "cm3/s", "L/min").
double flow_scale(std::string_view unit, std::string_view where);

/// Pa per one pressure unit ("Pa", "mmHg", "dyn/cm2").
double pressure_scale(std::string_view unit, std::string_view where);

enum class Dimension { length, velocity };

/// A command-line quantity, a number with its unit, in SI: "1.5mm", "0.2 cm", "2e-3m" (length);
/// "1.5m/s", "150cm/s" (velocity). InputError naming `where` (the option) otherwise.
double quantity(std::string_view text, std::string_view where, Dimension dimension);

} // namespace tearflow::units
