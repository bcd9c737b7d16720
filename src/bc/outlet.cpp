#include "bc/outlet.hpp"

#include <algorithm>
#include <stdexcept>

namespace tearflow::bc {

namespace {

/// f(law, its state) for the law's alternative.
template <class F> decltype(auto) with_state(const OutletLaw& law, const OutletState& s, F&& f) {
  return std::visit(
      [&](const auto& l) -> decltype(auto) {
        using L = std::decay_t<decltype(l)>;
        return f(l, std::get<typename detail::StateOf<L>::type>(s));
      },
      law);
}

template <class L> constexpr bool has_state = OutletWithState<L>;

} // namespace

bool coupled(const OutletLaw& law) {
  return std::visit([](const auto& l) { return l.coupled(); }, law);
}

OutletState initial_state(const OutletLaw& law) {
  return std::visit(
      [](const auto& l) -> OutletState {
        using L = std::decay_t<decltype(l)>;
        if constexpr (has_state<L>)
          return l.initial();
        else
          return detail::NoState<L>{};
      },
      law);
}

StepLaw step_law(const OutletLaw& law, const OutletState& state, double q_n,
                 const StepClock& clock) {
  return with_state(law, state, [&](const auto& l, const auto& s) {
    if constexpr (has_state<std::decay_t<decltype(l)>>)
      return l.step_law(s, q_n, clock);
    else
      return l.step_law(clock);
  });
}

OutletState commit(const OutletLaw& law, const OutletState& state, double q_n, double q_next,
                   double dt) {
  return with_state(law, state, [&](const auto& l, const auto& s) -> OutletState {
    if constexpr (has_state<std::decay_t<decltype(l)>>)
      return l.commit(s, q_n, q_next, dt);
    else
      return s;
  });
}

std::optional<WindkesselRCR> zero_d_branch(const OutletLaw& law) {
  return std::visit([](const auto& l) { return l.zero_d(); }, law);
}

std::optional<OutletState> start_state(const OutletLaw& law, double distal_pressure) {
  return std::visit(
      [&](const auto& l) -> std::optional<OutletState> {
        if constexpr (has_state<std::decay_t<decltype(l)>>) {
          if (auto s = l.start(distal_pressure))
            return OutletState{*s};
        }
        return std::nullopt;
      },
      law);
}

std::optional<double> distal_pressure(const OutletLaw& law, const OutletState& state) {
  return with_state(law, state, [](const auto& l, const auto& s) -> std::optional<double> {
    if constexpr (has_state<std::decay_t<decltype(l)>>)
      return l.distal_pressure(s);
    else
      return std::nullopt;
  });
}

std::size_t record_size(const OutletLaw& law) {
  return std::visit(
      [](const auto& l) -> std::size_t {
        using L = std::decay_t<decltype(l)>;
        if constexpr (has_state<L>)
          return L::record_size;
        else
          return 0;
      },
      law);
}

void append_record(const OutletLaw& law, const OutletState& state, std::vector<double>& out) {
  with_state(law, state, [&](const auto& l, const auto& s) {
    if constexpr (has_state<std::decay_t<decltype(l)>>) {
      const auto r = l.record(s);
      out.insert(out.end(), r.begin(), r.end());
    }
  });
}

OutletState restore(const OutletLaw& law, std::span<const double> record) {
  if (record.size() != record_size(law))
    throw std::logic_error("bc::restore: a record of the wrong size");
  return std::visit(
      [&](const auto& l) -> OutletState {
        using L = std::decay_t<decltype(l)>;
        if constexpr (has_state<L>) {
          std::array<double, L::record_size> r{};
          std::copy(record.begin(), record.end(), r.begin());
          return l.restore(r);
        } else {
          return detail::NoState<L>{};
        }
      },
      law);
}

std::string describe(const OutletLaw& law) {
  return std::visit([](const auto& l) { return l.describe(); }, law);
}

bool same_law(const OutletLaw& a, const OutletLaw& b) {
  return a.index() == b.index();
}

} // namespace tearflow::bc
