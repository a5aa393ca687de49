// `mire report CAMPAIGN_DIR`: one report.html for a whole campaign, assembled from the report files
// its commands wrote (mire/pipeline/campaign_report.hpp, doc/plots.md).
#include <iostream>
#include <memory>

#include "commands.hpp"
#include "mire/pipeline/campaign_report.hpp"
#include "mire/support/atomic_file.hpp"
#include "output_paths.hpp"
#include "report_html.hpp"

namespace mire::app {
namespace {

namespace fs = std::filesystem;

struct ReportArguments {
  std::string campaign, output;
  std::vector<std::string> command_line;
};

int runReport(const ReportArguments& args) {
  const fs::path output = args.output.empty() ? fs::path(args.campaign) / "campaign_report.html" : fs::path(args.output);
  CommandPaths paths{{}, {{args.campaign, "CAMPAIGN_DIR"}}, {}, {}};
  checkCommandPaths(paths);  // the page may be written inside the campaign: not an output checked here
  const pipeline::CampaignReport report = pipeline::assembleCampaignReport(
      args.campaign, output.parent_path().empty() ? fs::path(".") : output.parent_path(),
      commandLineText(args.command_line), versionString());
  support::writeFileAtomically(output, report.html);
  std::cout << "campaign " << args.campaign << ": " << report.stages.size() << " report files (";
  for (std::size_t i = 0; i < report.stages.size(); ++i) std::cout << (i ? ", " : "") << report.stages[i].kind;
  std::cout << ")\nwrote " << output.string() << "\n";
  return kOk;
}

}  // namespace

Runner addReportCommand(CLI::App& app) {
  auto args = std::make_shared<ReportArguments>();
  CLI::App* cmd = app.add_subcommand(
      "report",
      "one report.html for a campaign, from the report files its commands wrote (report.json, accuracy.json)");
  cmd->add_option("campaign", args->campaign, "the campaign folder (searched recursively for the report files)")->required();
  cmd->add_option("-o,--output", args->output, "the page to write (default CAMPAIGN_DIR/campaign_report.html)");
  return [args] {
    args->command_line = {"mire", "report", args->campaign};  // the positional as typed, not by its name
    if (!args->output.empty()) args->command_line.insert(args->command_line.end(), {"-o", args->output});
    return runReport(*args);
  };
}

}  // namespace mire::app
