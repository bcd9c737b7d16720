#pragma once
// The built-in verification drivers, one per file.
#include "verify/verification.hpp"

namespace tearflow::verify {

VerificationResult verify_poiseuille(const VerifyOptions& options);
VerificationResult verify_womersley(const VerifyOptions& options);
// Outlets (rcr.cpp: rcr and rc, splits.cpp).
VerificationResult verify_rcr(const VerifyOptions& options);
VerificationResult verify_rc(const VerifyOptions& options);
VerificationResult verify_splits(const VerifyOptions& options);
// Outlet tuning (tuning.cpp).
VerificationResult verify_tuning(const VerifyOptions& options);
// Solid (solid_statics.cpp, solid_dynamics.cpp).
VerificationResult verify_uniaxial(const VerifyOptions& options);
VerificationResult verify_lame(const VerifyOptions& options);
VerificationResult verify_robin(const VerifyOptions& options);
VerificationResult verify_energy(const VerifyOptions& options);
// Fluid-structure interaction (fsi_inflation.cpp, fsi_pulse.cpp).
VerificationResult verify_inflation(const VerifyOptions& options);
VerificationResult verify_pulse(const VerifyOptions& options);

} // namespace tearflow::verify
