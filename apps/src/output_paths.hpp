#pragma once
// The one check of a command's paths, made before any work: every input exists and is a
// regular file or folder (validate.hpp), and no output is an input or another output -
// compared after resolving symbolic links, '..' and hard links - nor lies inside an input
// folder; every output can be written. UsageError (exit 2) for a conflict or an empty path,
// std::runtime_error (exit 1) for a missing input or an unwritable place.
#include <filesystem>
#include <string>
#include <vector>

namespace mire::app {

struct PathArgument {
  std::filesystem::path path;
  std::string option;  // e.g. "--camera", "-o"
};

struct CommandPaths {
  std::vector<PathArgument> input_files;
  std::vector<PathArgument> input_folders;
  std::vector<PathArgument> output_files;
  std::vector<PathArgument> output_folders;
};

void checkCommandPaths(const CommandPaths& paths);

}  // namespace mire::app
