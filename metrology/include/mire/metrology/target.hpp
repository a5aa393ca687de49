#pragma once
// Planar calibration/measurement targets (target.yaml, ../shared/BRIEF.md §10).
// Frame M: origin at the first feature, x along `cols`, y along `rows`, z = x × y (into the
// board seen from the front), every feature at z = 0.
#include <Eigen/Core>

#include <filesystem>
#include <string>
#include <vector>

namespace mire::metrology {

enum class TargetType { Chessboard, Circles, AsymmetricCircles, AprilTag };

struct TargetSpec {
  TargetType type = TargetType::Chessboard;
  int cols = 0;  // inner corners (chessboard), circles or tags otherwise
  int rows = 0;
  double square_size_m = 0.0;  // chessboard
  double spacing_m = 0.0;      // circle grids: centre spacing (asymmetric: see README)
  double diameter_m = 0.0;     // circle grids
  std::string family;          // AprilTag family, e.g. "tag36h11"
  double tag_size_m = 0.0;     // AprilTag: black-border outer edge length
  double tag_spacing_m = 0.0;  // AprilTag: distance between neighbouring tag origins
  int first_id = 0;            // AprilTag: id of the tag at the origin, row-major after it
};

class Target {
 public:
  explicit Target(TargetSpec spec);  // validates; throws std::invalid_argument

  // Reads target.yaml; throws std::runtime_error naming the file and key.
  static Target fromFile(const std::filesystem::path& path);

  const TargetSpec& spec() const { return spec_; }
  // Every feature point in frame M; a detection refers to features by index here.
  const std::vector<Eigen::Vector3d>& points() const { return points_; }
  // True when the board looks the same turned by 180° (its frame is ambiguous).
  bool isRotationallyAmbiguous() const;
  // Serialised target.yaml text.
  std::string yamlString() const;

 private:
  TargetSpec spec_;
  std::vector<Eigen::Vector3d> points_;
};

}  // namespace mire::metrology
