// Planar targets: validation, feature layout in frame M and target.yaml (doc/targets.md).
#include "mire/metrology/target.hpp"

#include "mire/metrology/apriltag_family.hpp"
#include "mire/metrology/aruco_boards.hpp"
#include "mire/support/yaml.hpp"
#include "target_kalibr.hpp"

#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>
#include <stdexcept>

namespace mire::metrology {
namespace {

struct TypeName {
  TargetType type;
  const char* name;
};
constexpr TypeName kTypeNames[] = {{TargetType::Chessboard, "chessboard"},
                                   {TargetType::Circles, "circles"},
                                   {TargetType::AsymmetricCircles, "acircles"},
                                   {TargetType::AprilTag, "apriltag"},
                                   {TargetType::Charuco, "charuco"},
                                   {TargetType::ArucoGrid, "aruco_grid"}};

// The feature limit of doc/limits.md (the commands check the same number, apps/src/validate.hpp).
constexpr std::size_t kMaxTargetFeatures = 20'000;

bool isPositiveFinite(double value) { return std::isfinite(value) && value > 0.0; }

void require(bool condition, const std::string& message) {
  if (!condition) throw std::invalid_argument(message);
}

std::string joined(const std::vector<std::string>& names) {
  std::string text;
  for (const std::string& name : names) text += (text.empty() ? "" : ", ") + name;
  return text;
}

// The number of markers/tags a target needs from its dictionary, and the family's size.
void requireIds(long long first, long long count, long long available, const std::string& dictionary) {
  require(first >= 0 && first + count <= available, "ids " + std::to_string(first) + ".." +
                                                        std::to_string(first + count - 1) + " do not exist in " +
                                                        dictionary + " (ids 0.." + std::to_string(available - 1) + ")");
}

void validateAprilTag(const TargetSpec& spec) {
  require(isPositiveFinite(spec.tag_size_m), "tag_size_m must be positive");
  const detail::TagFamilyPtr family = detail::createTagFamily(spec.family);
  if (!family)
    throw std::invalid_argument("unknown AprilTag family '" + spec.family +
                                "' (known: " + joined(detail::tagFamilyNames()) + ")");
  if (spec.tags.empty()) {
    require(spec.cols >= 1 && spec.rows >= 1, "cols and rows must be at least 1 for an apriltag grid (got " +
                                                  std::to_string(spec.cols) + " x " + std::to_string(spec.rows) + ")");
    if (spec.cols * spec.rows > 1)
      require(isPositiveFinite(spec.tag_spacing_m) && spec.tag_spacing_m > spec.tag_size_m,
              "tag_spacing_m must be larger than tag_size_m (tags must not touch)");
    requireIds(spec.first_id, static_cast<long long>(spec.cols) * spec.rows, family->ncodes, spec.family);
    return;
  }
  std::set<int> ids;
  for (std::size_t k = 0; k < spec.tags.size(); ++k) {
    const TagPlacement& tag = spec.tags[k];
    const std::string entry = "tags[" + std::to_string(k) + "]";
    require(std::isfinite(tag.x_m) && std::isfinite(tag.y_m), entry + ": x and y must be finite (metres)");
    require(tag.id >= 0 && tag.id < static_cast<int>(family->ncodes),
            entry + ": id " + std::to_string(tag.id) + " does not exist in " + spec.family + " (ids 0.." +
                std::to_string(family->ncodes - 1) + ")");
    require(ids.insert(tag.id).second, entry + ": id " + std::to_string(tag.id) + " listed twice");
    for (std::size_t other = 0; other < k; ++other) {
      const TagPlacement& o = spec.tags[other];
      const bool apart = std::abs(tag.x_m - o.x_m) >= spec.tag_size_m || std::abs(tag.y_m - o.y_m) >= spec.tag_size_m;
      require(apart, entry + " (id " + std::to_string(tag.id) + ") overlaps tags[" + std::to_string(other) + "] (id " +
                         std::to_string(o.id) + ")");
    }
  }
}

void validateAruco(const TargetSpec& spec) {
  const cv::Ptr<cv::aruco::Dictionary> dictionary = arucoDictionary(spec.dictionary);
  if (!dictionary)
    throw std::invalid_argument("unknown dictionary '" + spec.dictionary +
                                "' (known: " + joined(arucoDictionaryNames()) + ")");
  require(isPositiveFinite(spec.marker_size_m), "marker_size_m must be positive");
  const long long available = dictionary->bytesList.rows;
  if (spec.type == TargetType::Charuco) {
    require(isPositiveFinite(spec.square_size_m), "square_size_m must be positive");
    require(spec.marker_size_m < spec.square_size_m, "marker_size_m must be smaller than square_size_m");
    // OpenCV puts a marker in every white square: ids 0 .. floor(cols·rows / 2) − 1.
    requireIds(0, static_cast<long long>(spec.cols) * spec.rows / 2, available, spec.dictionary);
  } else {
    require(isPositiveFinite(spec.marker_spacing_m), "marker_spacing_m must be positive");
    requireIds(spec.first_id, static_cast<long long>(spec.cols) * spec.rows, available, spec.dictionary);
  }
}

// Features the layout would have, counted before any is made: a huge cols × rows must be
// refused at once rather than allocated (doc/limits.md: at most kMaxTargetFeatures).
long long featureCount(const TargetSpec& spec) {
  const long long cols = std::max(spec.cols, 0), rows = std::max(spec.rows, 0);
  switch (spec.type) {
    case TargetType::AprilTag:
      return 4 * (spec.tags.empty() ? cols * rows : static_cast<long long>(spec.tags.size()));
    case TargetType::ArucoGrid:
      return 4 * cols * rows;
    case TargetType::Charuco:
      return std::max(cols - 1, 0LL) * std::max(rows - 1, 0LL);
    default:
      return cols * rows;
  }
}

void validateSpec(const TargetSpec& spec) {
  const long long features = featureCount(spec);
  require(features <= static_cast<long long>(kMaxTargetFeatures),
          "the target has " + std::to_string(features) + " features; mire handles at most " +
              std::to_string(kMaxTargetFeatures) + " (doc/limits.md)");
  if (spec.type == TargetType::AprilTag) return validateAprilTag(spec);
  const int minimum = spec.type == TargetType::ArucoGrid ? 1 : 3;  // OpenCV's grid finders need 3
  require(spec.cols >= minimum && spec.rows >= minimum,
          "cols and rows must be at least " + std::to_string(minimum) + " for a " + targetTypeName(spec.type) +
              " target (got " + std::to_string(spec.cols) + " x " + std::to_string(spec.rows) + ")");
  switch (spec.type) {
    case TargetType::Chessboard:
      require(isPositiveFinite(spec.square_size_m), "square_size_m must be positive");
      break;
    case TargetType::Circles:
    case TargetType::AsymmetricCircles: {
      require(isPositiveFinite(spec.spacing_m), "spacing_m must be positive");
      require(isPositiveFinite(spec.diameter_m), "diameter_m must be positive");
      const double nearest = spec.type == TargetType::Circles ? spec.spacing_m : spec.spacing_m * std::sqrt(2.0);
      require(spec.diameter_m < nearest, "diameter_m must be smaller than the distance between neighbouring centres (" +
                                             std::to_string(nearest) + " m)");
      break;
    }
    case TargetType::Charuco:
    case TargetType::ArucoGrid:
      validateAruco(spec);
      break;
    case TargetType::AprilTag:
      break;
  }
}

// The tags (AprilTag) or markers (ArUco grid) of a target, in feature order.
std::vector<TagPlacement> squareLayout(const TargetSpec& spec) {
  if (spec.type == TargetType::AprilTag && !spec.tags.empty()) return spec.tags;
  std::vector<TagPlacement> layout;
  if (spec.type != TargetType::AprilTag && spec.type != TargetType::ArucoGrid) return layout;
  const double pitch =
      spec.type == TargetType::AprilTag ? spec.tag_spacing_m : spec.marker_size_m + spec.marker_spacing_m;
  for (int r = 0; r < spec.rows; ++r)
    for (int c = 0; c < spec.cols; ++c) layout.push_back({spec.first_id + r * spec.cols + c, c * pitch, r * pitch});
  return layout;
}

std::vector<Eigen::Vector3d> squareCorners(const std::vector<TagPlacement>& layout, double size) {
  std::vector<Eigen::Vector3d> points;
  for (const TagPlacement& tag : layout) {
    const Eigen::Vector3d origin(tag.x_m, tag.y_m, 0.0);
    points.push_back(origin);
    points.emplace_back(origin + Eigen::Vector3d(size, 0.0, 0.0));
    points.emplace_back(origin + Eigen::Vector3d(size, size, 0.0));
    points.emplace_back(origin + Eigen::Vector3d(0.0, size, 0.0));
  }
  return points;
}

std::vector<Eigen::Vector3d> featurePoints(const TargetSpec& spec, const std::vector<TagPlacement>& layout) {
  if (spec.type == TargetType::AprilTag) return squareCorners(layout, spec.tag_size_m);
  if (spec.type == TargetType::ArucoGrid) return squareCorners(layout, spec.marker_size_m);
  std::vector<Eigen::Vector3d> points;
  if (spec.type == TargetType::Charuco) {  // OpenCV's CharucoBoard::chessboardCorners
    for (int r = 0; r + 1 < spec.rows; ++r)
      for (int c = 0; c + 1 < spec.cols; ++c)
        points.emplace_back((c + 1) * spec.square_size_m, (r + 1) * spec.square_size_m, 0.0);
    return points;
  }
  for (int r = 0; r < spec.rows; ++r) {
    for (int c = 0; c < spec.cols; ++c) {
      switch (spec.type) {
        case TargetType::Chessboard:
          points.emplace_back(c * spec.square_size_m, r * spec.square_size_m, 0.0);
          break;
        case TargetType::Circles:
          points.emplace_back(c * spec.spacing_m, r * spec.spacing_m, 0.0);
          break;
        case TargetType::AsymmetricCircles:  // OpenCV's asymmetric layout
          points.emplace_back((2 * c + r % 2) * spec.spacing_m, r * spec.spacing_m, 0.0);
          break;
        default:
          break;
      }
    }
  }
  return points;
}

// target.yaml through the YAML layer: errors name the file, the line and the key.
constexpr support::YamlRange kLengthRange{0.0, 10.0};  // metres: a printed target, not a room
constexpr support::YamlRange kPositionRange{-10.0, 10.0};

double length(const support::YamlNode& root, const char* key) {
  const double value = root.number(key, {-1e300, 1e300});
  if (!(value > 0.0)) root.at(key).fail("must be a positive length in metres");
  if (value > kLengthRange.max)  // the usual slip: a length written in millimetres
    root.at(key).fail(support::formatMessageNumber(value) +
                      " m is not a printed target; lengths are in metres, not "
                      "millimetres (25 mm is " +
                      std::string(key) + ": 0.025)");
  return value;
}

int count(const support::YamlNode& root, const char* key) { return static_cast<int>(root.integer(key, 1, 10000)); }

int firstId(const support::YamlNode& root) {
  return root.has("first_id") ? static_cast<int>(root.integer("first_id", 0, 1000000)) : 0;
}

std::string dictionaryName(const support::YamlNode& root) {
  std::string name = root.string("dictionary");
  if (!arucoDictionary(name))
    root.at("dictionary").fail("unknown dictionary '" + name + "' (known: " + joined(arucoDictionaryNames()) + ")");
  return name;
}

std::string familyName(const support::YamlNode& root) {
  std::string name = root.string("family");
  if (!detail::createTagFamily(name))
    root.at("family").fail("unknown AprilTag family '" + name + "' (known: " + joined(detail::tagFamilyNames()) + ")");
  return name;
}

// `tags: [ {id: 8, x: 0, y: 0}, ... ]`; entries checked one by one, with their line.
std::vector<TagPlacement> tagList(const support::YamlNode& root, const TargetSpec& spec) {
  const support::YamlNode list = root.at("tags");
  if (!list.isSequence() || list.size() == 0) list.fail("must be a non-empty list of {id, x, y} (metres)");
  std::vector<TagPlacement> tags;
  for (const support::YamlNode& entry : list.items()) {
    if (!entry.isMap()) entry.fail("each tag must be a map {id, x, y} (x, y: its top-left corner in metres)");
    entry.checkKeys({"id", "x", "y"});
    const TagPlacement tag{static_cast<int>(entry.integer("id", 0, 1000000)), entry.number("x", kPositionRange),
                           entry.number("y", kPositionRange)};
    TargetSpec partial = spec;
    partial.tags = tags;
    partial.tags.push_back(tag);
    try {
      validateAprilTag(partial);  // id in the family, not repeated, no overlap
    } catch (const std::invalid_argument& error) {
      entry.fail(error.what());
    }
    tags.push_back(tag);
  }
  return tags;
}

std::vector<std::string> knownKeys(TargetType type, bool tag_list) {
  switch (type) {
    case TargetType::Chessboard:
      return {"type", "cols", "rows", "square_size_m"};
    case TargetType::Circles:
    case TargetType::AsymmetricCircles:
      return {"type", "cols", "rows", "spacing_m", "diameter_m"};
    case TargetType::AprilTag:
      if (tag_list) return {"type", "family", "tag_size_m", "tags"};
      return {"type", "cols", "rows", "family", "tag_size_m", "tag_spacing_m", "first_id"};
    case TargetType::Charuco:
      return {"type", "cols", "rows", "square_size_m", "marker_size_m", "dictionary"};
    case TargetType::ArucoGrid:
      return {"type", "cols", "rows", "marker_size_m", "marker_spacing_m", "dictionary", "first_id"};
  }
  return {};
}

TargetSpec parseSpec(const support::YamlNode& root) {
  TargetSpec spec;
  const std::string type = root.string("type");
  bool known = false;
  for (const TypeName& entry : kTypeNames)
    if (type == entry.name) spec.type = entry.type, known = true;
  if (!known)
    root.at("type").fail("'" + type + "' is not one of chessboard, circles, acircles, apriltag, charuco, aruco_grid");
  const bool tag_list = spec.type == TargetType::AprilTag && root.has("tags");
  root.checkKeys(knownKeys(spec.type, tag_list));
  if (!tag_list) {
    spec.cols = count(root, "cols");
    spec.rows = count(root, "rows");
  }
  switch (spec.type) {
    case TargetType::Chessboard:
      spec.square_size_m = length(root, "square_size_m");
      break;
    case TargetType::Circles:
    case TargetType::AsymmetricCircles:
      spec.spacing_m = length(root, "spacing_m");
      spec.diameter_m = length(root, "diameter_m");
      break;
    case TargetType::AprilTag:
      spec.family = familyName(root);
      spec.tag_size_m = length(root, "tag_size_m");
      if (tag_list) {
        spec.tags = tagList(root, spec);
      } else {
        // A single tag needs no spacing.
        if (spec.cols * spec.rows != 1 || root.has("tag_spacing_m")) spec.tag_spacing_m = length(root, "tag_spacing_m");
        spec.first_id = firstId(root);
      }
      break;
    case TargetType::Charuco:
      spec.square_size_m = length(root, "square_size_m");
      spec.marker_size_m = length(root, "marker_size_m");
      spec.dictionary = dictionaryName(root);
      break;
    case TargetType::ArucoGrid:
      spec.marker_size_m = length(root, "marker_size_m");
      spec.marker_spacing_m = length(root, "marker_spacing_m");
      spec.dictionary = dictionaryName(root);
      spec.first_id = firstId(root);
      break;
  }
  return spec;
}

}  // namespace

std::string targetTypeName(TargetType type) {
  for (const TypeName& entry : kTypeNames)
    if (entry.type == type) return entry.name;
  return "unknown";
}

Target::Target(TargetSpec spec) : spec_(std::move(spec)) {
  validateSpec(spec_);
  layout_ = squareLayout(spec_);
  points_ = featurePoints(spec_, layout_);
}

Target Target::fromFile(const std::filesystem::path& path) {
  const support::YamlFile file = support::YamlFile::load(path);
  const support::YamlNode& root = file.rootMap();
  const TargetSpec spec = detail::isKalibrTarget(root) ? detail::kalibrTargetSpec(root) : parseSpec(root);
  try {
    return Target(spec);
  } catch (const std::invalid_argument& error) {
    root.fail(error.what());  // a rule between keys (e.g. diameter_m < spacing_m)
  }
}

bool Target::isRotationallyAmbiguous() const {
  switch (spec_.type) {
    case TargetType::Chessboard:
      // The corner squares at both ends of the diagonal have the same colour when
      // cols + rows is even: the board then looks the same turned by 180°.
      return (spec_.cols + spec_.rows) % 2 == 0;
    case TargetType::Circles:
      return true;
    case TargetType::AsymmetricCircles:
      // Turned by 180°, row r's offset (r mod 2) lands on row rows-1-r: it matches only
      // when rows is even.
      return spec_.rows % 2 == 0;
    case TargetType::AprilTag:
    case TargetType::Charuco:
    case TargetType::ArucoGrid:
      return false;  // marker ids fix the frame
  }
  return false;
}

double Target::featureSpacing() const {
  switch (spec_.type) {
    case TargetType::Chessboard:
      return spec_.square_size_m;
    case TargetType::Circles:
      return spec_.spacing_m;
    case TargetType::AsymmetricCircles:
      return spec_.spacing_m * std::sqrt(2.0);
    case TargetType::AprilTag:
      return spec_.tag_size_m;
    case TargetType::Charuco:
      return spec_.square_size_m;
    case TargetType::ArucoGrid:
      return spec_.marker_size_m;
  }
  return 0.0;
}

int Target::tagIndex(int tag_id) const {
  for (std::size_t k = 0; k < layout_.size(); ++k)
    if (layout_[k].id == tag_id) return static_cast<int>(k);
  return -1;
}

std::string Target::yamlString() const {
  std::ostringstream out;
  out << "# mire target (lengths in metres); frame M and feature order: doc/targets.md\n";
  out << "type: " << targetTypeName(spec_.type) << "\n";
  if (spec_.type != TargetType::AprilTag || spec_.tags.empty()) {
    out << "cols: " << spec_.cols << "\n";
    out << "rows: " << spec_.rows << "\n";
  }
  switch (spec_.type) {
    case TargetType::Chessboard:
      out << "square_size_m: " << support::formatYamlNumber(spec_.square_size_m) << "\n";
      break;
    case TargetType::Circles:
    case TargetType::AsymmetricCircles:
      out << "spacing_m: " << support::formatYamlNumber(spec_.spacing_m) << "\n";
      out << "diameter_m: " << support::formatYamlNumber(spec_.diameter_m) << "\n";
      break;
    case TargetType::AprilTag:
      out << "family: " << spec_.family << "\n";
      out << "tag_size_m: " << support::formatYamlNumber(spec_.tag_size_m) << "\n";
      if (spec_.tags.empty()) {
        if (spec_.tag_spacing_m > 0.0)
          out << "tag_spacing_m: " << support::formatYamlNumber(spec_.tag_spacing_m) << "\n";
        out << "first_id: " << spec_.first_id << "\n";
      } else {
        out << "tags:\n";
        for (const TagPlacement& tag : spec_.tags)
          out << "  - {id: " << tag.id << ", x: " << support::formatYamlNumber(tag.x_m)
              << ", y: " << support::formatYamlNumber(tag.y_m) << "}\n";
      }
      break;
    case TargetType::Charuco:
      out << "square_size_m: " << support::formatYamlNumber(spec_.square_size_m) << "\n";
      out << "marker_size_m: " << support::formatYamlNumber(spec_.marker_size_m) << "\n";
      out << "dictionary: " << spec_.dictionary << "\n";
      break;
    case TargetType::ArucoGrid:
      out << "marker_size_m: " << support::formatYamlNumber(spec_.marker_size_m) << "\n";
      out << "marker_spacing_m: " << support::formatYamlNumber(spec_.marker_spacing_m) << "\n";
      out << "dictionary: " << spec_.dictionary << "\n";
      out << "first_id: " << spec_.first_id << "\n";
      break;
  }
  return out.str();
}

}  // namespace mire::metrology
