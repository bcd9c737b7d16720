#pragma once
#include "io/case.hpp"

namespace tearflow::run {

/// The built-in default case that `tearflow run` runs without a case file: pulsatile flow
/// of blood in a 2 cm pipe with an aortic-like inflow waveform and a resistance outlet, one
/// cardiac cycle. (Later replaced by the parametric aortic dissection.)
io::Case default_case();

} // namespace tearflow::run
