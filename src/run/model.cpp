#include "run/model.hpp"

#include "core/error.hpp"

namespace tearflow::run {

physics::StepReport Model::advance() {
  physics::StepReport r = step_once(time(), case_.time.step);
  ++step_;
  return r;
}

int Model::take_state(io::Checkpoint&, const RunOptions&) const {
  input_error("--start-from is for flow and fluid-structure cases, not a {} run", series_name());
}

} // namespace tearflow::run
