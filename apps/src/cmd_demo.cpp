#include "commands.hpp"

#include <iostream>

namespace mire::app {
Runner addDemoCommand(CLI::App& app) {
  app.add_subcommand("demo", "(not implemented yet)");
  return [] {
    std::cerr << "mire demo: not implemented yet\n";
    return static_cast<int>(kUsage);
  };
}
}  // namespace mire::app
