#pragma once
// Shipped descriptions edited for a test (examples/mechanisms/).
#include <string>

#include "test_support.hpp"

namespace mire::test {

// examples/mechanisms/linear-delta.yaml with `stroke: [low, high]` [m] declared on every carriage.
inline std::string linearDeltaWithStrokes(const std::string& low, const std::string& high) {
  std::string description = readText(sourceDir() / "examples" / "mechanisms" / "linear-delta.yaml");
  const std::string stroke = "    stroke: [" + low + ", " + high + "]\n", branch = "    branch: +1";
  for (std::size_t at = description.find(branch); at != std::string::npos;
       at = description.find(branch, at + stroke.size() + branch.size()))
    description.insert(at, stroke);
  return description;
}

}  // namespace mire::test
