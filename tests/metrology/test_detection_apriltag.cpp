// AprilTag detection: against AprilTag's own reference detections on real photos, and
// against the exact ground truth of synthetic renders (pixel convention, corner order).
#include "mire/metrology/detection.hpp"

#include "synthetic_board.hpp"
#include "test_support.hpp"

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include <cstdio>
#include <fstream>

namespace mire::metrology {
namespace {

struct ReferenceTag {
  int id = -1;
  double p[4][2];  // AprilTag's corners, AprilTag's pixel convention and order
};

std::vector<ReferenceTag> readReference(const std::filesystem::path& path) {
  std::vector<ReferenceTag> tags;
  std::ifstream in(path);
  std::string line;
  while (std::getline(in, line)) {
    ReferenceTag tag;
    if (std::sscanf(line.c_str(), "%d, (%lf %lf), (%lf %lf), (%lf %lf), (%lf %lf)", &tag.id, &tag.p[0][0], &tag.p[0][1],
                    &tag.p[1][0], &tag.p[1][1], &tag.p[2][0], &tag.p[2][1], &tag.p[3][0], &tag.p[3][1]) == 9)
      tags.push_back(tag);
  }
  return tags;
}

// Largest corner coordinate difference between a detection and a reference (AprilTag's own test
// compares each coordinate within 0.1 px), after converting the detection back to AprilTag's
// conventions (+0.5 px; p[k] = our corner 3 − k).
double worstCornerDistance(const TagDetection& detection, const ReferenceTag& reference) {
  double worst = 0.0;
  for (int k = 0; k < 4; ++k) {
    const Eigen::Vector2d ours = detection.corners[3 - k] + Eigen::Vector2d(0.5, 0.5);
    worst = std::max(worst, (ours - Eigen::Vector2d(reference.p[k][0], reference.p[k][1])).cwiseAbs().maxCoeff());
  }
  return worst;
}

TEST(DetectionAprilTag, MatchesAprilTagsReferenceDetectionsOnPhotos) {
  MIRE_REQUIRE_SHARED("datasets/external/apriltag-photos");
  const auto folder = test::sharedDir() / "datasets/external/apriltag-photos";
  int references = 0, within_tenth = 0;
  double worst = 0.0;
  for (const char* name : {"33369213973_9d9bb4cc96_c", "34085369442_304b6bafd9_c", "34139872896_defdb2f8d9_c"}) {
    const cv::Mat gray = cv::imread((folder / (std::string(name) + ".jpg")).string(), cv::IMREAD_GRAYSCALE);
    ASSERT_FALSE(gray.empty()) << name;
    const std::vector<ReferenceTag> reference = readReference(folder / (std::string(name) + ".txt"));
    ASSERT_FALSE(reference.empty()) << name;
    // The reference was made with quad_decimate = 1 and refine_edges = 0.
    const std::vector<TagDetection> detections = detectAprilTags(gray, "tag36h11", false);
    EXPECT_EQ(detections.size(), reference.size()) << name;
    for (const ReferenceTag& tag : reference) {
      double best = std::numeric_limits<double>::infinity();
      for (const TagDetection& detection : detections)
        if (detection.id == tag.id) best = std::min(best, worstCornerDistance(detection, tag));
      ++references;
      if (best <= 0.1) ++within_tenth;
      worst = std::max(worst, best);
    }
  }
  // AprilTag's own test accepts 0.1 px per coordinate. Measured: 44 of 47 tags, worst 0.139 px
  // (the same 44 with the Euclidean corner distance, worst 0.14 px).
  // One tag is OpenCV's JPEG decoder (±1 grey level against AprilTag's pjpeg on 2 % of the
  // pixels); two differ by 0.11 and 0.14 px even with pjpeg and the bare library: Debian's
  // AprilTag 3.3.0 against the build that wrote the reference (doc/targets.md).
  std::cout << "AprilTag photos: " << within_tenth << " of " << references << " tags within 0.1 px, worst corner "
            << worst << " px\n";
  EXPECT_GE(within_tenth, references * 9 / 10);
  EXPECT_LT(worst, 0.2);
}

Target tagGrid() {
  TargetSpec spec;
  spec.type = TargetType::AprilTag;
  spec.cols = 3;
  spec.rows = 2;
  spec.family = "tag36h11";
  spec.tag_size_m = 0.04;
  spec.tag_spacing_m = 0.05;
  spec.first_id = 3;
  return Target(spec);
}

TEST(DetectionAprilTag, SyntheticGridCornersHaveNoConventionBias) {
  const Target target = tagGrid();
  Eigen::Vector2d bias = Eigen::Vector2d::Zero();
  double sum_squared = 0.0;
  std::size_t count = 0;
  for (int k = 0; k < 3; ++k) {
    test::SyntheticView view;
    view.seed = 40 + k;
    view.blur_sigma_px = 0.7;
    view.camera_T_target = test::lookAtTarget(target, 0.35, 0.3 * (k - 1), 0.2, 1.2 * k);  // also upside down
    const Detection detection = detectTarget(target, test::renderSynthetic(target, view));
    ASSERT_TRUE(detection.found) << detection.reason;
    ASSERT_EQ(detection.size(), target.points().size()) << detection.reason;
    for (std::size_t i = 0; i < detection.size(); ++i) {
      const Eigen::Vector2d error = detection.pixels[i] - view.project(target.points()[detection.ids[i]]);
      bias += error;
      sum_squared += error.squaredNorm();
      ++count;
    }
  }
  bias /= static_cast<double>(count);
  const double rms = std::sqrt(sum_squared / count);
  std::cout << "AprilTag synthetic: corner RMS " << rms << " px, mean offset (" << bias.x() << ", " << bias.y()
            << ") px\n";
  // A wrong pixel convention would show as a 0.5 px mean offset; a wrong corner order as
  // errors of a tag's size.
  EXPECT_LT(std::abs(bias.x()), 0.03);
  EXPECT_LT(std::abs(bias.y()), 0.03);
  EXPECT_LT(rms, 0.1);
}

TEST(DetectionAprilTag, PartialGridsAreFoundAndSaySo) {
  const Target target = tagGrid();
  test::SyntheticView view;
  // Shifted so that the left column of tags leaves the image.
  view.camera_T_target = test::lookAtTarget(target, 0.3, 0.1, 0.1, 0.0, Eigen::Vector2d(-0.115, 0.0));
  const cv::Mat image = test::renderSynthetic(target, view);
  const Detection partial = detectTarget(target, image);
  ASSERT_TRUE(partial.found) << partial.reason;
  EXPECT_EQ(partial.size(), 16u);
  EXPECT_NE(partial.reason.find("4 of 6 tags"), std::string::npos) << partial.reason;
  for (const int id : partial.ids) EXPECT_NE(id / 4 % 3, 0) << "tag of the left column reported";
  DetectionOptions strict;
  strict.allow_partial = false;
  EXPECT_FALSE(detectTarget(target, image, strict).found);
  // Re-detection in another image of the same pose keeps the same tags.
  view.seed = 2;
  const Detection again = refineDetection(target, test::renderSynthetic(target, view), partial);
  EXPECT_EQ(again.ids, partial.ids);
  EXPECT_THROW(detectAprilTags(image, "tag99h9", true), std::invalid_argument);
}

}  // namespace
}  // namespace mire::metrology
