#pragma once
// The parts of `mire demo`'s pipeline (demo.hpp) its stages share: the timed stage, the
// controller the closing stage runs, and the identification parts a mechanism's table entry picks.
#include "mire/datasets/mechanism_image_campaign.hpp"
#include "mire/mechanism/identification.hpp"
#include "mire/mechanism/prediction.hpp"
#include "mire/pipeline/demo.hpp"
#include "mire/pipeline/pose_set.hpp"

#include <array>
#include <chrono>
#include <filesystem>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

namespace mire::pipeline::demo {

// Wall time since construction.
class Stopwatch {
 public:
  double seconds() const { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count(); }

 private:
  std::chrono::steady_clock::time_point start_ = std::chrono::steady_clock::now();
};

// Runs one named stage of the demo, records its wall time and says so on the terminal.
template <class Work>
void timedStage(std::vector<StageTiming>& timings, const std::string& name, const Work& work) {
  const Stopwatch watch;
  work();
  timings.push_back({name, watch.seconds()});
  std::cerr << "mire demo: " << name << " done in " << timings.back().seconds << " s\n";
}

// What the closing stage needs of the identification: the identified prediction model, the
// nominal geometry the uncompensated controller runs, and its name in the stage's title.
struct IdentifiedController {
  mechanism::PredictionModel model;
  Eigen::VectorXd nominal;
  std::string label;
};

// A geometry scored on the campaign (demo_models.cpp): the positioning test's square side [m] (a
// 100 mm square, scaled down with the protocol on a smaller robot), the side errors [mm] of that
// square commanded through the model and reached by the true robot (datasets::positioningTestSides)
// and their RMS; V3 along the recorded lines [m] (paper eq. 29; NaN when the model's FKM fails).
double squareSide(const mechanism::Mechanism& model, const Eigen::VectorXd& geometric);
std::array<double, 4> squareSides(const datasets::TrueRobot& robot, const mechanism::Mechanism& model,
                                  const Eigen::VectorXd& geometric, double side);
double rms(const std::array<double, 4>& values);
double straightnessOf(const mechanism::Mechanism& model, const Eigen::VectorXd& geometric,
                      const std::vector<std::vector<Eigen::VectorXd>>& lines);

// The paper's letters the family's models take (A–D from model 12, E–H from model 31: Table 2).
std::string variantLetters(const std::string& family);

// The paper's study (demo_paper_study.cpp): the variants, the pose-count study, plan and select,
// V1–V3 and the square test, in one stage; the controller of the truth model's default variant.
IdentifiedController paperStudyStage(const DemoOptions& options, const datasets::MechanismImageCampaign& campaign,
                                     DemoResults& results);

// `mire plan` and `mire select` on the paper's study (demo_experiment_design.cpp).
DemoExperimentDesign experimentDesignStage(const DemoOptions& options, const mechanism::MechanismFamily& family,
                                           const mechanism::H4Nominal& nominal,
                                           const std::vector<mechanism::PoseObservation>& poses);

// Each model of the family's selection identified and written as `mire identify` does, one
// stage each (demo_models.cpp); the controller of the model with the truth, when the camera is fixed.
std::optional<IdentifiedController> modelStages(const DemoOptions& options,
                                                const datasets::MechanismImageCampaign& campaign, DemoResults& results);

}  // namespace mire::pipeline::demo
