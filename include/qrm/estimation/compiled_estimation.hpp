// qrm/estimation/compiled_estimation.hpp: include in exactly one source file of a program whose
// other source files are compiled with QRM_COMPILED_ESTIMATION defined. This file then compiles
// estimate_amplitude (all seven estimators) for analytic_oracle and any_oracle once, and the
// others call it instead of compiling their own copies (README, "Compiling the backends once":
// the same scheme as QRM_COMPILED_BACKENDS). Other oracle types, and estimators called by name,
// are compiled where they are used.
#pragma once

#include "estimator.hpp"

namespace qrm {
QRM_DETAIL_ESTIMATOR_INSTANCES(template)
}  // namespace qrm
