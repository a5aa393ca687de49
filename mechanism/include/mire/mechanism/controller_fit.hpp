#pragma once
// The parameters of the model a controller runs (often a simpler one than the identified: `delta`
// from a `delta-legs` identification, h4-12 from h4-31, a hexapod without encoder gains), fitted so
// that the identified robot best follows the controller's commands over a workspace
// (doc/accuracy.md, "Controller model"): Ceres least squares on the joints,
//   min over ξc, F of Σ_X ‖IKM_controller(F·X, ξc) − IKM_identified(X)‖²,
// F the controller's base frame from the identified one (the models need not share a frame: the
// H4's model 31 is written in another base frame than model 12), then the predicted residual:
// where the identified robot goes with the controller's commands,
// FKM_identified(IKM_controller(F·X, ξc)) − X, which the controller model cannot correct.
#include <Eigen/Core>

#include <limits>
#include <string>
#include <vector>

#include "mire/mechanism/prediction.hpp"
#include "mire/mechanism/registry.hpp"

namespace mire::mechanism {

struct ControllerFit {
  ParameterSet parameters;  // the controller model's, its free ones fitted
  // F: a pose X in the identified base frame is F·X in the controller's (command F·X).
  Eigen::Isometry3d frame = Eigen::Isometry3d::Identity();
  bool converged = false;
  double rms_joint_residual = 0.0;  // [rad or m]
  // Position error of the identified robot following the fitted controller's commands [m].
  double rms_position_error = 0.0, max_position_error = 0.0;
  Eigen::VectorXd worst_pose;  // where the largest error is
  int poses = 0;
  // The same error for the robot as the identification knows it (doc/accuracy.md, "Controller
  // model"): robots drawn from the identified geometry's covariance follow the fitted controller's
  // commands; the RMS position error of each draw, frame-free (rigidly aligned onto the commanded
  // positions, as a robot whose base frame is not known exactly is scored), less the part of the
  // identification's noise the draws count twice (measured by refitting the controller to some of
  // them), gives a mean and a spread. The mean is what to expect on the robot (it adds the
  // identification's own error to what the controller model cannot correct); the spread its 1σ.
  // NaN without a covariance.
  double expected_rms_position_error = std::numeric_limits<double>::quiet_NaN();
  double sigma_rms_position_error = std::numeric_limits<double>::quiet_NaN();
  int draws = 0;
};

// The pose a controller running `controller` is commanded for X: F·X in its own pose components.
Eigen::VectorXd controllerCommand(const Mechanism& controller, const Eigen::Isometry3d& frame,
                                  const Eigen::Isometry3d& pose);

// `workspace`: poses (the controller's pose components) in the identified base frame. Throws
// std::invalid_argument when the two models differ in joints or pose components, or when no pose
// is reachable by both.
ControllerFit fitControllerModel(const PredictionModel& identified, const RegisteredModel& controller,
                                 const std::vector<Eigen::VectorXd>& workspace);

}  // namespace mire::mechanism
