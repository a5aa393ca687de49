// Detection speed and accuracy (doc/detection-speed.md), run by hand, one thread (CPU time of the thread):
//   bench_detect [DEMO_DIR] [EXTERNAL_DIR]
// For every image: PNG/JPEG decode time, mire's detectTarget, OpenCV's classic
// findChessboardCorners (default flags + cornerSubPix 11x11, OpenCV's tutorial) and
// findChessboardCornersSB (default flags), each with its RMS error against the rendered truth.
// Images: rendered 640x480, 1024x768 and 2048x1536 (clean, cluttered, partial board, no board,
// small steeply tilted board, a target file with wrong cols/rows); real photos without a 12x9
// chessboard (EXTERNAL_DIR, default ../shared/datasets/external); the demo's 25 calibration
// views (DEMO_DIR written by `mire demo -o DEMO_DIR`), alone and mixed with 5 photos, with the
// calibration solve timed. Results: doc/detection-speed.md.
#include "mire/calibration/calibrate.hpp"
#include "mire/datasets/render.hpp"
#include "mire/datasets/simulation.hpp"
#include "mire/metrology/detection.hpp"

#include <opencv2/calib3d.hpp>
#include <opencv2/core/utility.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <limits>
#include <optional>
#include <string>
#include <vector>

namespace {

namespace fs = std::filesystem;
using namespace mire;

// CPU time of the calling thread: with cv::setNumThreads(1) all the work runs on it, and on
// a shared machine this is what one core spends, whatever the other processes do.
double threadCpuSeconds() {
  timespec now{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &now);
  return static_cast<double>(now.tv_sec) + 1e-9 * static_cast<double>(now.tv_nsec);
}

double seconds(const std::function<void()>& work) {
  const double start = threadCpuSeconds();
  work();
  return threadCpuSeconds() - start;
}

// Fast calls are repeated (best of 3) to damp the machine's load; slow ones run once.
double bestSeconds(const std::function<void()>& work) {
  double best = seconds(work);
  if (best < 0.2)
    for (int k = 0; k < 2; ++k) best = std::min(best, seconds(work));
  return best;
}

struct BenchImage {
  std::string set;  // group for the totals
  std::string name;
  std::vector<unsigned char> encoded;  // PNG / JPEG bytes, decoded in the timing
  metrology::TargetSpec searched;      // the target file the detectors are given
  std::vector<Eigen::Vector2d> truth;  // per feature of `searched` (empty: no truth)
  std::vector<bool> visible;
  bool board_complete = false;  // every corner visible (the finders can succeed)
};

struct DetectorResult {
  double seconds = 0.0;
  bool found = false;
  int corners = 0;
  double sum_sq = 0.0;  // squared errors to truth over `matched` corners
  int matched = 0;
};

// RMS against truth of an OpenCV row-major grid, over the grid's symmetries (OpenCV's order
// is not the target's).
void scoreGrid(const BenchImage& image, const std::vector<cv::Point2f>& grid, DetectorResult* result) {
  const int cols = image.searched.cols, rows = image.searched.rows;
  if (image.truth.empty() || static_cast<int>(grid.size()) != cols * rows) return;
  double best = std::numeric_limits<double>::infinity();
  for (int f = 0; f < 4; ++f) {
    double sum = 0.0;
    for (int r = 0; r < rows; ++r)
      for (int c = 0; c < cols; ++c) {
        const int cc = (f & 1) ? cols - 1 - c : c, rr = (f & 2) ? rows - 1 - r : r;
        const cv::Point2f& p = grid[rr * cols + cc];
        sum += (Eigen::Vector2d(p.x, p.y) - image.truth[r * cols + c]).squaredNorm();
      }
    best = std::min(best, sum);
  }
  result->sum_sq = best;
  result->matched = cols * rows;
}

DetectorResult runMire(const BenchImage& image, const cv::Mat& gray) {
  const metrology::Target target(image.searched);
  DetectorResult result;
  metrology::Detection detection;
  result.seconds = bestSeconds([&] { detection = metrology::detectTarget(target, gray); });
  result.found = detection.found;
  result.corners = static_cast<int>(detection.ids.size());
  if (image.truth.empty()) return result;
  for (std::size_t i = 0; i < detection.ids.size(); ++i) {
    const int id = detection.ids[i];
    if (!image.visible[id]) continue;
    result.sum_sq += (detection.pixels[i] - image.truth[id]).squaredNorm();
    ++result.matched;
  }
  return result;
}

DetectorResult runClassic(const BenchImage& image, const cv::Mat& gray) {
  const cv::Size pattern(image.searched.cols, image.searched.rows);
  DetectorResult result;
  std::vector<cv::Point2f> corners;
  result.seconds = bestSeconds([&] {
    corners.clear();
    if (cv::findChessboardCorners(gray, pattern, corners))
      cv::cornerSubPix(gray, corners, cv::Size(11, 11), cv::Size(-1, -1),
                       cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 30, 0.001));
  });
  result.found = !corners.empty() && static_cast<int>(corners.size()) == pattern.area();
  if (result.found) result.corners = pattern.area(), scoreGrid(image, corners, &result);
  return result;
}

DetectorResult runSB(const BenchImage& image, const cv::Mat& gray) {
  const cv::Size pattern(image.searched.cols, image.searched.rows);
  DetectorResult result;
  std::vector<cv::Point2f> corners;
  result.seconds = bestSeconds([&] { result.found = cv::findChessboardCornersSB(gray, pattern, corners); });
  if (result.found) result.corners = pattern.area(), scoreGrid(image, corners, &result);
  return result;
}

metrology::TargetSpec chessboard(int cols, int rows, double square_m) {
  metrology::TargetSpec spec;
  spec.cols = cols;
  spec.rows = rows;
  spec.square_size_m = square_m;
  return spec;
}

std::vector<unsigned char> encodePng(const cv::Mat& image) {
  std::vector<unsigned char> bytes;
  cv::imencode(".png", image, bytes);
  return bytes;
}

std::vector<unsigned char> readBytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// Rendered scenes at one image size: the demo's board (12x9 inner corners, 16 mm) through a
// mildly distorted camera, the demo's blur and noise.
void addRenderedScenes(int width, int height, std::vector<BenchImage>* images) {
  const double f = 0.8 * width;
  const calibration::Camera camera =
      calibration::cameraFromOpenCV(width, height, f, f, 0.5 * width - 0.5, 0.5 * height - 0.5, {-0.12, 0.05, 0, 0, 0});
  const metrology::TargetSpec spec = chessboard(12, 9, 0.016);
  const metrology::Target target(spec);
  datasets::NoiseOptions noise;
  noise.gaussian_sigma = 1.5;
  noise.shot_noise_gain = 20.0;
  const std::string size = std::to_string(width) + "x" + std::to_string(height);
  for (const bool cluttered : {false, true}) {
    datasets::RenderOptions options;
    options.blur_sigma_px = 0.6;
    options.cluttered_background = cluttered;
    options.seed = static_cast<std::uint64_t>(width);
    const datasets::Renderer renderer(camera, target, options);
    struct Scene {
      std::string name;
      datasets::ViewPlacement placement;
      bool absent = false;
    };
    std::vector<Scene> scenes;
    datasets::ViewPlacement centred;
    centred.centre_pixel = Eigen::Vector2d(0.5 * width, 0.5 * height);
    centred.distance_m = 0.30;  // the board spans about half the image width
    centred.tilt_rad = 0.45;
    centred.tilt_axis_rad = 0.6;
    centred.roll_rad = 0.2;
    scenes.push_back({cluttered ? "cluttered" : "clean", centred});
    if (cluttered) {
      datasets::ViewPlacement partial = centred;
      partial.centre_pixel = Eigen::Vector2d(0.97 * width, 0.55 * height);
      scenes.push_back({"partial", partial});
      datasets::ViewPlacement small = centred;
      small.distance_m *= 2.6;
      small.tilt_rad = 1.0;
      small.centre_pixel = Eigen::Vector2d(0.3 * width, 0.7 * height);
      scenes.push_back({"small-tilted", small});
      scenes.push_back({"no-board", centred, true});
    }
    for (const Scene& scene : scenes) {
      Eigen::Isometry3d pose = datasets::placeTarget(camera, target, scene.placement);
      if (scene.absent) pose.translation().z() = -pose.translation().z();  // behind the camera
      const datasets::Rendering rendering = renderer.render(pose);
      BenchImage image;
      image.set = "rendered " + size;
      image.name = size + " " + scene.name;
      image.encoded = encodePng(datasets::addNoise(rendering.radiance, noise, 7));
      image.searched = spec;
      if (!scene.absent) image.truth = rendering.truth.pixels, image.visible = rendering.truth.visible;
      image.board_complete = rendering.truth.visibleCount() == rendering.truth.pixels.size();
      images->push_back(image);
      if (scene.name == "cluttered") {
        for (const auto& [cols, rows] : {std::pair{11, 9}, std::pair{12, 10}}) {
          BenchImage wrong = image;
          wrong.name = size + " wrong cols/rows " + std::to_string(cols) + "x" + std::to_string(rows);
          wrong.searched = chessboard(cols, rows, 0.016);
          wrong.truth.clear();
          wrong.board_complete = false;
          images->push_back(wrong);
        }
      }
    }
  }
}

std::vector<fs::path> sortedFiles(const fs::path& folder, const std::vector<std::string>& extensions) {
  std::vector<fs::path> files;
  if (!fs::is_directory(folder)) return files;
  for (const auto& entry : fs::directory_iterator(folder))
    if (std::find(extensions.begin(), extensions.end(), entry.path().extension().string()) != extensions.end())
      files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  return files;
}

std::vector<fs::path> externalPhotos(const fs::path& external) {
  std::vector<fs::path> photos;
  for (const char* folder : {"apriltag-photos", "charuco", "visp-circles"})
    for (const fs::path& file : sortedFiles(external / folder, {".jpg"})) photos.push_back(file);
  return photos;
}

void addRealPhotos(const fs::path& external, std::vector<BenchImage>* images) {
  for (const fs::path& file : externalPhotos(external)) {
    BenchImage image;
    image.set = "real photos, no 12x9 board";
    image.name = file.parent_path().filename().string() + "/" + file.filename().string();
    image.encoded = readBytes(file);
    image.searched = chessboard(12, 9, 0.016);
    images->push_back(image);
  }
}

// The demo's calibration views with their truth; then 20 of them + 5 photos resized to the
// views' size (a calibration folder holds one image size).
void addDemoViews(const fs::path& demo, const fs::path& external, std::vector<BenchImage>* images) {
  const fs::path campaign = demo / "campaign";
  cv::FileStorage truth((campaign / "truth" / "calibration_truth.yaml").string(), cv::FileStorage::READ);
  if (!truth.isOpened()) {
    std::printf("no demo campaign in %s (run `mire demo -o DIR`): demo sets skipped\n", demo.string().c_str());
    return;
  }
  std::vector<BenchImage> views;
  for (const cv::FileNode& view : truth["views"]) {
    BenchImage image;
    image.set = "demo 25 views";
    const std::string file = static_cast<std::string>(view["images"][0]);
    image.name = "demo " + fs::path(file).filename().string();
    image.encoded = readBytes(campaign / "calibration" / file);
    image.searched = chessboard(12, 9, 0.016);
    cv::Mat features;
    view["features"] >> features;
    for (int k = 0; k < features.rows; ++k) {
      image.truth.emplace_back(features.at<double>(k, 0), features.at<double>(k, 1));
      image.visible.push_back(features.at<double>(k, 2) > 0.5);
    }
    image.board_complete = std::all_of(image.visible.begin(), image.visible.end(), [](bool v) { return v; });
    views.push_back(image);
  }
  images->insert(images->end(), views.begin(), views.end());
  const std::vector<fs::path> photos = externalPhotos(external);
  if (views.size() < 20 || photos.size() < 5) return;
  for (std::size_t k = 0; k < 20; ++k) {
    BenchImage mixed = views[k];
    mixed.set = "demo 20 views + 5 photos";
    images->push_back(mixed);
  }
  const cv::Mat first = cv::imdecode(views.front().encoded, cv::IMREAD_GRAYSCALE);
  for (std::size_t k = 0; k < 5; ++k) {
    cv::Mat photo = cv::imread(photos[k * photos.size() / 5].string(), cv::IMREAD_GRAYSCALE);
    cv::resize(photo, photo, first.size(), 0, 0, cv::INTER_AREA);
    BenchImage image;
    image.set = "demo 20 views + 5 photos";
    image.name = "photo " + photos[k * photos.size() / 5].filename().string() + " resized";
    image.encoded = encodePng(photo);
    image.searched = chessboard(12, 9, 0.016);
    images->push_back(image);
  }
}

struct Row {
  const BenchImage* image = nullptr;
  cv::Size size;
  double decode = 0.0;
  DetectorResult mire, classic, sb;
};

struct Totals {
  double decode = 0.0, mire = 0.0, classic = 0.0, sb = 0.0;
  const Row* worst_mire = nullptr;
  int count = 0;
  double sum_sq[3] = {0, 0, 0};
  int matched[3] = {0, 0, 0};
  int found[3] = {0, 0, 0};
  std::vector<calibration::CalibrationView> views;
  std::vector<Eigen::Vector3d> points;
  int width = 0, height = 0;
};

double rms(double sum_sq, int matched) { return matched > 0 ? std::sqrt(sum_sq / matched) : std::nan(""); }

void printRow(const Row& row) {
  const auto cell = [](const DetectorResult& r) {
    char text[64];
    if (std::isnan(r.seconds))
      std::snprintf(text, sizeof text, "%8s  %-12s", "skipped", "");
    else if (!r.found)
      std::snprintf(text, sizeof text, "%8.1f  %-12s", 1e3 * r.seconds, "-");
    else if (r.matched > 0)
      std::snprintf(text, sizeof text, "%8.1f  %3d %6.3fpx", 1e3 * r.seconds, r.corners, rms(r.sum_sq, r.matched));
    else
      std::snprintf(text, sizeof text, "%8.1f  %3d found! ", 1e3 * r.seconds, r.corners);
    return std::string(text);
  };
  std::printf("%-46s %6.1f | %s | %s | %s\n", row.image->name.c_str(), 1e3 * row.decode, cell(row.mire).c_str(),
              cell(row.classic).c_str(), cell(row.sb).c_str());
}

void accumulate(const Row& row, Totals* totals) {
  totals->decode += row.decode;
  totals->mire += row.mire.seconds;
  if (!std::isnan(row.classic.seconds)) totals->classic += row.classic.seconds;
  totals->sb += row.sb.seconds;
  ++totals->count;
  if (!totals->worst_mire || row.mire.seconds > totals->worst_mire->mire.seconds) totals->worst_mire = &row;
  const DetectorResult* results[3] = {&row.mire, &row.classic, &row.sb};
  for (int k = 0; k < 3; ++k) {
    totals->sum_sq[k] += results[k]->sum_sq;
    totals->matched[k] += results[k]->matched;
    totals->found[k] += results[k]->found ? 1 : 0;
  }
}

// The calibration solve on mire's detections (what `mire calibrate` adds to detection).
double solveSeconds(const std::vector<const Row*>& rows) {
  std::vector<calibration::CalibrationView> views;
  std::optional<metrology::Target> target;
  cv::Size size;
  for (const Row* row : rows) {
    const cv::Mat gray = cv::imdecode(row->image->encoded, cv::IMREAD_GRAYSCALE);
    target.emplace(row->image->searched);
    size = gray.size();
    const metrology::Detection detection = metrology::detectTarget(*target, gray);
    if (!detection.found) continue;
    views.push_back({row->image->name, detection.ids, detection.pixels});
  }
  if (views.size() < 3) return std::nan("");
  calibration::CalibrationOptions options;
  options.model = calibration::DistortionModel::OpenCV5;
  return seconds([&] { calibration::calibrateCamera(target->points(), views, size.width, size.height, options); });
}

}  // namespace

int main(int argc, char** argv) {
  cv::setNumThreads(1);
  const fs::path demo = argc > 1 ? fs::path(argv[1]) : fs::path();
  const fs::path external = argc > 2 ? fs::path(argv[2]) : fs::path("../shared/datasets/external");
  std::vector<BenchImage> images;
  if (!std::getenv("BENCH_DETECT_NO_RENDERED"))  // set: only the photos and the demo sets
    for (const auto& [w, h] : {std::pair{640, 480}, std::pair{1024, 768}, std::pair{2048, 1536}})
      addRenderedScenes(w, h, &images);
  addRealPhotos(external, &images);
  if (!demo.empty()) addDemoViews(demo, external, &images);

  if (const char* dump = std::getenv("BENCH_DETECT_DUMP")) {  // write the images for inspection, time nothing
    for (const BenchImage& image : images) {
      std::string file = image.name;
      std::replace_if(
          file.begin(), file.end(), [](char c) { return !std::isalnum(static_cast<unsigned char>(c)); }, '_');
      cv::imwrite((fs::path(dump) / (file + ".png")).string(), cv::imdecode(image.encoded, cv::IMREAD_GRAYSCALE));
    }
    return 0;
  }
  std::printf(
      "one thread, CPU time of the thread; times in ms; accuracy: corners found, RMS error to the rendered truth\n");
  std::printf("%-46s %6s | %-22s | %-22s | %-22s\n", "image", "decode", "mire", "OpenCV classic+subpix", "OpenCV SB");
  std::vector<Row> rows(images.size());
  for (std::size_t k = 0; k < images.size(); ++k) {
    Row& row = rows[k];
    row.image = &images[k];
    cv::Mat gray;
    row.decode = bestSeconds([&] { gray = cv::imdecode(images[k].encoded, cv::IMREAD_GRAYSCALE); });
    row.size = gray.size();
    row.mire = runMire(images[k], gray);
    // The classic finder takes minutes on a large image without the board: it can be skipped
    // above a width (BENCH_DETECT_CLASSIC_MAX_WIDTH) where the board is not complete, reported as "skipped".
    const char* classic_max = std::getenv("BENCH_DETECT_CLASSIC_MAX_WIDTH");
    if (classic_max && gray.cols > std::atoi(classic_max) && !images[k].board_complete)
      row.classic.seconds = std::nan("");
    else
      row.classic = runClassic(images[k], gray);
    row.sb = runSB(images[k], gray);
    printRow(row);
    std::fflush(stdout);
  }

  std::vector<std::string> sets;
  for (const BenchImage& image : images)
    if (std::find(sets.begin(), sets.end(), image.set) == sets.end()) sets.push_back(image.set);
  std::printf(
      "\nper set (one thread): total ms, ratios to SB and to decode, worst mire image, RMS px of found corners\n");
  for (const std::string& set : sets) {
    Totals totals;
    std::vector<const Row*> members;
    for (const Row& row : rows)
      if (row.image->set == set) accumulate(row, &totals), members.push_back(&row);
    std::printf(
        "%s (%d images): decode %.0f, mire %.0f, classic %.0f, SB %.0f ms; mire/SB %.2f, mire/decode %.1f; "
        "worst mire %.1f ms (%s); found mire %d classic %d SB %d; RMS mire %.4f classic %.4f SB %.4f px\n",
        set.c_str(), totals.count, 1e3 * totals.decode, 1e3 * totals.mire, 1e3 * totals.classic, 1e3 * totals.sb,
        totals.mire / totals.sb, totals.mire / totals.decode, 1e3 * totals.worst_mire->mire.seconds,
        totals.worst_mire->image->name.c_str(), totals.found[0], totals.found[1], totals.found[2],
        rms(totals.sum_sq[0], totals.matched[0]), rms(totals.sum_sq[1], totals.matched[1]),
        rms(totals.sum_sq[2], totals.matched[2]));
    if (set.rfind("demo", 0) == 0) {
      const double solve = solveSeconds(members);
      std::printf("  calibration solve on mire's detections: %.0f ms; mire detect / (decode + solve) = %.2f\n",
                  1e3 * solve, totals.mire / (totals.decode + solve));
    }
  }
  return 0;
}
