#pragma once
// The report of `mire identify`: report.html, report.json and Markdown linking the figures as SVG
// files (residuals per pose and leg with their σ band, singular values, Monte-Carlo parameter
// spreads beside the analytic σ).
#include <filesystem>
#include <string>
#include <vector>

#include "mire/mechanism/evaluation.hpp"
#include "mire/mechanism/identification.hpp"
#include "report_html.hpp"
#include "report_json.hpp"

namespace mire::app {

struct IdentifyReportData {
  std::string command_line;
  std::string model_label;                                                 // e.g. "h4-12, variant D"
  std::vector<mechanism::PoseResidual> residuals_before, residuals_after;  // q̄ − f per pose
  mechanism::IdentificationResult result;
  mechanism::ParameterSet initial;               // values before identification (nominal + estimated external)
  double v3_before_m = -1.0, v3_after_m = -1.0;  // < 0: no lines given
  const mechanism::MonteCarloStudy* study = nullptr;
  std::string summary_text;  // the console summary, repeated in the report
  std::string gauge_text;    // the gauge analysis in full, with every unidentifiable direction
  // report.json (doc/report-json.md): provenance, the model's name and variant, and the pose
  // covariance file the fit was weighted by (empty: none).
  ReportProvenance provenance;
  std::string model_name, variant;
  std::string pose_covariance_file;
};

// Writes DIR/report.md, DIR/residuals.svg, DIR/residuals_before.svg, DIR/singular_values.svg and,
// with a study, DIR/monte_carlo_spread.svg, DIR/report.html and DIR/report.json (each atomically).
// Creates DIR.
void writeIdentifyReport(const std::filesystem::path& dir, const IdentifyReportData& data);
// Per pose (result.poses order) and joint, the σ of q̄ − f the fit's weights imply: √diag((WᵀW)⁻¹)
// of the pose's whitening for a weighted fit (its covariance propagated to the joints), σ̂ for an
// unweighted one; empty when the whitening does not match. The band of the residual figures.
std::vector<Eigen::VectorXd> jointResidualSigmas(const mechanism::IdentificationResult& result);
// The figures of report.html, named as the SVG files the Markdown links (identify_report_html.cpp).
std::vector<NamedFigure> identifyFigures(const IdentifyReportData& data);
// DIR/report.html alone (identify_report_html.cpp).
void writeIdentifyReportHtml(const std::filesystem::path& path, const IdentifyReportData& data);
// DIR/report.json alone (identify_report_json.cpp).
void writeIdentifyReportJson(const std::filesystem::path& path, const IdentifyReportData& data);

}  // namespace mire::app
