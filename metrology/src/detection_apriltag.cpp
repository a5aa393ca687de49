// AprilTag grids through AprilTag 3 (layout: doc/targets.md; detection.hpp).
#include "detection_internal.hpp"
#include "mire/metrology/apriltag_family.hpp"

#include <apriltag/apriltag.h>
#include <apriltag/common/zarray.h>

#include <algorithm>
#include <array>
#include <memory>
#include <set>
#include <stdexcept>

namespace mire::metrology::detail {

struct DetectorDeleter {
  void operator()(apriltag_detector_t* detector) const { apriltag_detector_destroy(detector); }
};
struct DetectionsDeleter {
  void operator()(zarray_t* detections) const { apriltag_detections_destroy(detections); }
};

// AprilTag puts integer coordinates at pixel corners (pixel (i, j) covers [i, i+1) ×
// [j, j+1)); OpenCV at pixel centres. Checked against AprilTag's own reference detections
// (tests/metrology/test_detection_apriltag.cpp).
constexpr double kAprilTagToOpenCV = -0.5;

// AprilTag's corner k (p[k], counter-clockwise in the image for an upright tag, starting
// bottom-left) -> this target's corner order (top-left, top-right, bottom-right,
// bottom-left, clockwise in the image; target.hpp).
constexpr int kTargetCornerOfAprilTagCorner[4] = {3, 2, 1, 0};

}  // namespace mire::metrology::detail

namespace mire::metrology {

std::vector<TagDetection> detectAprilTags(const cv::Mat& gray, const std::string& family_name, bool refine_edges) {
  if (gray.empty() || gray.type() != CV_8UC1) throw std::invalid_argument("detectAprilTags: needs an 8-bit grey image");
  const detail::TagFamilyPtr family = detail::createTagFamily(family_name);
  if (!family) throw std::invalid_argument("unknown AprilTag family '" + family_name + "'");
  const std::unique_ptr<apriltag_detector_t, detail::DetectorDeleter> detector(apriltag_detector_create());
  apriltag_detector_add_family_bits(detector.get(), family.get(), 2);
  // Full resolution for quads (decimation costs corner accuracy and misses small tags).
  detector->quad_decimate = 1.0f;
  detector->quad_sigma = 0.0f;
  detector->refine_edges = refine_edges;
  detector->nthreads = 1;

  cv::Mat owned = gray.clone();  // AprilTag takes a non-const image
  image_u8_t image{owned.cols, owned.rows, static_cast<int32_t>(owned.step[0]), owned.data};
  const std::unique_ptr<zarray_t, detail::DetectionsDeleter> detections(apriltag_detector_detect(detector.get(), &image));
  std::vector<TagDetection> tags;
  for (int i = 0; i < zarray_size(detections.get()); ++i) {
    apriltag_detection_t* detection = nullptr;
    zarray_get(detections.get(), i, &detection);
    TagDetection tag;
    tag.id = detection->id;
    tag.hamming = detection->hamming;
    tag.decision_margin = detection->decision_margin;
    for (int k = 0; k < 4; ++k)
      tag.corners[detail::kTargetCornerOfAprilTagCorner[k]] = Eigen::Vector2d(
          detection->p[k][0] + detail::kAprilTagToOpenCV, detection->p[k][1] + detail::kAprilTagToOpenCV);
    tags.push_back(tag);
  }
  return tags;
}

namespace detail {

namespace {

// The layout ids of a detection's tags (features 4k..4k+3 are tag k's corners).
std::set<int> tagIds(const Target& target, const Detection& detection) {
  std::set<int> ids;
  for (const int feature : detection.ids) ids.insert(target.tagLayout()[static_cast<std::size_t>(feature / 4)].id);
  return ids;
}

std::string idList(const std::set<int>& ids) {
  std::string text;
  for (const int id : ids) text += (text.empty() ? "" : ", ") + std::to_string(id);
  return text;
}

}  // namespace

std::vector<Detection> detectAprilTagCandidates(const Target& target, const cv::Mat& gray,
                                                const DetectionOptions& options) {
  // Repeated ids and ids outside the layout are sorted out by the layout's geometry
  // (detection_tag_layout.cpp).
  std::vector<SquareInstance> instances;
  std::set<int> exact;
  for (const TagDetection& tag : detectAprilTags(gray, target.spec().family, options.subpixel)) {
    instances.push_back({tag.id, tag.corners});
    if (tag.hamming == 0) exact.insert(tag.id);
  }
  // A group of tags that all needed corrected bits is refused: a family with a small Hamming
  // distance (tag16h5: 5, up to 2 bits corrected) decodes the black squares of another family's
  // tags as valid ids, and a single such tag fits its own four corners exactly (reprojection RMS
  // 0.07 px on rendered tag36h11 images read as tag16h5, for a pose 0.24 m and 90° off).
  std::vector<Detection> candidates;
  std::set<int> refused;
  for (Detection& candidate : layoutDetections(target, instances, options, "tags")) {
    const std::set<int> ids = tagIds(target, candidate);
    if (std::any_of(ids.begin(), ids.end(), [&exact](int id) { return exact.count(id) > 0; }))
      candidates.push_back(std::move(candidate));
    else
      refused.insert(ids.begin(), ids.end());
  }
  if (candidates.empty()) {
    Detection none;
    none.reason = "no tag of the target (" + target.spec().family + ") found";
    if (!refused.empty())
      none.reason = "no tag of the target (" + target.spec().family +
                    ") decoded exactly: the tags fitting its layout (ids " + idList(refused) +
                    ") all needed corrected bits: the image probably shows another tag family or layout";
    candidates.push_back(none);
  }
  return candidates;
}

Detection detectAprilTagGrid(const Target& target, const cv::Mat& gray, const DetectionOptions& options) {
  return detectAprilTagCandidates(target, gray, options).front();
}

}  // namespace detail
}  // namespace mire::metrology
