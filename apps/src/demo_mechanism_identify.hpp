#pragma once
// The identification steps of `mire demo --mechanism` (doc/demo-mechanisms.md), shared with the
// end-to-end σ study (benchmarks/bench_chain_mechanisms.cpp, doc/uncertainty.md): the measured
// data read as `mire identify` reads it, the gauged initial model, the fit with the calibration's
// shared term, and the truth expressed in the identification's gauge (scoring only).
#include <filesystem>
#include <optional>
#include <vector>

#include "mire/datasets/mechanism_image_campaign.hpp"
#include "mire/mechanism/gauge.hpp"
#include "mire/mechanism/identification.hpp"
#include "mire/mechanism/identification_covariance.hpp"
#include "mire/mechanism/registry.hpp"

namespace mire::app {

// What every model's identification reads, as `mire identify` reads it: poses.csv with its
// covariance side file and joints.csv, the straight lines (V3), and the shared-term side file
// when it exists.
struct MeasuredData {
  std::vector<mechanism::PoseObservation> poses;
  std::vector<std::vector<Eigen::VectorXd>> lines;
  std::optional<mechanism::SharedPoseTerm> shared;
};
MeasuredData readMeasuredData(const datasets::MechanismImageCampaign& campaign, const std::filesystem::path& poses_csv);

// The initial model as `mire identify` builds it: the mounting from the data (motion type),
// then the gauge by pivoted QR.
struct GaugedModel {
  mechanism::IdentificationModel model;
  mechanism::GaugeAnalysis gauge;
};
GaugedModel initialModel(const mechanism::RegisteredModel& registered,
                         const std::vector<mechanism::PoseObservation>& poses);

// Where the shared term's refits hold the gauge parameters: `HeldAtMainFit`, at the main fit's
// values (as `mire identify` does, apps/src/cmd_identify.cpp), so the refits measure the
// estimate's change within one gauge — the change the truth in the gauge is scored against;
// `Reinitialised`, at the values the refit's own initialisation gives them on the shifted poses
// (what `mire identify` did before it held the gauge: the gauge moved with the shifted poses; kept
// for the study, doc/studies/2026-11-24-chain-study-delta-gough-stewart.md).
enum class RefitGauge { HeldAtMainFit, Reinitialised };

// The shared calibration term added to `result` (a fit of `initial` on data.poses) by refits on
// shifted poses, each initialised as the main fit, with the main fit's gauge parameters held
// (doc/uncertainty.md). Nothing when data.shared is empty.
void addSharedTermLikeTheCommand(const mechanism::RegisteredModel& registered, const GaugedModel& initial,
                                 const MeasuredData& data, mechanism::IdentificationResult& result,
                                 RefitGauge gauge = RefitGauge::HeldAtMainFit);

// The weighted fit, then addSharedTermLikeTheCommand().
mechanism::IdentificationResult identifyLikeTheCommand(const mechanism::RegisteredModel& registered,
                                                       const GaugedModel& initial, const MeasuredData& data);

// The truth in the identification's gauge (scoring only): the true geometry's exact-model
// observations at the commanded poses (no defect, no noise), identified from the same initial
// model with the same parameters held; the fit is exact, and lands where the gauge puts it.
mechanism::ParameterSet truthInGauge(const datasets::MechanismImageCampaign& campaign, const GaugedModel& initial,
                                     const std::vector<mechanism::PoseObservation>& measured);

}  // namespace mire::app
