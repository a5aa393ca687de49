#pragma once
// Model `gough-stewart-gains` (48): the 42 parameters of `gough-stewart` plus one encoder
// scale per leg, s1 … s6 (leg metres per metre of reading, nominal 1): ρ_i = ρ0_i + s_i·q̄_i.
// A leg driven by a screw reads its length through the screw lead; a lead off by δ (the
// screw's accuracy class, the motor's steps per turn) makes every reading off by δ·q̄_i, which
// the 42-parameter model cannot represent (doc/studies/2026-11-23-mechanisms-sigma-and-defects.md).
#include <memory>

#include "mire/mechanism/gough_stewart.hpp"
#include "mire/mechanism/mechanism.hpp"
#include "mire/mechanism/parameter_set.hpp"

namespace mire::mechanism {

// goughStewartParameters(nominal) followed by s1 … s6 = 1 (dimensionless, free).
ParameterSet goughStewartGainsParameters(const GoughStewartNominal& nominal = {});
std::unique_ptr<Mechanism> makeGoughStewartGainsMechanism(const GoughStewartNominal& nominal = {});

}  // namespace mire::mechanism
