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

// "chessboard", "circles", "acircles", "apriltag" (the `type` key of target.yaml).
std::string targetTypeName(TargetType type);

struct TargetSpec {
  TargetType type = TargetType::Chessboard;
  int cols = 0;  // inner corners (chessboard), circles or tags otherwise
  int rows = 0;
  double square_size_m = 0.0;  // chessboard
  // Circle grids: symmetric: distance between neighbouring centres in a row or a column.
  // Asymmetric (OpenCV's layout, circle (c, r) at ((2c + r mod 2)·s, r·s)): s is the distance
  // between rows and half the distance between neighbours in a row; nearest neighbours
  // (diagonal) are s·√2 apart.
  double spacing_m = 0.0;
  double diameter_m = 0.0;     // circle grids
  std::string family;          // AprilTag family, e.g. "tag36h11"
  double tag_size_m = 0.0;     // AprilTag: black-border outer edge length
  double tag_spacing_m = 0.0;  // AprilTag: distance between neighbouring tag origins
  int first_id = 0;            // AprilTag: id of the tag at the origin, row-major after it
};

// Feature layout in frame M (z = 0 everywhere), index = what Detection::ids refer to:
// - chessboard: inner corner (c, r) has index r·cols + c, at (c·s, r·s);
// - circles: centre (c, r) has index r·cols + c, at (c·s, r·s);
// - acircles: centre (c, r) has index r·cols + c, at ((2c + r mod 2)·s, r·s);
// - apriltag: tag k (row-major, k = r·cols + c, id first_id + k) has its top-left outer
//   border corner at (c·tag_spacing, r·tag_spacing); its corners have indices 4k + j with
//   j = 0 top-left, 1 top-right, 2 bottom-right, 3 bottom-left (the tag seen upright from
//   the front, x right, y down), i.e. offsets (0,0), (t,0), (t,t), (0,t) with t = tag_size.

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
  // Smallest distance between two neighbouring features (m); sets sub-pixel windows.
  double featureSpacing() const;
  // AprilTag grids: the tag index k of a tag id, or -1 when the id is not on this target.
  int tagIndex(int tag_id) const;
  // Serialised target.yaml text.
  std::string yamlString() const;

 private:
  TargetSpec spec_;
  std::vector<Eigen::Vector3d> points_;
};

}  // namespace mire::metrology
