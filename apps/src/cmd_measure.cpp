#include "commands.hpp"

#include <iostream>

namespace mire::app {
Runner addMeasureCommand(CLI::App& app) {
  app.add_subcommand("measure", "(not implemented yet)");
  return [] {
    std::cerr << "mire measure: not implemented yet\n";
    return static_cast<int>(kUsage);
  };
}
}  // namespace mire::app
