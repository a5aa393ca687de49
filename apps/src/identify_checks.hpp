#pragma once
// Checks of `mire identify`'s inputs and options beyond what the readers check (a pose at a
// time): the pose count limit, rotation vectors beyond 2π, a mixture of weighted and
// unweighted poses, priors too tight to mean anything, Monte-Carlo subset sizes too small to
// identify the free parameters. Messages name the file and pose, or the option (UsageError).
#include "mire/mechanism/identification.hpp"
#include "mire/mechanism/pose.hpp"

#include <filesystem>
#include <string>
#include <vector>

namespace mire::app {

void checkIdentifyPoses(const std::vector<mechanism::PoseObservation>& poses, const std::filesystem::path& poses_file,
                        bool unweighted);

// --prior sigma (SI) below 1e-9 (1 nm, 1 nrad): it would freeze the parameter with σ ≈ 0.
void checkPriorSigma(const std::string& text, double sigma);

// --mc subset sizes from their text ("6,15,71" split by CLI11): integers, each at least large
// enough that size × joints equations exceed `free_parameters`.
std::vector<int> parseSubsetSizes(const std::vector<std::string>& texts, int joints, std::size_t free_parameters,
                                  std::size_t pose_count);

}  // namespace mire::app
