// doc/cli.md and `mire X --help` do not drift apart: every option the help of a subcommand prints
// appears in that subcommand's section of doc/cli.md, every option the section's table lists exists,
// and every subcommand (nested ones too, e.g. `simulate poses`) has a section.
#include "test_support.hpp"

#include <cctype>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

namespace {

struct Help {
  std::vector<std::string> options;      // "-o", "--output", ...
  std::vector<std::string> subcommands;  // names listed under "Subcommands:"
};

// CLI11's help: option lines start with exactly two spaces and a dash, subcommand lines with two
// spaces and a name, in their own "Options:" / "Subcommands:" blocks; descriptions that wrap are
// indented further.
Help parseHelp(const std::string& text) {
  Help help;
  std::istringstream lines(text);
  std::string block;
  for (std::string line; std::getline(lines, line);) {
    if (!line.empty() && line.back() == ':' && line[0] != ' ') {
      block = line;
      continue;
    }
    if (line.size() < 3 || line.compare(0, 2, "  ") != 0 || line[2] == ' ') continue;
    const std::string first = line.substr(2, line.find(' ', 2) - 2);
    if (block == "Options:" && first[0] == '-') {
      std::stringstream names(first);
      for (std::string name; std::getline(names, name, ',');) help.options.push_back(name);
    } else if (block == "Subcommands:") {
      help.subcommands.push_back(first);
    }
  }
  return help;
}

using mire::test::readText;

// The section of the Markdown whose heading starts with "`mire <command>`": from that heading to
// the next heading of the same or a higher level. Empty when there is no such heading.
std::string section(const std::string& markdown, const std::string& command) {
  std::istringstream lines(markdown);
  std::string out;
  std::size_t level = 0;
  for (std::string line; std::getline(lines, line);) {
    const std::size_t hashes = line.find_first_not_of('#');
    const bool heading = hashes != std::string::npos && hashes > 0 && line[hashes] == ' ';
    if (heading && level > 0 && hashes <= level) break;
    if (level > 0) out += line + "\n";
    if (heading && level == 0 && line.compare(hashes + 1, command.size() + 7, "`mire " + command + "`") == 0)
      level = hashes;
  }
  return out;
}

bool isNameChar(char c) { return std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '-' || c == '_'; }

// `name` as a whole word: "--mc" is not found inside "--mc-repeats".
bool mentions(const std::string& text, const std::string& name) {
  for (std::size_t at = text.find(name); at != std::string::npos; at = text.find(name, at + 1)) {
    const bool starts = at == 0 || !isNameChar(text[at - 1]);
    const bool ends = at + name.size() == text.size() || !isNameChar(text[at + name.size()]);
    if (starts && ends) return true;
  }
  return false;
}

// The option names of the first cells of the table rows ("| `-o`, `--output` | ...") of the command's
// own part of its section (before any nested subcommand's heading).
std::vector<std::string> tabledOptions(const std::string& text) {
  std::vector<std::string> names;
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);) {
    if (line.rfind('#', 0) == 0) break;
    if (line.rfind("| `-", 0) != 0) continue;
    const std::string cell = line.substr(1, line.find('|', 1) - 1);
    for (std::size_t open = cell.find('`'); open != std::string::npos; open = cell.find('`', open + 1)) {
      const std::size_t close = cell.find('`', open + 1);
      if (close == std::string::npos) break;
      names.push_back(cell.substr(open + 1, close - open - 1));
      open = close;
    }
  }
  return names;
}

Help helpOf(const std::string& command) {
  int code = -1;
  const std::string out = mire::test::captureCommand(
      mire::test::mireBinary().string() + (command.empty() ? "" : " " + command) + " --help", &code);
  EXPECT_EQ(code, 0) << "mire " << command << " --help:\n" << out;
  return parseHelp(out);
}

// Every subcommand path ("calibrate", "simulate poses", ...) with its help, depth first.
void collectCommands(const std::string& prefix, const Help& help, std::vector<std::pair<std::string, Help>>* commands) {
  for (const std::string& sub : help.subcommands) {
    const std::string path = prefix.empty() ? sub : prefix + " " + sub;
    const Help sub_help = helpOf(path);  // a copy: the recursion grows the vector
    commands->emplace_back(path, sub_help);
    collectCommands(path, sub_help, commands);
  }
}

}  // namespace

TEST(CliDoc, ParsesCli11Help) {
  const Help help = parseHelp(
      "Usage: mire x [OPTIONS]\n\nOptions:\n  -h,--help                   Print this help\n"
      "  --mc TEXT ...               sizes\n  --threads INT:INT in [1 - 256]=2\n"
      "                              -- wrapped description starting with a dash\n\nSubcommands:\n"
      "  poses                       Images per pose\n");
  EXPECT_EQ(help.options, (std::vector<std::string>{"-h", "--help", "--mc", "--threads"}));
  EXPECT_EQ(help.subcommands, (std::vector<std::string>{"poses"}));
  EXPECT_TRUE(mentions("`--mc-repeats`, `--mc`", "--mc"));
  EXPECT_FALSE(mentions("`--mc-repeats`", "--mc"));
  const std::string doc = "# t\n## `mire a`\n| `--x` | y |\n### `mire a b`\n| `--z` | y |\n## `mire c`\n--w\n";
  EXPECT_NE(section(doc, "a").find("--z"), std::string::npos);
  EXPECT_EQ(section(doc, "a").find("--w"), std::string::npos);
  EXPECT_EQ(section(doc, "a b"), "| `--z` | y |\n");
  EXPECT_EQ(tabledOptions(section(doc, "a")), (std::vector<std::string>{"--x"}));
}

TEST(CliDoc, EverySubcommandAndOptionOfTheHelpIsInDocCli) {
  const std::string doc = readText(mire::test::sourceDir() / "doc" / "cli.md");
  ASSERT_FALSE(doc.empty()) << "doc/cli.md is missing";
  std::vector<std::pair<std::string, Help>> commands;
  collectCommands("", helpOf(""), &commands);
  ASSERT_GE(commands.size(), 10u) << "mire --help lists too few subcommands";
  for (const auto& [command, help] : commands) {
    const std::string text = section(doc, command);
    if (text.empty()) {
      ADD_FAILURE() << "doc/cli.md has no section headed `mire " << command << "`";
      continue;
    }
    const std::set<std::string> printed(help.options.begin(), help.options.end());
    for (const std::string& option : help.options)
      EXPECT_TRUE(mentions(text, option)) << "mire " << command << " --help prints " << option
                                          << ", which doc/cli.md's section `mire " << command << "` does not mention";
    for (const std::string& option : tabledOptions(text))
      EXPECT_TRUE(printed.count(option) == 1) << "doc/cli.md's section `mire " << command << "` lists " << option
                                              << ", which mire " << command << " --help does not print";
  }
}
