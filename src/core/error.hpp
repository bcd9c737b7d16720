#pragma once
// Errors that reach the user. Every message names the file, the key or line, and what was
// expected; the command-line program prints it and exits non-zero.
#include <stdexcept>
#include <string>

#include <fmt/format.h>

namespace tearflow {

/// Bad input: a missing file, an unknown key, a wrong unit, an inverted element, ...
class InputError : public std::runtime_error {
public:
  using std::runtime_error::runtime_error;
};

/// A computation that could not go on: NaN, Newton failure, linear solver breakdown.
class SolverError : public std::runtime_error {
public:
  using std::runtime_error::runtime_error;
};

template <typename... Args>
[[noreturn]] void input_error(fmt::format_string<Args...> f, Args&&... args) {
  throw InputError(fmt::format(f, std::forward<Args>(args)...));
}

} // namespace tearflow
