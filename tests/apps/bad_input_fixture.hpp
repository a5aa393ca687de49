#pragma once
// The bad-input matrix (doc/robustness.md): valid inputs made once per suite with
// `mire simulate` and the simulated H4 campaign, then one mutated copy per case. Each case
// asserts the exit code, the message (naming the file, line, image, key or option), that
// nothing was written and that every input kept its bytes.
#include <gtest/gtest.h>

#include "test_support.hpp"

#include <sys/stat.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace mire::app::badinput {

namespace fs = std::filesystem;

inline std::string slurp(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

inline void spit(const fs::path& path, const std::string& text) {
  fs::create_directories(path.parent_path());
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << text;
}

// Every regular file under `root` (recursively) with its bytes; other entries by their kind.
inline std::map<std::string, std::string> snapshot(const fs::path& root) {
  std::map<std::string, std::string> files;
  if (!fs::exists(root)) return files;
  for (const auto& entry : fs::recursive_directory_iterator(root)) {
    const std::string key = fs::relative(entry.path(), root).string();
    const auto status = entry.symlink_status();
    if (fs::is_symlink(status))
      files[key] = "symlink->" + fs::read_symlink(entry.path()).string();
    else if (fs::is_regular_file(status))
      files[key] = slurp(entry.path());
    else if (fs::is_directory(status))
      files[key] = "<dir>";
    else
      files[key] = "<special>";
  }
  return files;
}

// Paths of the suite's valid inputs (made once).
struct Fixture {
  fs::path root;
  fs::path sim;       // mire simulate poses: camera.yaml, target.yaml, poses/<id>/img_XX.png
  fs::path cal;       // mire simulate calibration: images/, camera.yaml, target.yaml
  fs::path campaign;  // poses.csv, joints.csv, lines.csv of the simulated H4
  fs::path spec;      // the simulation spec used for sim (explicit pose list)
  fs::path cal_spec;
  std::string error;  // why the fixture could not be made
};

// A case's own folder, with helpers to write its mutated inputs.
struct CaseEnv {
  const Fixture& f;
  fs::path dir;

  std::string p(const std::string& relative) const { return (dir / relative).string(); }
  std::string write(const std::string& relative, const std::string& text) const {
    spit(dir / relative, text);
    return p(relative);
  }
  std::string copy(const fs::path& from, const std::string& relative) const {
    fs::create_directories((dir / relative).parent_path());
    fs::copy(from, dir / relative, fs::copy_options::recursive);
    return p(relative);
  }
  std::string fifo(const std::string& relative) const {
    ::mkfifo((dir / relative).c_str(), 0644);
    return p(relative);
  }
  std::string folder(const std::string& relative) const {
    fs::create_directories(dir / relative);
    return p(relative);
  }
  // A copy of `from` with the first occurrence of `what` replaced by `with`.
  std::string edit(const fs::path& from, const std::string& relative, const std::string& what,
                   const std::string& with) const {
    std::string text = slurp(from);
    const auto at = text.find(what);
    if (at != std::string::npos)
      text.replace(at, what.size(), with);
    else
      text += "\n# EDIT FAILED: '" + what + "' not found\n";
    return write(relative, text);
  }
  // Inputs of the fixture, as strings for command lines.
  std::string camera() const { return (f.sim / "camera.yaml").string(); }
  std::string target() const { return (f.sim / "target.yaml").string(); }
  std::string poses_dir() const { return (f.sim / "poses").string(); }
  std::string images() const { return (f.cal / "images").string(); }
  std::string cal_target() const { return (f.cal / "target.yaml").string(); }
  std::string poses_csv() const { return (f.campaign / "poses.csv").string(); }
  std::string joints_csv() const { return (f.campaign / "joints.csv").string(); }
  std::string lines_csv() const { return (f.campaign / "lines.csv").string(); }
};

struct Case {
  std::string name;
  std::function<std::string(const CaseEnv&)> arguments;  // after "mire "
  int exit_code;
  std::vector<std::string> message;  // each must appear in stdout+stderr (with {dir} = the case folder)
};

// gtest prints a case by its name (ctest's test names stay readable).
inline void PrintTo(const Case& c, std::ostream* os) { *os << c.name; }

const Fixture& fixture();
const std::vector<Case>& allCases();

}  // namespace mire::app::badinput
