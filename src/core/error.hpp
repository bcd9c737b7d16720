#pragma once
// Errors that reach the user. Every message names the file, the key or line, and what was
// expected; the command-line program prints it and exits non-zero.
#include <stdexcept>
#include <string>

#include <fmt/format.h>

namespace tearflow {

/// Bad input: a missing file, an unknown key, a wrong unit, an inverted element, ...
/// `collective`: every rank checked the same input and threw it (see SolverError).
class InputError : public std::runtime_error {
public:
  explicit InputError(const std::string& what, bool collective = false)
      : std::runtime_error(what), collective(collective) {}
  bool collective;
};

/// A computation that could not go on: NaN, Newton failure, linear solver breakdown.
/// `collective`: every rank threw it at the same point (a converged reason or a norm that
/// all ranks share), so the ranks can stop together and one of them report it; otherwise
/// the others may be waiting in a collective call and the program must abort them.
class SolverError : public std::runtime_error {
public:
  explicit SolverError(const std::string& what, bool collective = false)
      : std::runtime_error(what), collective(collective) {}
  bool collective;
};

template <typename... Args>
[[noreturn]] void input_error(fmt::format_string<Args...> f, Args&&... args) {
  throw InputError(fmt::format(f, std::forward<Args>(args)...));
}

/// input_error for a check every rank makes alike, before any rank can be left waiting.
template <typename... Args>
[[noreturn]] void collective_input_error(fmt::format_string<Args...> f, Args&&... args) {
  throw InputError(fmt::format(f, std::forward<Args>(args)...), true);
}

} // namespace tearflow
