#pragma once
// The built-in verification drivers, one per file.
#include "verify/verification.hpp"

namespace tearflow::verify {

VerificationResult verify_poiseuille(const VerifyOptions& options);
VerificationResult verify_womersley(const VerifyOptions& options);

} // namespace tearflow::verify
