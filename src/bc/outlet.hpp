#pragma once
// The outlet laws: one closed set. An outlet closes the domain with the traction
// h = -P n + beta rho (u.n)_- u (Q the outward flux) and a law relating P to Q; whatever its
// memory, within one step it is P_af = p0 + r Q_af (outlet_step.hpp), so the 3D problem needs
// that one mechanism. Each law is a type in its own header:
//   memoryless (MemorylessOutlet): coupled() (dP/dQ != 0), step_law(clock), zero_d() (its
//     branch of the 0D outlet network: start-up and tuning; none if it sets the pressure),
//     describe() (the run's fingerprint);
//   with a 0D state (OutletWithState): those, with step_law(state, Q_n, clock), and a State,
//     initial(), commit(state, Q_n, Q_n+1, dt), start(P_d of the 0D periodic state) (none when
//     the case gave the initial state), distal_pressure(state) (faces.csv), and the checkpoint
//     record: record_size, record(state), restore(record).
// Adding a law: its header (outlet_<law>.hpp), its alternative in OutletLaw below, the case
// reader's table (io/case_conditions.cpp) and docs/case-file.md.
#include <array>
#include <concepts>
#include <cstddef>
#include <optional>
#include <span>
#include <string>
#include <variant>
#include <vector>

#include "bc/outlet_pressure.hpp"
#include "bc/outlet_rc.hpp"
#include "bc/outlet_rcr.hpp"
#include "bc/outlet_resistance.hpp"
#include "bc/outlet_step.hpp"
#include "bc/windkessel.hpp"

namespace tearflow::bc {

template <class L>
concept MemorylessOutlet = requires(const L& l, const StepClock& c) {
  { l.coupled() } -> std::same_as<bool>;
  { l.step_law(c) } -> std::same_as<StepLaw>;
  { l.zero_d() } -> std::same_as<std::optional<WindkesselRCR>>;
  { l.describe() } -> std::same_as<std::string>;
};

template <class L>
concept OutletWithState = requires(const L& l, const typename L::State& s, const StepClock& c,
                                   double x, const std::array<double, L::record_size>& r) {
  { l.coupled() } -> std::same_as<bool>;
  { l.initial() } -> std::same_as<typename L::State>;
  { l.step_law(s, x, c) } -> std::same_as<StepLaw>;
  { l.commit(s, x, x, x) } -> std::same_as<typename L::State>;
  { l.zero_d() } -> std::same_as<std::optional<WindkesselRCR>>;
  { l.start(x) } -> std::same_as<std::optional<typename L::State>>;
  { l.distal_pressure(s) } -> std::same_as<double>;
  { l.record(s) } -> std::same_as<std::array<double, L::record_size>>;
  { l.restore(r) } -> std::same_as<typename L::State>;
  { l.describe() } -> std::same_as<std::string>;
};

/// The laws a case can name (the reader's table maps each to its `type:`).
using OutletLaw = std::variant<PressureOutlet, ResistanceOutlet, RcrOutlet, RcOutlet>;

namespace detail {
template <class L> struct NoState {}; // one distinct type per memoryless law
template <class L> struct StateOf {
  static_assert(MemorylessOutlet<L>, "an outlet law lacks part of bc/outlet.hpp's interface");
  using type = NoState<L>;
};
template <OutletWithState L> struct StateOf<L> { using type = typename L::State; };
template <class V> struct StatesOf;
template <class... L> struct StatesOf<std::variant<L...>> {
  using type = std::variant<typename StateOf<L>::type...>;
};
} // namespace detail

/// An outlet's 0D state at t_n: the alternative of its law's state.
using OutletState = detail::StatesOf<OutletLaw>::type;

bool coupled(const OutletLaw& law); ///< dP/dQ != 0: the Jacobian needs the outlet's term
OutletState initial_state(const OutletLaw& law);
/// P_af = p0 + r Q_af for the step `clock` from the state and flux at t_n.
StepLaw step_law(const OutletLaw& law, const OutletState& state, double q_n,
                 const StepClock& clock);
/// The state at t_{n+1} from the fluxes at t_n and t_{n+1}.
OutletState commit(const OutletLaw& law, const OutletState& state, double q_n, double q_next,
                   double dt);
/// The law's branch in the 0D network of the outlets; none when it sets the pressure.
std::optional<WindkesselRCR> zero_d_branch(const OutletLaw& law);
/// The state a run starts from given its branch's P_d in the 0D periodic state; none when
/// the law has no state or the case gave it.
std::optional<OutletState> start_state(const OutletLaw& law, double distal_pressure);
/// The capacitor's pressure of a law with one [Pa] (faces.csv's distal_pressure_Pa).
std::optional<double> distal_pressure(const OutletLaw& law, const OutletState& state);
std::size_t record_size(const OutletLaw& law); ///< numbers of the state in a checkpoint
void append_record(const OutletLaw& law, const OutletState& state, std::vector<double>& out);
/// The state from record_size(law) numbers.
OutletState restore(const OutletLaw& law, std::span<const double> record);
std::string describe(const OutletLaw& law);
/// True when a and b are the same law (alternative), parameters aside.
bool same_law(const OutletLaw& a, const OutletLaw& b);

} // namespace tearflow::bc
