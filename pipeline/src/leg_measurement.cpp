#include "mire/pipeline/leg_measurement.hpp"

#include "mire/support/constants.hpp"

#include "mire/mechanism/pose.hpp"
#include "mire/metrology/leg_axis.hpp"
#include "mire/pipeline/identify.hpp"
#include "mire/pipeline/image_folders.hpp"
#include "mire/support/progress.hpp"
#include "mire/support/yaml.hpp"

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <array>
#include <cmath>
#include <map>
#include <stdexcept>

namespace mire::pipeline {
namespace fs = std::filesystem;
namespace {

Eigen::Vector3d vector3(const support::YamlNode& node, const std::string& key, support::YamlRange range) {
  const std::vector<double> values = node.at(key).asDoubles(range);
  if (values.size() != 3) node.at(key).fail("expected 3 numbers, got " + std::to_string(values.size()));
  return {values[0], values[1], values[2]};
}

// The segments of the legs in the camera frame at this pose: nominal FKM from the joints, then
// the approximate camera placement.
std::vector<mechanism::LegSegment> predictedSegments(const mechanism::RegisteredModel& model, const LegsSpec& spec,
                                                     const Eigen::VectorXd& joints) {
  const Eigen::VectorXd geometric = model.nominal.values();
  const mechanism::FkmResult fkm =
      model.mechanism->forwardKinematics(geometric, joints, model.mechanism->referencePose(geometric));
  if (!fkm.converged)
    throw std::runtime_error("the nominal FKM did not converge from the joints (" + fkm.message + ")");
  std::vector<mechanism::LegSegment> segments = model.mechanism->legSegments(geometric, fkm.bTe);
  if (segments.empty()) throw std::runtime_error("the nominal model cannot reach the pose of the joints");
  const Eigen::Isometry3d camera_T_base = spec.base_T_camera.inverse();
  for (mechanism::LegSegment& s : segments) {
    s.from = camera_T_base * s.from;
    s.to = camera_T_base * s.to;
  }
  return segments;
}

void drawContours(const fs::path& file, const cv::Mat& grey, const std::vector<metrology::LegContours>& legs) {
  cv::Mat image;
  cv::cvtColor(grey, image, cv::COLOR_GRAY2BGR);
  for (const metrology::LegContours& leg : legs)
    for (const metrology::ContourFit& contour : leg.contours) {
      for (const Eigen::Vector2d& p : contour.inliers_px)
        cv::circle(image, cv::Point(static_cast<int>(std::lround(p.x())), static_cast<int>(std::lround(p.y()))), 1,
                   cv::Scalar(0, 0, 255), cv::FILLED);
      if (contour.inliers_px.size() > 1)
        cv::line(image, cv::Point2d(contour.inliers_px.front().x(), contour.inliers_px.front().y()),
                 cv::Point2d(contour.inliers_px.back().x(), contour.inliers_px.back().y()), cv::Scalar(0, 255, 0), 1,
                 cv::LINE_AA);
    }
  cv::imwrite(file.string(), image);
}

void measurePose(const calibration::Camera& camera, const LegsSpec& spec, const mechanism::RegisteredModel& model,
                 const Eigen::VectorXd& joints, const fs::path& folder, const fs::path& debug_dir, PoseLegs* pose) {
  const std::vector<mechanism::LegSegment> segments = predictedSegments(model, spec, joints);
  const std::vector<fs::path> images = poseImages(folder);
  pose->images = static_cast<int>(images.size());
  if (images.empty()) throw std::runtime_error("no image files in " + folder.string());
  metrology::LegContourOptions options;
  options.search_px = spec.search_px;
  std::vector<std::vector<std::array<metrology::ContourFit, 2>>> fits(segments.size());
  std::vector<std::string> first_error(segments.size());
  for (std::size_t i = 0; i < images.size(); ++i) {
    const cv::Mat grey = cv::imread(images[i].string(), cv::IMREAD_GRAYSCALE);
    if (grey.empty()) throw std::runtime_error(images[i].string() + ": unreadable image");
    if (grey.cols != camera.width || grey.rows != camera.height)
      throw std::runtime_error(images[i].string() + ": " + std::to_string(grey.cols) + "x" + std::to_string(grey.rows) +
                               " image, the camera's is " + std::to_string(camera.width) + "x" +
                               std::to_string(camera.height));
    const metrology::EdgeImage image = metrology::EdgeImage::of(grey);
    std::vector<metrology::LegContours> found;
    for (std::size_t leg = 0; leg < segments.size(); ++leg) {
      found.push_back(
          metrology::measureLegContours(image, camera, segments[leg].from, segments[leg].to, spec.radius_m, options));
      if (found.back().ok)
        fits[leg].push_back(found.back().contours);
      else if (first_error[leg].empty())
        first_error[leg] = images[i].filename().string() + ": " + found.back().error;
    }
    if (i == 0 && !debug_dir.empty()) drawContours(debug_dir / (pose->pose_id + ".png"), grey, found);
  }
  for (std::size_t leg = 0; leg < segments.size(); ++leg) {
    if (fits[leg].empty()) {
      pose->problems.push_back("leg " + std::to_string(leg + 1) + " not measured (" + first_error[leg] + ")");
      continue;
    }
    try {
      const metrology::LegAxis axis = metrology::averageLegAxis(fits[leg], spec.radius_m);
      pose->legs.push_back({pose->pose_id, static_cast<int>(leg), axis.axis, axis.covariance});
      pose->spread_ratios.push_back(axis.spread_ratio);
    } catch (const std::invalid_argument& e) {
      pose->problems.push_back("leg " + std::to_string(leg + 1) + " not measured (" + e.what() + ")");
    }
  }
}

}  // namespace

LegsSpec readLegsYaml(const fs::path& legs_yaml) {
  const support::YamlFile file = support::YamlFile::load(legs_yaml);
  const support::YamlNode& root = file.rootMap();
  root.checkKeys({"model", "radius_mm", "base_T_camera", "search_px"});
  LegsSpec spec;
  spec.model = root.string("model");
  spec.radius_m = root.number("radius_mm", {0.1, 500.0}) * 1e-3;
  spec.search_px = root.optionalNumber("search_px", {2.0, 200.0}).value_or(spec.search_px);
  const support::YamlNode placement = root.at("base_T_camera");
  placement.requireMap();
  placement.checkKeys({"t_mm", "r_deg"});
  spec.base_T_camera.translation() = vector3(placement, "t_mm", {-1e5, 1e5}) * 1e-3;
  spec.base_T_camera.linear() =
      mechanism::fromRotationVector(vector3(placement, "r_deg", {-360.0, 360.0}) * support::kRadiansPerDegree);
  const std::string where = root.at("model").where() + ": key 'model': ";
  try {
    if (chooseModel(spec.model, "").registered().mechanism->legCount() == 0)
      throw std::invalid_argument("model '" + spec.model + "' has no observable legs (doc/legs.md)");
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(where + e.what());
  }
  return spec;
}

std::vector<PoseLegs> measureLegFolders(const calibration::Camera& camera, const LegsSpec& spec,
                                        const std::vector<mechanism::JointRow>& joints, const fs::path& poses_dir,
                                        int threads, const fs::path& debug_dir) {
  const mechanism::RegisteredModel model = chooseModel(spec.model, "").registered();
  std::map<std::string, Eigen::VectorXd> joints_of;
  for (const mechanism::JointRow& row : joints) joints_of[row.pose_id] = row.joints;
  const auto folders = poseFolders(poses_dir);
  std::vector<PoseLegs> poses(folders.size());
  support::Progress progress("measuring legs", folders.size());
  parallelForEach(folders.size(), threads, [&](std::size_t i) {
    PoseLegs& pose = poses[i];
    pose.pose_id = folders[i].first;
    try {
      const auto row = joints_of.find(pose.pose_id);
      if (row == joints_of.end()) throw std::runtime_error("no row in the joints file");
      measurePose(camera, spec, model, row->second, folders[i].second, debug_dir, &pose);
    } catch (const cv::Exception& e) {
      pose.problems.push_back(folders[i].second.string() + ": OpenCV failed (" + e.err + ")");
    } catch (const std::exception& e) {
      pose.problems.push_back(e.what());
    }
    progress.advance();
  });
  return poses;
}

}  // namespace mire::pipeline
