#pragma once
// `mire demo`: the pipeline's demo stages (mire/pipeline/demo.hpp, doc/simulation.md,
// doc/demo-mechanisms.md), then the report: report.md, report.html, report.json and the figures,
// one writer whose sections appear when their results exist (the paper's study, or each model).
#include <filesystem>
#include <string>
#include <vector>

#include "mire/pipeline/demo.hpp"
#include "report_json.hpp"

namespace mire::app {

using pipeline::DemoExperimentDesign;
using pipeline::DemoModelScore;
using pipeline::DemoOptions;
using pipeline::DemoParameterScore;
using pipeline::DemoPoseCount;
using pipeline::DemoResults;
using pipeline::DemoVariant;
using pipeline::PaperStudy;
using pipeline::StageTiming;

// Runs the demo's stages into options.output, then writes its report; returns the results.
DemoResults runDemo(const DemoOptions& options);

// Writes report.md, report.json, report.html and the figures; returns the files written (relative names).
std::vector<std::string> writeDemoReport(const DemoOptions& options, const DemoResults& results);

// report.json: the results without the run times (never the same twice).
void writeDemoReportJson(const std::filesystem::path& path, const ReportProvenance& provenance,
                         const DemoOptions& options, const DemoResults& results);

}  // namespace mire::app
