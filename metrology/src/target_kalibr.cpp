// Kalibr's aprilgrid target file (doc/targets.md, "Kalibr aprilgrid"), as Kalibr spells it:
//   target_type: 'aprilgrid', tagCols, tagRows, tagSize (the tag's black edge, m),
//   tagSpacing (the gap between tags as a fraction of tagSize).
// kalibr_create_target_pdf draws tag id cols·y + x at (x, y)·tagSize·(1 + tagSpacing) with y
// pointing UP the printed page (tag 0 bottom-left), tag36h11 codes upright inside a two-bit
// black border, plus black squares in the gaps at the tags' corners. mire's frame M has y
// pointing down the page (doc/targets.md), so the grid becomes a tag layout: tag (x, y) has its
// top-left corner at (x·p, (rows − 1 − y)·p). The corners are the black border's outer corners,
// as for every mire AprilTag target.
#include "target_kalibr.hpp"

#include <string>

namespace mire::metrology::detail {
namespace {

constexpr support::YamlRange kKalibrLength{-1e300, 1e300};  // checked below, with the reason

double positiveLength(const support::YamlNode& root, const char* key) {
  const double value = root.number(key, kKalibrLength);
  if (!(value > 0.0)) root.at(key).fail("must be a positive length in metres");
  if (value > 10.0) root.at(key).fail("is in metres in Kalibr's files too (0.088 for an 88 mm tag)");
  return value;
}

}  // namespace

bool isKalibrTarget(const support::YamlNode& root) { return root.has("target_type") && !root.has("type"); }

TargetSpec kalibrTargetSpec(const support::YamlNode& root) {
  const std::string type = root.string("target_type");
  if (type != "aprilgrid")
    root.at("target_type")
        .fail("Kalibr target '" + type +
              "': mire reads Kalibr's 'aprilgrid' only; describe a checkerboard or circle grid in mire's "
              "target.yaml (doc/targets.md)");
  root.checkKeys({"target_type", "tagCols", "tagRows", "tagSize", "tagSpacing"});
  const int cols = static_cast<int>(root.integer("tagCols", 1, 10000));
  const int rows = static_cast<int>(root.integer("tagRows", 1, 10000));
  const double size = positiveLength(root, "tagSize");
  const double spacing = root.number("tagSpacing", {0.0, 1.0});
  if (!(spacing > 0.0)) root.at("tagSpacing").fail("must be above 0 (the gap between tags / tagSize, Kalibr: 0..1)");
  const long long tags = static_cast<long long>(cols) * rows;
  if (tags > 587)  // tag36h11 has 587 codes, Kalibr numbers the tags from 0
    root.fail(std::to_string(cols) + " x " + std::to_string(rows) + " tags need ids 0.." + std::to_string(tags - 1) +
              "; tag36h11 has 0..586");
  TargetSpec spec;
  spec.type = TargetType::AprilTag;
  spec.family = "tag36h11_border2";
  spec.tag_size_m = size;
  const double pitch = size * (1.0 + spacing);
  for (int y = 0; y < rows; ++y)
    for (int x = 0; x < cols; ++x) spec.tags.push_back({cols * y + x, x * pitch, (rows - 1 - y) * pitch});
  return spec;
}

}  // namespace mire::metrology::detail
