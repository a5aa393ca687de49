#pragma once
// One report for a whole campaign (doc/plots.md, "A campaign's report"): camera → poses →
// identification → compensation → accuracy, assembled from the files the commands wrote under the
// campaign folder — every report.json (calibrate, measure, plan, select, identify, compensate, a
// demo) and accuracy.json — never by running anything again. Each stage gives its result with its
// uncertainty and a link to its own report.html; the page ends with every stage's command line and
// the SHA-256 of every input file the commands name, as the files are now (a file changed or gone
// since the command ran shows as such: the record is the command's, the checksum is today's).
#include <filesystem>
#include <string>
#include <vector>

namespace mire::pipeline {

struct CampaignStageFile {
  std::string kind;            // "calibrate", "measure", … as the file's "report" key says
  std::filesystem::path file;  // the report.json / accuracy.json read
  std::filesystem::path html;  // its report.html beside it, empty when none
};

struct CampaignReport {
  std::string html;                       // the page
  std::vector<CampaignStageFile> stages;  // in the chain's order
};

// The report files under `campaign` (recursively), in the chain's order (calibrate, measure, plan,
// select, identify, compensate, accuracy, demo; then by path). Throws std::runtime_error naming
// the folder when it is not a folder or holds no report file, and naming the file (and the JSON
// parser's message) when one cannot be read.
std::vector<CampaignStageFile> findCampaignReports(const std::filesystem::path& campaign);

// The page for those files; `command_line` and `version` for its own provenance line. Links to
// the stages' report.html are relative to `output_dir` (where the page will be written).
CampaignReport assembleCampaignReport(const std::filesystem::path& campaign, const std::filesystem::path& output_dir,
                                      const std::string& command_line, const std::string& version);

}  // namespace mire::pipeline
