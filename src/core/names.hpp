#pragma once
// Names in messages: the likely meant one for a typo, and lists written as prose.
#include <string>
#include <string_view>
#include <vector>

namespace tearflow {

/// The closest candidate to `word` by edit distance (optimal string alignment, ignoring
/// case), or "" when none is close enough to be a likely typo.
std::string nearest_name(std::string_view word, const std::vector<std::string>& candidates);

/// "a, b or c".
std::string join_names(const std::vector<std::string>& names, std::string_view last = "or");

} // namespace tearflow
