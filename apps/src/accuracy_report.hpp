#pragma once
// accuracy.json of `mire accuracy` (doc/accuracy.md, doc/file-formats.md): the ISO 9283 figures
// per position, per pair of positions and per straight line, SI units (m, rad) in the key names,
// each with its σ and its noise-only part; written as report.json is (report_json.hpp).
#include <filesystem>
#include <string>

#include "mire/pipeline/accuracy.hpp"
#include "report_json.hpp"

namespace mire::app {

// {"pose_components", "cycles_used", "unmeasured", "positions", "distances", "lines"}: the figures
// as accuracy.json holds them (the demos' closed-loop section reuses them).
Json accuracyFiguresJson(const pipeline::AccuracyResult& result);

void writeAccuracyJson(const std::filesystem::path& path, const ReportProvenance& provenance,
                       const std::string& model_name, const pipeline::AccuracyResult& result);

}  // namespace mire::app
