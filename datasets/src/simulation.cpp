// Simulation specs and the image sets they describe (simulation.hpp).
#include "mire/datasets/simulation.hpp"

#include "mire/calibration/camera_formats.hpp"
#include "mire/calibration/camera_io.hpp"
#include "mire/metrology/pose_types.hpp"
#include "mire/support/atomic_file.hpp"
#include "mire/support/yaml.hpp"

#include <opencv2/core.hpp>
#include <opencv2/core/utility.hpp>

#include <cmath>
#include <cstdio>
#include <functional>
#include <map>
#include <mutex>
#include <optional>
#include <sstream>
#include <stdexcept>

namespace mire::datasets {
namespace {

// Optional keys of one spec section, with their defaults; errors name the file, the line and
// the full key (support/yaml.hpp). An absent section reads as all defaults.
class SpecSection {
 public:
  explicit SpecSection(std::optional<support::YamlNode> node) : node_(std::move(node)) {
    if (node_) node_->requireMap();
  }
  // Unknown keys are errors (a misspelt `nosie:` would silently render without noise).
  void allow(const std::vector<std::string>& keys) const {
    if (node_) node_->checkKeys(keys);
  }
  std::optional<support::YamlNode> find(const std::string& key) const {
    if (!node_) return std::nullopt;
    auto found = node_->find(key);
    if (found && found->isNull()) return std::nullopt;
    return found;
  }
  bool has(const std::string& key) const { return find(key).has_value(); }
  SpecSection child(const std::string& key) const { return SpecSection(find(key)); }
  double number(const std::string& key, double fallback, double minimum, double maximum) const {
    const auto value = find(key);
    return value ? value->asDouble({minimum, maximum}) : fallback;
  }
  int integer(const std::string& key, int fallback, int minimum, int maximum) const {
    const auto value = find(key);
    return value ? static_cast<int>(value->asInt(minimum, maximum)) : fallback;
  }
  bool flag(const std::string& key, bool fallback) const {
    const auto value = find(key);
    if (!value) return fallback;
    // 0/1 as the specs always wrote them, or true/false.
    if (const auto number = support::parseYamlNumber(value->asString())) return value->asInt(0, 1) == 1;
    return value->asBool();
  }
  std::string text(const std::string& key, const std::string& fallback) const {
    const auto value = find(key);
    return value ? value->asString() : fallback;
  }
  std::vector<double> numbers(const std::string& key, std::size_t size, double minimum, double maximum) const {
    const auto value = find(key);
    if (!value) throw support::YamlError(where() + ": missing key '" + key + "'");
    std::vector<double> result = value->asDoubles({minimum, maximum});
    if (size != 0 && result.size() != size) value->fail("must have " + std::to_string(size) + " values");
    return result;
  }
  [[noreturn]] void fail(const std::string& key, const std::string& what) const {
    if (const auto value = find(key)) value->fail(what);
    throw support::YamlError(where() + ": key '" + key + "': " + what);
  }
  std::string where() const { return node_ ? node_->where() : std::string("(absent section)"); }

 private:
  std::optional<support::YamlNode> node_;
};

// The noise seed of image `image` of view/pose `item`: distinct, reproducible streams.
std::uint64_t noiseSeed(std::uint64_t seed, std::size_t item, std::size_t image) {
  std::uint64_t z = seed * 0x9E3779B97F4A7C15ULL + item * 0xBF58476D1CE4E5B9ULL + image * 0x94D049BB133111EBULL + 1;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

// Renders every item (a view or a pose) once and writes its noisy images, items in parallel
// (the PNG encoding, single-threaded in OpenCV, costs more than the render). Each
// item's render runs serially inside its worker (nested parallel_for_); the output does not
// depend on the schedule (per-pixel jitter, noise seeded by item and image). Returns each
// item's feature truth; `progress` is called under a lock, one image at a time. `rods`: the
// rods seen at each item, or empty for none at all.
std::vector<FeatureTruth> renderItems(const Renderer& renderer, const std::vector<Eigen::Isometry3d>& poses,
                                      const std::vector<std::vector<Rod>>& rods, int images_per_item,
                                      const NoiseOptions& noise, std::uint64_t seed, PngEncoding png,
                                      const std::function<std::filesystem::path(std::size_t, int)>& image_path,
                                      const ProgressCallback& progress) {
  std::vector<FeatureTruth> truths(poses.size());
  const std::size_t total = poses.size() * static_cast<std::size_t>(images_per_item);
  std::mutex progress_mutex;
  std::size_t done = 0;
  cv::parallel_for_(cv::Range(0, static_cast<int>(poses.size())), [&](const cv::Range& range) {
    for (int item = range.start; item < range.end; ++item) {
      const auto k = static_cast<std::size_t>(item);
      const Rendering rendering = rods.empty() ? renderer.render(poses[k]) : renderer.render(poses[k], rods[k]);
      const cv::Mat sigma = noiseSigma(rendering.radiance, noise);
      for (int image = 0; image < images_per_item; ++image) {
        writePng(image_path(k, image),
                 addNoiseWithSigma(rendering.radiance, sigma, noiseSeed(seed, k, static_cast<std::size_t>(image))), png);
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
  out << "t"
      << "[:" << t.x() << t.y() << t.z() << "]";
  out << "r"
      << "[:" << r.x() << r.y() << r.z() << "]";
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
  out << "camera_file"
      << "camera.yaml";
  out << "target_file"
      << "target.yaml";
  out << "spec_file" << spec.file.filename().string();
  out << "seed" << static_cast<int>(spec.seed);  // specs limit seeds to 2^30
  out << "noise_gaussian_sigma" << spec.noise.gaussian_sigma;
  out << "noise_shot_gain" << spec.noise.shot_noise_gain;
  out << "blur_sigma_px" << spec.render.blur_sigma_px;
  out << "supersampling" << spec.render.supersampling;
  return out;
}

// OpenCV's "%YAML:1.0" first line is no YAML directive (PyYAML stops there); "%YAML 1.2" is
// standard and cv::FileStorage reads it too. The features matrices keep OpenCV's tag.
std::string truthText(cv::FileStorage& truth) {
  std::string text = truth.releaseAndGetString();
  if (text.compare(0, 9, "%YAML:1.0") == 0) text.replace(0, 9, "%YAML 1.2");
  return text;
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

namespace {

void readRender(const SpecSection& render, SimulationSpec& spec) {
  render.allow({"supersampling", "adaptive", "dark_level", "light_level", "background_level", "cluttered_background",
                "blur_sigma_px", "vignetting", "vignetting_coefficients"});
  spec.render.supersampling = render.integer("supersampling", 4, 1, 16);
  spec.render.adaptive = render.flag("adaptive", true);
  spec.render.dark_level = render.number("dark_level", spec.render.dark_level, 0, 255);
  spec.render.light_level = render.number("light_level", spec.render.light_level, 0, 255);
  spec.render.background_level = render.number("background_level", spec.render.background_level, 0, 255);
  spec.render.cluttered_background = render.flag("cluttered_background", false);
  spec.render.blur_sigma_px = render.number("blur_sigma_px", 0.0, 0.0, 20.0);
  const std::string vignetting = render.text("vignetting", "none");
  if (vignetting == "none") {
    spec.render.vignetting = Vignetting::None;
  } else if (vignetting == "cos4") {
    spec.render.vignetting = Vignetting::Cos4;
  } else if (vignetting == "polynomial") {
    spec.render.vignetting = Vignetting::Polynomial;
    if (!render.has("vignetting_coefficients")) render.fail("vignetting", "'polynomial' needs vignetting_coefficients");
    spec.render.vignetting_coefficients = render.numbers("vignetting_coefficients", 0, -100.0, 100.0);
  } else {
    render.fail("vignetting", "'" + vignetting + "' is not one of none, cos4, polynomial");
  }
  spec.render.seed = spec.seed;
}

void readCalibrationViews(const SpecSection& calibration, SimulationSpec& spec) {
  calibration.allow({"views", "images_per_view", "distance_m", "max_tilt_deg", "max_roll_deg", "margin_px"});
  spec.calibration.views = calibration.integer("views", 25, 1, 10000);
  if (calibration.has("distance_m")) {
    const std::vector<double> range = calibration.numbers("distance_m", 2, 0.0, 1000.0);
    if (!(range[0] > 0.0 && range[1] >= range[0]))
      calibration.fail("distance_m", "must be [min, max] with 0 < min <= max");
    spec.calibration.min_distance_m = range[0], spec.calibration.max_distance_m = range[1];
  }
  spec.calibration.max_tilt_deg = calibration.number("max_tilt_deg", 50.0, 0.0, 80.0);
  spec.calibration.max_roll_deg = calibration.number("max_roll_deg", 20.0, 0.0, 180.0);
  spec.calibration.margin_px = calibration.number("margin_px", 15.0, 0.0, 1000.0);
  spec.images_per_view = calibration.integer("images_per_view", 1, 1, 1000);
}

// An explicit pose list: ids become folder names, so they must be plain and unique.
void readPoseList(const support::YamlNode& list, SimulationSpec& spec) {
  spec.poses_from_grid = false;
  std::map<std::string, int> lines;
  for (const support::YamlNode& item : list.items()) {
    item.requireMap();
    item.checkKeys({"id", "t", "r"});
    const support::YamlNode id = item.at("id");
    SimulatedPose pose;
    pose.id = id.asString();
    if (pose.id.empty() || pose.id == "." || pose.id == ".." ||
        pose.id.find_first_not_of("ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789_.-") !=
            std::string::npos)
      id.fail("'" + pose.id + "' is not usable as a folder name (letters, digits, '_', '-', '.')");
    const auto [it, inserted] = lines.emplace(pose.id, id.line());
    if (!inserted) id.fail("'" + pose.id + "' is given twice (first at line " + std::to_string(it->second) + ")");
    const std::vector<double> t = item.at("t").asDoubles({-1000.0, 1000.0});
    const std::vector<double> r = item.at("r").asDoubles({-100.0, 100.0});
    if (t.size() != 3) item.at("t").fail("must have 3 values (metres)");
    if (r.size() != 3) item.at("r").fail("must have 3 values (a rotation vector, radians)");
    if (!(t[2] > 0.0))
      item.at("t").fail("z = " + support::formatMessageNumber(t[2]) + " m puts the target behind the camera");
    pose.camera_T_target =
        metrology::isometryFromVectors(Eigen::Vector3d(t[0], t[1], t[2]), Eigen::Vector3d(r[0], r[1], r[2]));
    spec.poses.push_back(pose);
  }
  if (spec.poses.empty()) list.fail("is empty");
}

void readPoseGrid(const SpecSection& grid, SimulationSpec& spec) {
  grid.allow({"size_m", "counts", "theta_deg", "camera_distance_m", "camera_tilt_deg"});
  if (grid.has("size_m")) {
    const std::vector<double> size = grid.numbers("size_m", 3, 0.0, 100.0);
    spec.grid.size_m = Eigen::Vector3d(size[0], size[1], size[2]);
  }
  if (const auto counts = grid.find("counts")) {
    const auto items = counts->items();
    if (items.size() != 3) counts->fail("must be 3 integers between 1 and 100");
    for (int i = 0; i < 3; ++i)
      spec.grid.counts[i] = static_cast<int>(items[static_cast<std::size_t>(i)].asInt(1, 100));
  }
  if (grid.has("theta_deg")) spec.grid.theta_deg = grid.numbers("theta_deg", 0, -360.0, 360.0);
  spec.grid.camera_distance_m = grid.number("camera_distance_m", spec.grid.camera_distance_m, 0.01, 100.0);
  spec.grid.camera_tilt_deg = grid.number("camera_tilt_deg", spec.grid.camera_tilt_deg, -80.0, 80.0);
  spec.poses = generatePoseGrid(spec.target, spec.grid);
}

void readPoses(const SpecSection& poses, SimulationSpec& spec) {
  poses.allow({"images_per_pose", "list", "grid"});
  spec.images_per_pose = poses.integer("images_per_pose", 10, 1, 1000);
  if (const auto list = poses.find("list")) {
    if (poses.has("grid")) list->fail("give either 'list' or 'grid', not both");
    readPoseList(*list, spec);
  } else {
    readPoseGrid(poses.child("grid"), spec);
  }
}

}  // namespace

SimulationSpec readSimulationSpec(const std::filesystem::path& path) {
  const support::YamlFile yaml = support::YamlFile::load(path);
  const support::YamlNode& root = yaml.rootMap();
  root.checkKeys({"camera", "target", "seed", "render", "noise", "calibration", "poses", "png"});
  const std::filesystem::path base = path.parent_path();
  const auto resolve = [&](const std::string& relative) {
    const std::filesystem::path p(relative);
    return p.is_absolute() ? p : base / p;
  };

  SimulationSpec spec;
  spec.file = path;
  const support::YamlNode camera = root.at("camera");
  spec.camera =
      camera.isScalar() ? calibration::readCamera(resolve(camera.asString())) : calibration::cameraFromYaml(camera);
  spec.target = metrology::Target::fromFile(resolve(root.string("target")));
  const SpecSection top(root);
  spec.seed = static_cast<std::uint64_t>(top.integer("seed", 1, 0, 1 << 30));
  readRender(top.child("render"), spec);
  const SpecSection noise = top.child("noise");
  noise.allow({"gaussian_sigma", "shot_noise_gain"});
  spec.noise.gaussian_sigma = noise.number("gaussian_sigma", 0.0, 0.0, 100.0);
  spec.noise.shot_noise_gain = noise.number("shot_noise_gain", 0.0, 0.0, 1e9);
  readCalibrationViews(top.child("calibration"), spec);
  readPoses(top.child("poses"), spec);
  const std::string png = top.text("png", "compressed");
  if (png == "stored")
    spec.png = PngEncoding::Stored;
  else if (png != "compressed")
    top.fail("png", "'" + png + "' is not one of compressed, stored");
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
  truth << "views"
        << "[";
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
  const std::vector<FeatureTruth> truths = renderItems(
      renderer, views, {}, spec.images_per_view, spec.noise, spec.seed, spec.png,
      [&](std::size_t k, int image) { return output_dir / image_file(k, image); }, progress);
  std::size_t visible = 0, features = 0;
  for (std::size_t k = 0; k < views.size(); ++k) {
    truth << "{"
          << "id" << view_name(k);
    truth << "images"
          << "[";
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
  support::writeFileAtomically(output_dir / "truth.yaml", truthText(truth));
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
    truth.writeComment(
        "Generated set: bTc the camera in the base frame; effector: x, y, z (m), theta (rad) in B; "
        "eTm: the board's centre on the effector, printed face towards -z_E.");
    truth << "bTc"
          << "{";
    writePose(truth, poseGridCamera(spec.target, spec.grid));
    truth << "}";
  }
  truth << "images_per_pose" << spec.images_per_pose;
  truth << "poses"
        << "[";
  std::ostringstream csv;
  csv << "pose_id,images_used,images_total,tx_m,ty_m,tz_m,rx_rad,ry_rad,rz_rad,sigma_tx_mm,sigma_ty_mm,sigma_tz_mm,"
         "sigma_rx_deg,sigma_ry_deg,sigma_rz_deg,rms_px\n";
  SimulationResult result;
  std::vector<Eigen::Isometry3d> poses;
  std::vector<std::vector<Rod>> rods;
  for (const SimulatedPose& pose : spec.poses) {
    std::filesystem::create_directories(output_dir / "poses" / pose.id);
    poses.push_back(pose.camera_T_target);
    rods.push_back(pose.rods);
  }
  // The robot is static while its images are taken: one render, independent noise each.
  const std::vector<FeatureTruth> truths = renderItems(
      renderer, poses, rods, spec.images_per_pose, spec.noise, spec.seed, spec.png,
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
    truth << "{"
          << "id" << pose.id;
    writePose(truth, pose.camera_T_target);
    if (pose.has_effector)
      truth << "effector"
            << "[:" << pose.effector[0] << pose.effector[1] << pose.effector[2] << pose.effector[3] << "]";
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
  support::writeFileAtomically(output_dir / "truth.yaml", truthText(truth));
  support::writeFileAtomically(output_dir / "truth_poses.csv", csv.str());
  result.views_or_poses = spec.poses.size();
  result.visible_fraction = features ? static_cast<double>(visible) / features : 0.0;
  return result;
}

}  // namespace mire::datasets
