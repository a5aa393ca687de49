#pragma once
// Planar calibration/measurement targets (target.yaml, doc/file-formats.md, doc/targets.md).
// Frame M: origin at the first feature, x along `cols`, y along `rows`, z = x × y (into the
// board seen from the front), every feature at z = 0.
#include <Eigen/Core>

#include <filesystem>
#include <string>
#include <vector>

namespace mire::metrology {

enum class TargetType { Chessboard, Circles, AsymmetricCircles, AprilTag, Charuco, ArucoGrid };

// "chessboard", "circles", "acircles", "apriltag", "charuco", "aruco_grid" (the `type` key of
// target.yaml).
std::string targetTypeName(TargetType type);

// One tag of a free AprilTag layout: its id and the top-left outer border corner of the
// upright tag in frame M (metres).
struct TagPlacement {
  int id = -1;
  double x_m = 0.0;
  double y_m = 0.0;
};

struct TargetSpec {
  TargetType type = TargetType::Chessboard;
  // Inner corners (chessboard), circles, tags or markers (aruco_grid); squares (charuco, as
  // OpenCV's squaresX, squaresY). Unused (0) for an AprilTag target given by `tags`.
  int cols = 0;
  int rows = 0;
  double square_size_m = 0.0;  // chessboard, charuco
  // Circle grids: symmetric: distance between neighbouring centres in a row or a column.
  // Asymmetric (OpenCV's layout, circle (c, r) at ((2c + r mod 2)·s, r·s)): s is the distance
  // between rows and half the distance between neighbours in a row; nearest neighbours
  // (diagonal) are s·√2 apart.
  double spacing_m = 0.0;
  double diameter_m = 0.0;     // circle grids
  std::string family;          // AprilTag family, e.g. "tag36h11"
  double tag_size_m = 0.0;     // AprilTag: black-border outer edge length
  double tag_spacing_m = 0.0;  // AprilTag: distance between neighbouring tag origins
  int first_id = 0;            // AprilTag, aruco_grid: id of the tag at the origin, row-major after it
  // Free AprilTag layout (doc/targets.md); empty = the regular grid given by cols, rows,
  // tag_spacing_m and first_id.
  std::vector<TagPlacement> tags;
  std::string dictionary;         // charuco, aruco_grid: OpenCV's predefined name, e.g. "DICT_6X6_250"
  double marker_size_m = 0.0;     // charuco, aruco_grid: marker black-border outer edge length
  double marker_spacing_m = 0.0;  // aruco_grid: gap between neighbouring markers (OpenCV's markerSeparation)
};

// Feature layout in frame M (z = 0 everywhere), index = what Detection::ids refer to:
// - chessboard: inner corner (c, r) has index r·cols + c, at (c·s, r·s);
// - circles: centre (c, r) has index r·cols + c, at (c·s, r·s);
// - acircles: centre (c, r) has index r·cols + c, at ((2c + r mod 2)·s, r·s);
// - apriltag: tag k (row-major, k = r·cols + c, id first_id + k) has its top-left outer
//   border corner at (c·tag_spacing, r·tag_spacing); its corners have indices 4k + j with
//   j = 0 top-left, 1 top-right, 2 bottom-right, 3 bottom-left (the tag seen upright from
//   the front, x right, y down), i.e. offsets (0,0), (t,0), (t,t), (0,t) with t = tag_size.
//   With a `tags` list, tag k is the k-th entry, its top-left corner at (x_m, y_m).
// - charuco (OpenCV's CharucoBoard object points and corner ids): the origin is the board's
//   outer corner at the dark square (0, 0), not a feature; inner corner (c, r), c < cols − 1,
//   r < rows − 1, has index r·(cols − 1) + c, at ((c + 1)·s, (r + 1)·s).
// - aruco_grid (OpenCV's GridBoard object points): marker k (row-major, id first_id + k) has
//   its top-left corner at (c·p, r·p), p = marker_size + marker_spacing; corners 4k + j as
//   for AprilTags (OpenCV's marker corner order is the same).

class Target {
 public:
  explicit Target(TargetSpec spec);  // validates; throws std::invalid_argument

  // Reads target.yaml; throws std::runtime_error naming the file, the line and the key.
  static Target fromFile(const std::filesystem::path& path);

  const TargetSpec& spec() const { return spec_; }
  // Every feature point in frame M; a detection refers to features by index here.
  const std::vector<Eigen::Vector3d>& points() const { return points_; }
  // True when the board looks the same turned by 180° (its frame is ambiguous).
  bool isRotationallyAmbiguous() const;
  // Smallest distance between two neighbouring features (m); sets sub-pixel windows.
  double featureSpacing() const;
  // AprilTag targets and ArUco grids: the tag index k of a tag id, or -1 when the id is not on
  // this target.
  int tagIndex(int tag_id) const;
  // AprilTag targets: every tag's placement (the regular grid expanded, row-major).
  const std::vector<TagPlacement>& tagLayout() const { return layout_; }
  // Serialised target.yaml text.
  std::string yamlString() const;

 private:
  TargetSpec spec_;
  std::vector<Eigen::Vector3d> points_;
  std::vector<TagPlacement> layout_;  // AprilTag: tag k's placement; ArUco grid: marker k's
};

}  // namespace mire::metrology
