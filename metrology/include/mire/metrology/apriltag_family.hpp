#pragma once
// RAII ownership of an AprilTag 3 tag family, created from its name (target.yaml `family`).
#include <apriltag/apriltag.h>

#include <memory>
#include <string>
#include <vector>

namespace mire::metrology::detail {

struct TagFamilyDeleter {
  void (*destroy)(apriltag_family_t*) = nullptr;
  void operator()(apriltag_family_t* family) const {
    if (family && destroy) destroy(family);
  }
};
using TagFamilyPtr = std::unique_ptr<apriltag_family_t, TagFamilyDeleter>;

// The family called `name`, or nullptr when AprilTag 3 has no family of that name.
TagFamilyPtr createTagFamily(const std::string& name);

// Names accepted by createTagFamily, for error messages.
std::vector<std::string> tagFamilyNames();

}  // namespace mire::metrology::detail
