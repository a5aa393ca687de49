// Code comments and docs cite the paper's equations or files in doc/, never a document outside the
// repository. Scans every tracked C++, Python and CMake file and doc/*.md.
#include "test_support.hpp"

#include "mire/mechanism/registry.hpp"

#include <algorithm>
#include <fstream>
#include <functional>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;

// The outside brief's name, spelt so that this file does not contain it.
const std::string kOutsideDocument = std::string("BRI") + "EF";

bool isScanned(const std::string& relative) {
  const fs::path path(relative);
  const std::string ext = path.extension().string();
  const std::string name = path.filename().string();
  if (ext == ".cpp" || ext == ".hpp" || ext == ".h" || ext == ".py" || ext == ".cmake" || name == "CMakeLists.txt")
    return true;
  return ext == ".md" && path.parent_path() == "doc";
}

// Tracked files (git ls-files); without git (an exported tree), every file outside hidden and build folders.
std::vector<std::string> candidateFiles(const fs::path& root) {
  std::vector<std::string> files;
  int code = -1;
  const std::string listing = mire::test::captureCommand("git -C '" + root.string() + "' ls-files 2>/dev/null", &code);
  if (code == 0 && !listing.empty()) {
    std::istringstream lines(listing);
    for (std::string line; std::getline(lines, line);) files.push_back(line);
    return files;
  }
  for (auto it = fs::recursive_directory_iterator(root); it != fs::recursive_directory_iterator(); ++it) {
    const std::string name = it->path().filename().string();
    if (it->is_directory() && (name.rfind('.', 0) == 0 || name.rfind("build", 0) == 0)) {
      it.disable_recursion_pending();
      continue;
    }
    if (it->is_regular_file()) files.push_back(fs::relative(it->path(), root).generic_string());
  }
  return files;
}

// Calls check(where, line) for every line of every tracked file `selected` accepts ("path:line");
// returns how many files it read.
int forEachLine(const std::function<bool(const std::string&)>& selected,
                const std::function<void(const std::string&, const std::string&)>& check) {
  const fs::path root = mire::test::sourceDir();
  int scanned = 0;
  for (const std::string& relative : candidateFiles(root)) {
    if (!selected(relative)) continue;
    std::ifstream in(root / relative);
    EXPECT_TRUE(in) << relative;
    ++scanned;
    int line_number = 0;
    for (std::string line; std::getline(in, line);) check(relative + ":" + std::to_string(++line_number), line);
  }
  return scanned;
}

}  // namespace

TEST(DocCitations, NoSourceOrDocCitesTheOutsideBrief) {
  const int scanned = forEachLine(isScanned, [](const std::string& where, const std::string& line) {
    EXPECT_EQ(line.find(kOutsideDocument), std::string::npos)
        << where << " cites a document outside the repository (cite the paper's equation or doc/):\n  " << line;
  });
  EXPECT_GT(scanned, 100) << "too few source files found under " << mire::test::sourceDir();
}

// Comments state contracts and cite the paper or doc/, never the tracker ("issue <number>") or a work
// log; doc headings name topics, not sessions ("Stop 27"): history lives in CHANGELOG.md and the
// dated pages of doc/studies/.
TEST(DocCitations, NoCommentOrDocCitesTheTrackerOrAWorkLog) {
  const std::regex tracker(R"((^|[^A-Za-z])[Ii]ssues? +#?[0-9]+)");
  const std::regex work_log_heading(R"(^#+ .*\b[Ss]tops? [0-9]+)");
  const auto selected = [](const std::string& relative) {
    const std::string ext = fs::path(relative).extension().string();
    const bool doc_page = ext == ".md" && relative.rfind("doc/", 0) == 0;  // doc/studies/ too
    return isScanned(relative) || doc_page || ext == ".sh";
  };
  const int scanned = forEachLine(selected, [&](const std::string& where, const std::string& line) {
    EXPECT_FALSE(std::regex_search(line, tracker))
        << where << " cites the tracker (state the contract, cite doc/):\n  " << line;
    EXPECT_FALSE(std::regex_search(line, work_log_heading))
        << where << " is a work-log heading (history: CHANGELOG.md):\n  " << line;
  });
  EXPECT_GT(scanned, 100) << "too few files found under " << mire::test::sourceDir();
}

// A model's name is spelled once, in the table of mechanisms (mechanism/src/registry.cpp), and in
// the kinematics that carry it (Mechanism::name()); every other product file asks the table
// (doc/architecture.md, "Adding a mechanism"). Tests, benchmarks and examples choose models by
// name as a user does.
TEST(DocCitations, ModelNamesAreSpelledOnlyInTheTableOfMechanisms) {
  const std::vector<std::string> product{"apps/",      "calibration/", "datasets/", "mechanism/",
                                         "metrology/", "pipeline/",    "support/",  "python/src/"};
  const auto selected = [&](const std::string& relative) {
    const std::string ext = fs::path(relative).extension().string();
    if (ext != ".cpp" && ext != ".hpp") return false;
    return std::any_of(product.begin(), product.end(),
                       [&](const std::string& dir) { return relative.rfind(dir, 0) == 0; });
  };
  std::set<std::string> spelling;
  const int scanned = forEachLine(selected, [&](const std::string& where, const std::string& line) {
    for (const mire::mechanism::ModelInfo& model : mire::mechanism::registeredModels())
      if (line.find('"' + model.name + '"') != std::string::npos) spelling.insert(where.substr(0, where.find(':')));
  });
  EXPECT_GT(scanned, 100) << "too few files found under " << mire::test::sourceDir();
  EXPECT_EQ(spelling,
            (std::set<std::string>{"mechanism/src/registry.cpp",
                                   "mechanism/include/mire/mechanism/detail/parallel_kinematics.hpp",
                                   "mechanism/include/mire/mechanism/detail/gough_stewart_gains_kinematics.hpp"}));
}
