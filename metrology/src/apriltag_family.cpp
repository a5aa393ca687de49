#include "mire/metrology/apriltag_family.hpp"

#include <apriltag/tag16h5.h>
#include <apriltag/tag25h9.h>
#include <apriltag/tag36h10.h>
#include <apriltag/tag36h11.h>
#include <apriltag/tagCircle21h7.h>
#include <apriltag/tagCircle49h12.h>
#include <apriltag/tagCustom48h12.h>
#include <apriltag/tagStandard41h12.h>
#include <apriltag/tagStandard52h13.h>

namespace mire::metrology::detail {
namespace {

// Kalibr's aprilgrid (kalibr_create_target_pdf) prints tag36h11 codes inside a black border
// two bits wide: the same codes, each data bit one cell further in, the black square two cells
// wider (doc/targets.md, "Kalibr aprilgrid").
apriltag_family_t* tag36h11Border2Create() {
  apriltag_family_t* family = tag36h11_create();
  for (uint32_t i = 0; i < family->nbits; ++i) {
    ++family->bit_x[i];
    ++family->bit_y[i];
  }
  family->width_at_border += 2;
  family->total_width += 2;
  return family;
}

struct FamilyEntry {
  const char* name;
  apriltag_family_t* (*create)();
  void (*destroy)(apriltag_family_t*);
};

constexpr FamilyEntry kFamilies[] = {
    {"tag36h11", tag36h11_create, tag36h11_destroy},
    {"tag36h11_border2", tag36h11Border2Create, tag36h11_destroy},
    {"tag36h10", tag36h10_create, tag36h10_destroy},
    {"tag25h9", tag25h9_create, tag25h9_destroy},
    {"tag16h5", tag16h5_create, tag16h5_destroy},
    {"tagCircle21h7", tagCircle21h7_create, tagCircle21h7_destroy},
    {"tagCircle49h12", tagCircle49h12_create, tagCircle49h12_destroy},
    {"tagCustom48h12", tagCustom48h12_create, tagCustom48h12_destroy},
    {"tagStandard41h12", tagStandard41h12_create, tagStandard41h12_destroy},
    {"tagStandard52h13", tagStandard52h13_create, tagStandard52h13_destroy},
};

}  // namespace

TagFamilyPtr createTagFamily(const std::string& name) {
  for (const FamilyEntry& entry : kFamilies)
    if (name == entry.name) return TagFamilyPtr(entry.create(), TagFamilyDeleter{entry.destroy});
  return TagFamilyPtr(nullptr, TagFamilyDeleter{});
}

std::vector<std::string> tagFamilyNames() {
  std::vector<std::string> names;
  for (const FamilyEntry& entry : kFamilies) names.emplace_back(entry.name);
  return names;
}

}  // namespace mire::metrology::detail
