#pragma once
// `mire compensate --report DIR` (doc/accuracy.md): report.json (what was written, for how many
// poses or grid points, the commands' σ summarised per component, the controller fit's errors)
// and report.html (the result first, the σ of every command by component, each unit on its own
// axis, the poses or points left out, the provenance). Writers: compensate_report_json.cpp,
// compensate_report_html.cpp.
#include <Eigen/Core>

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "mire/mechanism/controller_fit.hpp"
#include "mire/mechanism/parameter_set.hpp"
#include "report_json.hpp"

namespace mire::app {

struct CompensateReportData {
  ReportProvenance provenance;
  std::string mode;                          // "poses" (joint commands), "grid" (pose corrections), "controller-model"
  std::string model;                         // the identified model's name
  std::string output;                        // the file written
  std::vector<std::string> component_names;  // of the commands: joints or pose components
  std::vector<mechanism::Unit> units;        // their SI units
  std::vector<Eigen::VectorXd> sigmas;       // per written row, σ per component (SI)
  std::vector<std::string> left_out;         // unreachable poses, grid points
  bool has_covariance = false;
  std::optional<mechanism::ControllerFit> controller;  // --controller-model
  std::string controller_model;
};

void writeCompensateReportJson(const std::filesystem::path& path, const CompensateReportData& data);
void writeCompensateReportHtml(const std::filesystem::path& path, const CompensateReportData& data);

}  // namespace mire::app
