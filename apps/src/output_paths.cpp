#include "output_paths.hpp"

#include "validate.hpp"

#include "mire/support/side_files.hpp"

#include <unistd.h>

#include <system_error>

namespace mire::app {
namespace fs = std::filesystem;

namespace {

// The path with symbolic links, '.' and '..' resolved (its missing tail kept as written).
fs::path resolved(const fs::path& path) {
  std::error_code ec;
  fs::path result = fs::weakly_canonical(fs::absolute(path, ec), ec);
  return ec ? fs::absolute(path).lexically_normal() : result;
}

bool isWithin(const fs::path& inner, const fs::path& outer) {
  auto i = inner.begin();
  for (auto o = outer.begin(); o != outer.end(); ++o, ++i) {
    if (o->empty() && std::next(o) == outer.end()) break;  // trailing separator
    if (i == inner.end() || *i != *o) return false;
  }
  return true;
}

// Same file: same resolved path, or both exist and are the same inode (hard links).
bool sameFile(const fs::path& a, const fs::path& b) {
  if (resolved(a) == resolved(b)) return true;
  std::error_code ec;
  return fs::exists(a, ec) && fs::exists(b, ec) && fs::equivalent(a, b, ec) && !ec;
}

std::string describe(const PathArgument& argument) { return argument.option + " '" + argument.path.string() + "'"; }

void checkWritable(const PathArgument& output, bool folder) {
  std::error_code ec;
  const fs::file_status status = fs::status(output.path, ec);
  if (fs::exists(status)) {
    if (folder && !fs::is_directory(status))
      throw std::runtime_error(describe(output) + ": exists and is not a folder");
    if (!folder && !fs::is_regular_file(status))
      throw std::runtime_error(describe(output) + ": exists and is not a regular file");
  }
  // The nearest existing ancestor must be a folder we may write in (folders are created).
  fs::path place = resolved(output.path).parent_path();
  if (folder && fs::exists(status)) place = resolved(output.path);
  while (!place.empty() && !fs::exists(place, ec) && place != place.root_path()) place = place.parent_path();
  if (!fs::is_directory(place, ec))
    throw std::runtime_error(describe(output) + ": '" + place.string() + "' is not a folder");
  if (::access(place.c_str(), W_OK | X_OK) != 0)
    throw std::runtime_error(describe(output) + ": cannot write in '" + place.string() + "' (permission)");
}

// The side files that travel with an input (support/side_files.hpp) and exist: readers pick
// them up by name, so overwriting one changes the input (e.g. `ikm --params id.yaml -o
// id_covariance.csv`, `fkm --frame camera --params id.yaml -o id.csv`).
std::vector<fs::path> existingSideFiles(const fs::path& input) {
  std::vector<fs::path> sides;
  std::error_code ec;
  for (const fs::path& side :
       {support::covarianceSidePath(input), support::sharedTermSidePath(input), support::mechanismSidePath(input)})
    if (fs::exists(side, ec)) sides.push_back(side);
  return sides;
}

void checkOutputAgainstInputs(const PathArgument& output, bool folder, const CommandPaths& paths) {
  const fs::path out = resolved(output.path);
  for (const PathArgument& input : paths.input_files) {
    for (const fs::path& side : existingSideFiles(input.path)) {
      if (sameFile(output.path, side))
        throw UsageError(describe(output) + " is '" + side.string() + "', the side file of the input " +
                         describe(input) + ": it would be overwritten; choose another name");
      if (folder && isWithin(resolved(side), out))
        throw UsageError(describe(output) + " holds '" + side.string() + "', the side file of the input " +
                         describe(input) + ": choose another output folder");
    }
    if (sameFile(output.path, input.path))
      throw UsageError(describe(output) + " is the input " + describe(input) + ": it would be overwritten");
    if (folder && isWithin(resolved(input.path), out))
      throw UsageError(describe(output) + " holds the input " + describe(input) + ": choose another output folder");
  }
  for (const PathArgument& input : paths.input_folders) {
    const fs::path in = resolved(input.path);
    if (isWithin(out, in) || sameFile(output.path, input.path))
      throw UsageError(describe(output) + " lies inside the input folder " + describe(input) + ": choose another place");
    if (folder && isWithin(in, out))
      throw UsageError(describe(output) + " holds the input folder " + describe(input) +
                       ": choose another output folder");
  }
}

}  // namespace

void checkCommandPaths(const CommandPaths& paths) {
  for (const PathArgument& input : paths.input_files) requireInputFile(input.path, input.option);
  for (const PathArgument& input : paths.input_folders) requireInputFolder(input.path, input.option);

  std::vector<std::pair<PathArgument, bool>> outputs;  // (argument, is a folder)
  for (const PathArgument& output : paths.output_files) outputs.emplace_back(output, false);
  for (const PathArgument& output : paths.output_folders) outputs.emplace_back(output, true);
  for (const auto& [output, folder] : outputs)
    if (output.path.empty()) throw UsageError(output.option + ": empty path");
  for (std::size_t i = 0; i < outputs.size(); ++i) {
    const auto& [output, folder] = outputs[i];
    checkOutputAgainstInputs(output, folder, paths);
    for (std::size_t j = i + 1; j < outputs.size(); ++j) {
      const auto& [other, other_folder] = outputs[j];
      const fs::path a = resolved(output.path), b = resolved(other.path);
      if (sameFile(output.path, other.path) || (folder && isWithin(b, a)) || (other_folder && isWithin(a, b)))
        throw UsageError(describe(output) + " and " + describe(other) + " would overwrite each other");
    }
    checkWritable(output, folder);
  }
}

}  // namespace mire::app
