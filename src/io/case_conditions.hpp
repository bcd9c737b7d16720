#pragma once
// A case file's boundary_conditions, read straight into bc::BoundaryCondition. Each outlet
// law of bc/outlet.hpp is one row of the table in case_conditions.cpp: its `type:`, its keys
// and its reader.
#include <filesystem>
#include <vector>

#include "bc/boundary_condition.hpp"
#include "io/case_yaml.hpp"

namespace tearflow::io {

/// A periodic waveform read from the case, where it was given (the period's check).
struct GivenWaveform {
  YamlValue where;
  bc::Waveform waveform;
};

/// Reads the list `v` (files taken from `case_dir`); every periodic waveform read is appended
/// to `periodic` in document order.
std::vector<bc::BoundaryCondition> read_boundary_conditions(const YamlValue& v,
                                                            const std::filesystem::path& case_dir,
                                                            std::vector<GivenWaveform>& periodic);

} // namespace tearflow::io
