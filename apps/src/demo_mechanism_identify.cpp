// The identification steps of `mire demo --mechanism` (demo_mechanism_identify.hpp).
#include "demo_mechanism_identify.hpp"

#include "mire/mechanism/io.hpp"
#include "mire/mechanism/translating_target.hpp"
#include "mire/metrology/poses_csv.hpp"

#include <algorithm>

namespace mire::app {
namespace fs = std::filesystem;
namespace mech = mire::mechanism;

MeasuredData readMeasuredData(const datasets::MechanismImageCampaign& campaign, const fs::path& poses_csv) {
  const std::vector<std::string> columns = campaign.robot.mechanism().jointColumnNames();
  MeasuredData data;
  data.poses =
      mech::readObservations(poses_csv, campaign.joints_file(), metrology::covarianceSidePath(poses_csv), columns).poses;
  for (auto& line : mech::readLinesCsv(campaign.lines_file(), columns)) data.lines.push_back(std::move(line.joints));
  const fs::path shared_path = mech::sharedTermPath(poses_csv);
  if (fs::exists(shared_path)) data.shared = mech::readSharedTermCsv(shared_path);
  return data;
}

GaugedModel initialModel(const mech::RegisteredModel& registered, const std::vector<mech::PoseObservation>& poses) {
  GaugedModel initial;
  initial.model = mech::makeInitialModel(registered.mechanism, registered.nominal, poses, registered.external_form);
  initial.gauge = mech::fixGauge(initial.model, poses);
  return initial;
}

void addSharedTermLikeTheCommand(const mech::RegisteredModel& registered, const GaugedModel& initial,
                                 const MeasuredData& data, mech::IdentificationResult& result, RefitGauge gauge) {
  if (!data.shared) return;
  mech::IdentificationOptions quiet;
  quiet.compute_identifiability = false;
  mech::addSharedTermCovariance(result, data.poses, *data.shared, [&](const std::vector<mech::PoseObservation>& shifted) {
    mech::IdentificationModel start =
        mech::makeInitialModel(registered.mechanism, registered.nominal, shifted, registered.external_form);
    if (gauge == RefitGauge::HeldAtMainFit)
      for (const std::string& name : initial.gauge.gauge)
        start.parameters.setValue(name, initial.model.parameters.value(name));
    start.parameters.fix(initial.gauge.gauge);
    mech::IdentificationResult refit = mech::identify(start, shifted, quiet);
    mech::alignTranslatingTarget(*refit.model.mechanism, refit.model.external, refit.model.parameters, shifted);
    return refit;
  });
}

mech::IdentificationResult identifyLikeTheCommand(const mech::RegisteredModel& registered, const GaugedModel& initial,
                                                  const MeasuredData& data) {
  mech::IdentificationResult result = mech::identify(initial.model, data.poses);
  addSharedTermLikeTheCommand(registered, initial, data, result);
  return result;
}

mech::ParameterSet truthInGauge(const datasets::MechanismImageCampaign& campaign, const GaugedModel& initial,
                                const std::vector<mech::PoseObservation>& measured) {
  const mech::Mechanism& mechanism = campaign.robot.mechanism();
  std::vector<mech::PoseObservation> exact;
  for (std::size_t i = 0; i < campaign.commanded.size(); ++i) {
    const Eigen::Isometry3d bTe = mechanism.poseToTransform(campaign.commanded[i]);
    mech::PoseObservation pose;
    pose.id = campaign.pose_ids[i];
    pose.joints = mechanism.inverseKinematics(campaign.robot.geometry.values(), bTe).joints;
    pose.cTm = mech::toPoseVector(campaign.bTc.inverse() * bTe * campaign.mTe.inverse());
    const auto same = std::find_if(measured.begin(), measured.end(), [&](const auto& p) { return p.id == pose.id; });
    if (same != measured.end()) pose.covariance = same->covariance;
    exact.push_back(pose);
  }
  mech::IdentificationOptions options;
  options.compute_identifiability = false;
  mech::IdentificationResult truth = mech::identify(initial.model, exact, options);
  mech::alignTranslatingTarget(truth, exact);
  return truth.model.parameters;
}

}  // namespace mire::app
