#pragma once
// report.json beside every report (doc/report-json.md): the results and full covariances of a
// command, machine-readable, written with nlohmann::json. Deterministic: the same inputs and
// options give a byte-identical file (no date, no timing, keys in a fixed order). Numbers are
// the shortest decimal that reads back to the same double; JSON has no NaN/Inf, so a
// non-finite value is written as null with its reason in the sibling key "<key>_null_reason",
// and a non-finite number that reaches the file any other way fails the command (nothing
// written).
#include <Eigen/Core>
#include <nlohmann/json_fwd.hpp>

#include <filesystem>
#include <string>
#include <vector>

#include "mire/calibration/calibrate.hpp"
#include "mire/calibration/model_check.hpp"
#include "mire/mechanism/experiment_design.hpp"
#include "mire/mechanism/model_selection.hpp"
#include "mire/pipeline/camera_plan.hpp"
#include "output_paths.hpp"

// Declared only: CLI11 costs seconds of compile time in every file that includes this one
// (doc/install.md, "Build time"). The demo's report.json is declared in demo.hpp.
namespace CLI {
class App;
}

namespace mire::app {

using Json = nlohmann::ordered_json;

// Where a report came from: mire's version, the command line as parsed, the files read and
// written (paths as given).
struct ReportProvenance {
  std::vector<std::string> command_line;
  std::vector<PathArgument> inputs;
  std::vector<PathArgument> outputs;
};

// "mire <command> --option value ..." as CLI11 parsed it (options in their declaration order,
// each given option once with all its values; flags without value).
std::vector<std::string> commandLineOf(const CLI::App& command);

// The document every report.json starts with: {"format", "report", "provenance"}.
Json reportHeader(const std::string& report, const ReportProvenance& provenance);

// obj[key] = value, or null and obj[key + "_null_reason"] = reason when value is not finite.
void setNumber(Json& object, const std::string& key, double value, const std::string& reason);
// An array of numbers; throws std::logic_error on a non-finite entry.
Json numberArray(const Eigen::VectorXd& values);
Json numberArray(const std::vector<double>& values);
// Row-major nested arrays; throws std::logic_error on a non-finite entry.
Json matrixJson(const Eigen::MatrixXd& matrix);
// {"names", "units", "matrix"}: a covariance, symmetrised ((C + Cᵀ)/2: the solvers' matrices
// differ from symmetric by rounding), its diagonal unchanged.
Json covarianceJson(const std::vector<std::string>& names, const std::vector<std::string>& units,
                    const Eigen::MatrixXd& covariance);

// Checks that no number is non-finite, then writes `document` (2-space indent, final newline)
// atomically. Throws std::logic_error naming the key path of a non-finite number.
void writeReportJson(const std::filesystem::path& path, const Json& document);

// One writer per report (identify's is in identify_report.hpp), each in <command>_report_json.cpp.
void writeCalibrateReportJson(const std::filesystem::path& path, const ReportProvenance& provenance,
                              const calibration::CalibrationResult& result,
                              const calibration::ProjectionUncertaintySummary& uncertainty,
                              const calibration::ModelCheck& check);

struct PlanReportSettings {
  ReportProvenance provenance;
  std::string model;
  int candidates = 0;
  unsigned seed = 0;
  std::string mounting = "camera-fixed";  // or camera-on-effector
};
void writePlanReportJson(const std::filesystem::path& path, const PlanReportSettings& settings,
                         const mechanism::CandidateInformation& info, const mechanism::DesignReport& report);
// The same with the `camera` section (null: none; `mire plan --camera`).
void writePlanReportJson(const std::filesystem::path& path, const PlanReportSettings& settings,
                         const mechanism::CandidateInformation& info, const mechanism::DesignReport& report,
                         const pipeline::CameraPlanSummary* camera);

// `joint_unit`: the unit of the scores (rad or m).
void writeSelectReportJson(const std::filesystem::path& path, const ReportProvenance& provenance,
                           const mechanism::SelectionResult& result, mechanism::Unit joint_unit, int folds,
                           unsigned seed);

}  // namespace mire::app
