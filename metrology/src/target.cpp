// Planar targets: validation, feature layout in frame M and target.yaml (BRIEF §10).
#include "mire/metrology/target.hpp"

#include "mire/metrology/apriltag_family.hpp"

#include <opencv2/core.hpp>

#include <cmath>
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
                                   {TargetType::AprilTag, "apriltag"}};

bool isPositiveFinite(double value) { return std::isfinite(value) && value > 0.0; }

void require(bool condition, const std::string& message) {
  if (!condition) throw std::invalid_argument(message);
}

void validateSpec(const TargetSpec& spec) {
  const int minimum = spec.type == TargetType::AprilTag ? 1 : 3;  // OpenCV's grid finders need 3
  require(spec.cols >= minimum && spec.rows >= minimum,
          "cols and rows must be at least " + std::to_string(minimum) + " for a " +
              targetTypeName(spec.type) + " target (got " + std::to_string(spec.cols) + " x " +
              std::to_string(spec.rows) + ")");
  switch (spec.type) {
    case TargetType::Chessboard:
      require(isPositiveFinite(spec.square_size_m), "square_size_m must be positive");
      break;
    case TargetType::Circles:
    case TargetType::AsymmetricCircles: {
      require(isPositiveFinite(spec.spacing_m), "spacing_m must be positive");
      require(isPositiveFinite(spec.diameter_m), "diameter_m must be positive");
      const double nearest =
          spec.type == TargetType::Circles ? spec.spacing_m : spec.spacing_m * std::sqrt(2.0);
      require(spec.diameter_m < nearest, "diameter_m must be smaller than the distance between neighbouring centres (" +
                                             std::to_string(nearest) + " m)");
      break;
    }
    case TargetType::AprilTag: {
      require(isPositiveFinite(spec.tag_size_m), "tag_size_m must be positive");
      require(isPositiveFinite(spec.tag_spacing_m) && spec.tag_spacing_m > spec.tag_size_m,
              "tag_spacing_m must be larger than tag_size_m (tags must not touch)");
      const detail::TagFamilyPtr family = detail::createTagFamily(spec.family);
      if (!family) {
        std::string names;
        for (const std::string& name : detail::tagFamilyNames()) names += (names.empty() ? "" : ", ") + name;
        throw std::invalid_argument("unknown AprilTag family '" + spec.family + "' (known: " + names + ")");
      }
      const long long last_id = static_cast<long long>(spec.first_id) + spec.cols * spec.rows - 1;
      require(spec.first_id >= 0 && last_id < static_cast<long long>(family->ncodes),
              "tag ids " + std::to_string(spec.first_id) + ".." + std::to_string(last_id) + " do not exist in " +
                  spec.family + " (ids 0.." + std::to_string(family->ncodes - 1) + ")");
      break;
    }
  }
}

std::vector<Eigen::Vector3d> featurePoints(const TargetSpec& spec) {
  std::vector<Eigen::Vector3d> points;
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
        case TargetType::AprilTag: {
          const Eigen::Vector3d origin(c * spec.tag_spacing_m, r * spec.tag_spacing_m, 0.0);
          const double t = spec.tag_size_m;
          points.push_back(origin);
          points.push_back(origin + Eigen::Vector3d(t, 0.0, 0.0));
          points.push_back(origin + Eigen::Vector3d(t, t, 0.0));
          points.push_back(origin + Eigen::Vector3d(0.0, t, 0.0));
          break;
        }
      }
    }
  }
  return points;
}

// Reading one key of target.yaml with errors naming the file and the key.
class SpecReader {
 public:
  SpecReader(const cv::FileStorage& storage, std::string file) : storage_(storage), file_(std::move(file)) {}

  bool has(const char* key) const { return !storage_[key].empty(); }

  void fail(const char* key, const std::string& what) const {
    throw std::runtime_error(file_ + ": key '" + key + "': " + what);
  }

  std::string text(const char* key) const {
    const cv::FileNode node = storage_[key];
    if (node.empty()) fail(key, "missing");
    if (!node.isString()) fail(key, "must be a string");
    return node.string();
  }
  int integer(const char* key) const {
    const cv::FileNode node = storage_[key];
    if (node.empty()) fail(key, "missing");
    if (!node.isInt()) fail(key, "must be an integer");
    return static_cast<int>(node);
  }
  double real(const char* key) const {
    const cv::FileNode node = storage_[key];
    if (node.empty()) fail(key, "missing");
    if (!node.isReal() && !node.isInt()) fail(key, "must be a number");
    const double value = static_cast<double>(node);
    if (!isPositiveFinite(value)) fail(key, "must be a positive length in metres");
    return value;
  }

 private:
  const cv::FileStorage& storage_;
  std::string file_;
};

}  // namespace

std::string targetTypeName(TargetType type) {
  for (const TypeName& entry : kTypeNames)
    if (entry.type == type) return entry.name;
  return "unknown";
}

Target::Target(TargetSpec spec) : spec_(std::move(spec)) {
  validateSpec(spec_);
  points_ = featurePoints(spec_);
}

Target Target::fromFile(const std::filesystem::path& path) {
  const std::string file = path.string();
  cv::FileStorage storage;
  try {
    if (!std::filesystem::is_regular_file(path)) throw std::runtime_error(file + ": cannot open target file");
    storage.open(file, cv::FileStorage::READ | cv::FileStorage::FORMAT_YAML);
  } catch (const cv::Exception& error) {
    throw std::runtime_error(file + ": not a valid YAML target file (" + error.err + ")");
  }
  if (!storage.isOpened()) throw std::runtime_error(file + ": cannot open target file");
  const SpecReader reader(storage, file);

  TargetSpec spec;
  const std::string type = reader.text("type");
  bool known = false;
  for (const TypeName& entry : kTypeNames)
    if (type == entry.name) spec.type = entry.type, known = true;
  if (!known) reader.fail("type", "'" + type + "' is not one of chessboard, circles, acircles, apriltag");
  spec.cols = reader.integer("cols");
  spec.rows = reader.integer("rows");
  switch (spec.type) {
    case TargetType::Chessboard:
      spec.square_size_m = reader.real("square_size_m");
      break;
    case TargetType::Circles:
    case TargetType::AsymmetricCircles:
      spec.spacing_m = reader.real("spacing_m");
      spec.diameter_m = reader.real("diameter_m");
      break;
    case TargetType::AprilTag:
      spec.family = reader.text("family");
      spec.tag_size_m = reader.real("tag_size_m");
      spec.tag_spacing_m = reader.real("tag_spacing_m");
      spec.first_id = reader.has("first_id") ? reader.integer("first_id") : 0;
      break;
  }
  try {
    return Target(spec);
  } catch (const std::invalid_argument& error) {
    throw std::runtime_error(file + ": " + error.what());
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
      return false;  // tag ids fix the frame
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
  }
  return 0.0;
}

int Target::tagIndex(int tag_id) const {
  if (spec_.type != TargetType::AprilTag) return -1;
  const int index = tag_id - spec_.first_id;
  return index >= 0 && index < spec_.cols * spec_.rows ? index : -1;
}

std::string Target::yamlString() const {
  std::ostringstream out;
  out.precision(17);
  out << "%YAML:1.0\n---\n";
  out << "# mire target (lengths in metres); frame M: origin at the first feature, x along cols, y along rows\n";
  out << "type: " << targetTypeName(spec_.type) << "\n";
  out << "cols: " << spec_.cols << "\n";
  out << "rows: " << spec_.rows << "\n";
  switch (spec_.type) {
    case TargetType::Chessboard:
      out << "square_size_m: " << spec_.square_size_m << "\n";
      break;
    case TargetType::Circles:
    case TargetType::AsymmetricCircles:
      out << "spacing_m: " << spec_.spacing_m << "\n";
      out << "diameter_m: " << spec_.diameter_m << "\n";
      break;
    case TargetType::AprilTag:
      out << "family: " << spec_.family << "\n";
      out << "tag_size_m: " << spec_.tag_size_m << "\n";
      out << "tag_spacing_m: " << spec_.tag_spacing_m << "\n";
      out << "first_id: " << spec_.first_id << "\n";
      break;
  }
  return out.str();
}

}  // namespace mire::metrology
