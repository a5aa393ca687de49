// Simulation specs and the image sets they describe (simulation.hpp).
#include "mire/datasets/simulation.hpp"

#include "mire/calibration/camera_io.hpp"
#include "mire/metrology/pose_types.hpp"
#include "mire/support/atomic_file.hpp"

#include <opencv2/core.hpp>
#include <opencv2/core/utility.hpp>
#include <opencv2/imgcodecs.hpp>

#include <cmath>
#include <cstdio>
#include <functional>
#include <mutex>
#include <sstream>
#include <stdexcept>

namespace mire::datasets {
namespace {


// Reads the keys of one spec node with errors naming the file and the full key.
class NodeReader {
 public:
  NodeReader(cv::FileNode node, std::string file, std::string prefix)
      : node_(std::move(node)), file_(std::move(file)), prefix_(std::move(prefix)) {}

  [[noreturn]] void fail(const std::string& key, const std::string& what) const {
    throw std::runtime_error(file_ + ": key '" + prefix_ + key + "': " + what);
  }
  bool has(const std::string& key) const { return !node_.empty() && node_.isMap() && !node_[key].empty(); }
  cv::FileNode node(const std::string& key) const { return has(key) ? node_[key] : cv::FileNode(); }
  NodeReader child(const std::string& key) const { return NodeReader(node(key), file_, prefix_ + key + "."); }

  double number(const std::string& key, double fallback, double minimum, double maximum) const {
    if (!has(key)) return fallback;
    const cv::FileNode value = node_[key];
    if (!value.isReal() && !value.isInt()) fail(key, "must be a number");
    const double result = static_cast<double>(value);
    if (!(result >= minimum && result <= maximum))
      fail(key, "must be between " + std::to_string(minimum) + " and " + std::to_string(maximum));
    return result;
  }
  int integer(const std::string& key, int fallback, int minimum, int maximum) const {
    if (!has(key)) return fallback;
    if (!node_[key].isInt()) fail(key, "must be an integer");
    const int result = static_cast<int>(node_[key]);
    if (result < minimum || result > maximum)
      fail(key, "must be between " + std::to_string(minimum) + " and " + std::to_string(maximum));
    return result;
  }
  bool flag(const std::string& key, bool fallback) const { return integer(key, fallback ? 1 : 0, 0, 1) == 1; }
  std::string text(const std::string& key, const std::string& fallback) const {
    if (!has(key)) return fallback;
    if (!node_[key].isString()) fail(key, "must be a string");
    return node_[key].string();
  }
  std::vector<double> numbers(const std::string& key, std::size_t size) const {
    const cv::FileNode value = node_[key];
    if (!value.isSeq()) fail(key, "must be a list of numbers");
    std::vector<double> result;
    for (const cv::FileNode& item : value) {
      if (!item.isReal() && !item.isInt()) fail(key, "must be a list of numbers");
      result.push_back(static_cast<double>(item));
    }
    if (size != 0 && result.size() != size) fail(key, "must have " + std::to_string(size) + " values");
    return result;
  }

 private:
  cv::FileNode node_;
  std::string file_;
  std::string prefix_;
};

calibration::Camera readInlineCamera(const NodeReader& camera, const std::string& file) {
  const int width = camera.integer("image_width", 0, 1, 1 << 16);
  const int height = camera.integer("image_height", 0, 1, 1 << 16);
  if (width == 0 || height == 0) camera.fail("image_width", "inline camera needs image_width and image_height");
  cv::Mat matrix, distortion;
  camera.node("camera_matrix") >> matrix;
  camera.node("distortion_coefficients") >> distortion;
  if (matrix.rows != 3 || matrix.cols != 3) camera.fail("camera_matrix", "must be a 3x3 matrix");
  matrix.convertTo(matrix, CV_64F);
  distortion.convertTo(distortion, CV_64F);
  const std::vector<double> coefficients(distortion.begin<double>(), distortion.end<double>());
  try {
    return calibration::cameraFromOpenCV(width, height, matrix.at<double>(0, 0), matrix.at<double>(1, 1),
                                         matrix.at<double>(0, 2), matrix.at<double>(1, 2), coefficients);
  } catch (const std::invalid_argument& error) {
    throw std::runtime_error(file + ": key 'camera': " + error.what());
  }
}

// The noise seed of image `image` of view/pose `item`: distinct, reproducible streams.
std::uint64_t noiseSeed(std::uint64_t seed, std::size_t item, std::size_t image) {
  std::uint64_t z = seed * 0x9E3779B97F4A7C15ULL + item * 0xBF58476D1CE4E5B9ULL + image * 0x94D049BB133111EBULL + 1;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

void writePng(const std::filesystem::path& path, const cv::Mat& image) {
  support::writeAtomically(path, [&](const std::filesystem::path& temporary) { return cv::imwrite(temporary.string(), image); });
}

// Renders every item (a view or a pose) once and writes its noisy images, items in parallel
// (issue 18: the PNG encoding, single-threaded in OpenCV, cost more than the render). Each
// item's render runs serially inside its worker (nested parallel_for_); the output does not
// depend on the schedule (per-pixel jitter, noise seeded by item and image). Returns each
// item's feature truth; `progress` is called under a lock, one image at a time.
std::vector<FeatureTruth> renderItems(const Renderer& renderer, const std::vector<Eigen::Isometry3d>& poses,
                                      int images_per_item, const NoiseOptions& noise, std::uint64_t seed,
                                      const std::function<std::filesystem::path(std::size_t, int)>& image_path,
                                      const ProgressCallback& progress) {
  std::vector<FeatureTruth> truths(poses.size());
  const std::size_t total = poses.size() * static_cast<std::size_t>(images_per_item);
  std::mutex progress_mutex;
  std::size_t done = 0;
  cv::parallel_for_(cv::Range(0, static_cast<int>(poses.size())), [&](const cv::Range& range) {
    for (int item = range.start; item < range.end; ++item) {
      const auto k = static_cast<std::size_t>(item);
      const Rendering rendering = renderer.render(poses[k]);
      const cv::Mat sigma = noiseSigma(rendering.radiance, noise);
      for (int image = 0; image < images_per_item; ++image) {
        writePng(image_path(k, image),
                 addNoiseWithSigma(rendering.radiance, sigma, noiseSeed(seed, k, static_cast<std::size_t>(image))));
        const std::lock_guard<std::mutex> lock(progress_mutex);
        ++done;
        if (progress) progress(done, total);
      }
      truths[k] = rendering.truth;
    }
  });
  return truths;
}

void writePose(cv::FileStorage& out, const Eigen::Isometry3d& pose) {
  const Eigen::Vector3d t = pose.translation();
  const Eigen::Vector3d r = metrology::rotationVector(pose.linear());
  out << "t" << "[:" << t.x() << t.y() << t.z() << "]";
  out << "r" << "[:" << r.x() << r.y() << r.z() << "]";
}

void writeFeatures(cv::FileStorage& out, const FeatureTruth& truth) {
  // One row per feature of target.yaml's layout: u, v (px, OpenCV convention), visible.
  cv::Mat features(static_cast<int>(truth.pixels.size()), 3, CV_64F);
  for (int i = 0; i < features.rows; ++i) {
    features.at<double>(i, 0) = truth.pixels[static_cast<std::size_t>(i)].x();
    features.at<double>(i, 1) = truth.pixels[static_cast<std::size_t>(i)].y();
    features.at<double>(i, 2) = truth.visible[static_cast<std::size_t>(i)] ? 1.0 : 0.0;
  }
  out << "features" << features;
}

cv::FileStorage openTruth(const SimulationSpec& spec, const char* kind) {
  cv::FileStorage out(".yaml", cv::FileStorage::WRITE | cv::FileStorage::MEMORY | cv::FileStorage::FORMAT_YAML);
  out.writeComment(std::string("mire simulate ") + kind +
                   ": ground truth. Units: metres, radians (rotation vectors as cv::Rodrigues), pixels "
                   "(OpenCV convention). t, r: cTm (target frame M to camera frame C). features: one row "
                   "per target feature (target.yaml layout): u, v, visible (projected centre of circles).");
  out << "camera_file" << "camera.yaml";
  out << "target_file" << "target.yaml";
  out << "spec_file" << spec.file.filename().string();
  out << "seed" << static_cast<int>(spec.seed);  // specs limit seeds to 2^30
  out << "noise_gaussian_sigma" << spec.noise.gaussian_sigma;
  out << "noise_shot_gain" << spec.noise.shot_noise_gain;
  out << "blur_sigma_px" << spec.render.blur_sigma_px;
  out << "supersampling" << spec.render.supersampling;
  return out;
}

void writeCommonFiles(const SimulationSpec& spec, const std::filesystem::path& dir) {
  std::filesystem::create_directories(dir);
  support::writeFileAtomically(dir / "camera.yaml", calibration::cameraYamlString(spec.camera));
  support::writeFileAtomically(dir / "target.yaml", spec.target.yamlString());
}

std::string formatNumber(double value) {
  char text[64];
  std::snprintf(text, sizeof text, "%.17g", value);
  return text;
}

}  // namespace

SimulationSpec readSimulationSpec(const std::filesystem::path& path) {
  const std::string file = path.string();
  if (!std::filesystem::is_regular_file(path)) throw std::runtime_error(file + ": cannot open simulation spec");
  cv::FileStorage storage;
  try {
    storage.open(file, cv::FileStorage::READ | cv::FileStorage::FORMAT_YAML);
  } catch (const cv::Exception& error) {
    throw std::runtime_error(file + ": not a valid YAML spec (" + error.err + ")");
  }
  if (!storage.isOpened()) throw std::runtime_error(file + ": cannot open simulation spec");
  const NodeReader root(storage.root(), file, "");
  const std::filesystem::path base = path.parent_path();
  const auto resolve = [&](const std::string& relative) {
    const std::filesystem::path p(relative);
    return p.is_absolute() ? p : base / p;
  };

  SimulationSpec spec;
  spec.file = path;
  if (!root.has("camera")) root.fail("camera", "missing (a camera.yaml path or an inline camera)");
  if (root.node("camera").isString())
    spec.camera = calibration::readCameraYaml(resolve(root.text("camera", "")));
  else
    spec.camera = readInlineCamera(root.child("camera"), file);
  if (!root.has("target")) root.fail("target", "missing (a target.yaml path)");
  spec.target = metrology::Target::fromFile(resolve(root.text("target", "")));
  spec.seed = static_cast<std::uint64_t>(root.integer("seed", 1, 0, 1 << 30));

  const NodeReader render = root.child("render");
  spec.render.supersampling = render.integer("supersampling", 4, 1, 16);
  spec.render.adaptive = render.flag("adaptive", true);
  spec.render.dark_level = render.number("dark_level", spec.render.dark_level, 0, 255);
  spec.render.light_level = render.number("light_level", spec.render.light_level, 0, 255);
  spec.render.background_level = render.number("background_level", spec.render.background_level, 0, 255);
  spec.render.cluttered_background = render.flag("cluttered_background", false);
  spec.render.blur_sigma_px = render.number("blur_sigma_px", 0.0, 0.0, 20.0);
  const std::string vignetting = render.text("vignetting", "none");
  if (vignetting == "none")
    spec.render.vignetting = Vignetting::None;
  else if (vignetting == "cos4")
    spec.render.vignetting = Vignetting::Cos4;
  else if (vignetting == "polynomial") {
    spec.render.vignetting = Vignetting::Polynomial;
    if (!render.has("vignetting_coefficients")) render.fail("vignetting_coefficients", "missing (polynomial vignetting)");
    spec.render.vignetting_coefficients = render.numbers("vignetting_coefficients", 0);
  } else
    render.fail("vignetting", "'" + vignetting + "' is not one of none, cos4, polynomial");
  spec.render.seed = spec.seed;

  const NodeReader noise = root.child("noise");
  spec.noise.gaussian_sigma = noise.number("gaussian_sigma", 0.0, 0.0, 100.0);
  spec.noise.shot_noise_gain = noise.number("shot_noise_gain", 0.0, 0.0, 1e9);

  const NodeReader calibration = root.child("calibration");
  spec.calibration.views = calibration.integer("views", 25, 1, 10000);
  if (calibration.has("distance_m")) {
    const std::vector<double> range = calibration.numbers("distance_m", 2);
    if (!(range[0] > 0.0 && range[1] >= range[0])) calibration.fail("distance_m", "must be [min, max] with 0 < min <= max");
    spec.calibration.min_distance_m = range[0], spec.calibration.max_distance_m = range[1];
  }
  spec.calibration.max_tilt_deg = calibration.number("max_tilt_deg", 50.0, 0.0, 80.0);
  spec.calibration.max_roll_deg = calibration.number("max_roll_deg", 20.0, 0.0, 180.0);
  spec.calibration.margin_px = calibration.number("margin_px", 15.0, 0.0, 1000.0);
  spec.images_per_view = calibration.integer("images_per_view", 1, 1, 1000);

  const NodeReader poses = root.child("poses");
  spec.images_per_pose = poses.integer("images_per_pose", 10, 1, 1000);
  if (poses.has("list")) {
    spec.poses_from_grid = false;
    int index = 0;
    for (const cv::FileNode& item : poses.node("list")) {
      const NodeReader entry(item, file, "poses.list[" + std::to_string(index) + "].");
      SimulatedPose pose;
      pose.id = entry.text("id", "");
      if (pose.id.empty() || pose.id.find_first_of("/\\ ") != std::string::npos)
        entry.fail("id", "missing, or not usable as a folder name");
      const std::vector<double> t = entry.numbers("t", 3), r = entry.numbers("r", 3);
      pose.camera_T_target = metrology::isometryFromVectors(Eigen::Vector3d(t[0], t[1], t[2]), Eigen::Vector3d(r[0], r[1], r[2]));
      spec.poses.push_back(pose);
      ++index;
    }
    if (spec.poses.empty()) poses.fail("list", "is empty");
  } else {
    const NodeReader grid = poses.child("grid");
    if (grid.has("size_m")) {
      const std::vector<double> size = grid.numbers("size_m", 3);
      spec.grid.size_m = Eigen::Vector3d(size[0], size[1], size[2]);
    }
    if (grid.has("counts")) {
      const std::vector<double> counts = grid.numbers("counts", 3);
      for (int i = 0; i < 3; ++i) {
        if (counts[static_cast<std::size_t>(i)] < 1 || counts[static_cast<std::size_t>(i)] > 100)
          grid.fail("counts", "must be 3 integers between 1 and 100");
        spec.grid.counts[i] = static_cast<int>(counts[static_cast<std::size_t>(i)]);
      }
    }
    if (grid.has("theta_deg")) spec.grid.theta_deg = grid.numbers("theta_deg", 0);
    spec.grid.camera_distance_m = grid.number("camera_distance_m", spec.grid.camera_distance_m, 0.01, 100.0);
    spec.grid.camera_tilt_deg = grid.number("camera_tilt_deg", spec.grid.camera_tilt_deg, -80.0, 80.0);
    spec.poses = generatePoseGrid(spec.target, spec.grid);
  }
  return spec;
}

SimulationResult simulateCalibration(const SimulationSpec& spec, const std::filesystem::path& output_dir,
                                     const ProgressCallback& progress) {
  const std::vector<Eigen::Isometry3d> views =
      generateCalibrationViews(spec.camera, spec.target, spec.calibration, spec.seed);
  const Renderer renderer(spec.camera, spec.target, spec.render);
  writeCommonFiles(spec, output_dir);
  std::filesystem::create_directories(output_dir / "images");

  cv::FileStorage truth = openTruth(spec, "calibration");
  truth << "views" << "[";
  SimulationResult result;
  const auto view_name = [](std::size_t k) {
    char name[32];
    std::snprintf(name, sizeof name, "view_%03zu", k);
    return std::string(name);
  };
  const auto image_file = [&](std::size_t k, int image) {
    std::string file = "images/" + view_name(k);
    if (spec.images_per_view > 1) {
      char suffix[16];
      std::snprintf(suffix, sizeof suffix, "_%02d", image);
      file += suffix;
    }
    return file + ".png";
  };
  const std::vector<FeatureTruth> truths =
      renderItems(renderer, views, spec.images_per_view, spec.noise, spec.seed,
                  [&](std::size_t k, int image) { return output_dir / image_file(k, image); }, progress);
  std::size_t visible = 0, features = 0;
  for (std::size_t k = 0; k < views.size(); ++k) {
    truth << "{" << "id" << view_name(k);
    truth << "images" << "[";
    for (int image = 0; image < spec.images_per_view; ++image) truth << image_file(k, image);
    result.images += static_cast<std::size_t>(spec.images_per_view);
    truth << "]";
    writePose(truth, views[k]);
    writeFeatures(truth, truths[k]);
    truth << "}";
    visible += truths[k].visibleCount();
    features += truths[k].pixels.size();
  }
  truth << "]";
  support::writeFileAtomically(output_dir / "truth.yaml", truth.releaseAndGetString());
  result.views_or_poses = views.size();
  result.visible_fraction = features ? static_cast<double>(visible) / features : 0.0;
  return result;
}

SimulationResult simulatePoses(const SimulationSpec& spec, const std::filesystem::path& output_dir,
                               const ProgressCallback& progress) {
  if (spec.poses.empty()) throw std::runtime_error(spec.file.string() + ": no poses to simulate");
  const Renderer renderer(spec.camera, spec.target, spec.render);
  writeCommonFiles(spec, output_dir);

  cv::FileStorage truth = openTruth(spec, "poses");
  if (spec.poses_from_grid) {
    truth.writeComment("Generated set: bTc the camera in the base frame; effector: x, y, z (m), theta (rad) in B; "
                       "eTm: the board's centre on the effector, printed face towards -z_E.");
    truth << "bTc" << "{";
    writePose(truth, poseGridCamera(spec.target, spec.grid));
    truth << "}";
  }
  truth << "images_per_pose" << spec.images_per_pose;
  truth << "poses" << "[";
  std::ostringstream csv;
  csv << "pose_id,images_used,images_total,tx_m,ty_m,tz_m,rx_rad,ry_rad,rz_rad,sigma_tx_mm,sigma_ty_mm,sigma_tz_mm,"
         "sigma_rx_deg,sigma_ry_deg,sigma_rz_deg,rms_px\n";
  SimulationResult result;
  std::vector<Eigen::Isometry3d> poses;
  for (const SimulatedPose& pose : spec.poses) {
    std::filesystem::create_directories(output_dir / "poses" / pose.id);
    poses.push_back(pose.camera_T_target);
  }
  // The robot is static while its images are taken: one render, independent noise each.
  const std::vector<FeatureTruth> truths = renderItems(
      renderer, poses, spec.images_per_pose, spec.noise, spec.seed,
      [&](std::size_t k, int image) {
        char name[32];
        std::snprintf(name, sizeof name, "img_%02d.png", image);
        return output_dir / "poses" / spec.poses[k].id / name;
      },
      progress);
  std::size_t visible = 0, features = 0;
  for (std::size_t k = 0; k < spec.poses.size(); ++k) {
    const SimulatedPose& pose = spec.poses[k];
    const FeatureTruth& feature_truth = truths[k];
    result.images += static_cast<std::size_t>(spec.images_per_pose);
    truth << "{" << "id" << pose.id;
    writePose(truth, pose.camera_T_target);
    if (pose.has_effector) truth << "effector" << "[:" << pose.effector[0] << pose.effector[1] << pose.effector[2] << pose.effector[3] << "]";
    writeFeatures(truth, feature_truth);
    truth << "}";
    const Eigen::Vector3d t = pose.camera_T_target.translation();
    const Eigen::Vector3d r = metrology::rotationVector(pose.camera_T_target.linear());
    csv << pose.id << ',' << spec.images_per_pose << ',' << spec.images_per_pose;
    for (const double value : {t.x(), t.y(), t.z(), r.x(), r.y(), r.z()}) csv << ',' << formatNumber(value);
    csv << ",0,0,0,0,0,0,0\n";
    visible += feature_truth.visibleCount();
    features += feature_truth.pixels.size();
  }
  truth << "]";
  support::writeFileAtomically(output_dir / "truth.yaml", truth.releaseAndGetString());
  support::writeFileAtomically(output_dir / "truth_poses.csv", csv.str());
  result.views_or_poses = spec.poses.size();
  result.visible_fraction = features ? static_cast<double>(visible) / features : 0.0;
  return result;
}

}  // namespace mire::datasets
