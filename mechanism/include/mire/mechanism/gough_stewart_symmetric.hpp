#pragma once
// Model `gough-stewart-symmetric` (5): the Gough–Stewart platform as a symmetric controller sees it,
// its 12 joints placed by two radii and two pair half-angles, one leg length at encoder zero:
// rb, beta_b, rp, beta_p, rho0 (doc/mechanisms.md). The hexapod's analogue of the Delta's common
// geometry: what `mire compensate --controller-model` fits when the controller cannot take 42 values.
#include <memory>

#include "mire/mechanism/gough_stewart.hpp"

namespace mire::mechanism {

// The nominal's layout must be the 3-fold symmetric one (pairs about 0/120/240° on the base,
// 60/180/300° on the platform, equal half-angles); std::invalid_argument otherwise.
ParameterSet goughStewartSymmetricParameters(const GoughStewartNominal& nominal = {});
std::unique_ptr<Mechanism> makeGoughStewartSymmetricMechanism(const GoughStewartNominal& nominal = {});

}  // namespace mire::mechanism
