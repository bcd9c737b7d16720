#pragma once
// The waveform values of a case file (`flow` of an inflow, `pressure` of an outlet): a
// constant, a CSV or SimVascular .flow file, or inline samples; see docs/case-file.md.
#include <filesystem>
#include <optional>
#include <string_view>

#include "bc/waveform.hpp"
#include "io/case_yaml.hpp"

namespace tearflow::io {

/// What a waveform measures: its name in messages, SI unit and the unit converter.
struct Quantity {
  std::string_view name;
  std::string_view si_unit;
  double (*scale)(std::string_view unit, std::string_view where);
};
extern const Quantity kFlow;     ///< m3/s; units::flow_scale
extern const Quantity kPressure; ///< Pa; units::pressure_scale

/// Reads `v`, a number in the unit of the sibling key `sibling_units` (SI if absent), or a
/// mapping with `file` or `times`/`values`, and returns it in SI units. Waveform files are
/// taken from `case_dir`.
bc::Waveform read_case_waveform(const YamlValue& v, const std::optional<YamlValue>& sibling_units,
                                const Quantity& q, const std::filesystem::path& case_dir);

} // namespace tearflow::io
