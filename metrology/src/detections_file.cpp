// mire's detections CSV and mrcal's corners vnlog (detections_file.hpp, doc/targets.md).
#include "mire/metrology/detections_file.hpp"

#include "mire/support/csv.hpp"
#include "mire/support/input_file.hpp"

#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>

namespace mire::metrology {
namespace {

[[noreturn]] void failAt(const std::string& where, const std::string& what) {
  throw std::runtime_error(where + ": " + what);
}

// Adds one feature to the image's entry (created in order of first appearance).
void addFeature(DetectionsFile* file, std::map<std::string, std::size_t>* index, const std::string& image, int id,
                const Eigen::Vector2d& pixel) {
  const auto [entry, inserted] = index->emplace(image, file->images.size());
  if (inserted) file->images.push_back({image, {}, {}});
  ImageDetections& detections = file->images[entry->second];
  detections.ids.push_back(id);
  detections.pixels.push_back(pixel);
}

void readImageSize(const std::filesystem::path& path, DetectionsFile* file) {
  std::ifstream in(path);
  std::string line;
  for (int number = 1; std::getline(in, line) && !line.empty() && line[0] == '#'; ++number) {
    const std::string key = "# image_size_px:";
    if (line.rfind(key, 0) != 0) continue;
    std::istringstream values(line.substr(key.size()));
    int width = 0, height = 0;
    if (!(values >> width >> height) || width <= 0 || height <= 0)
      failAt(path.string() + ":" + std::to_string(number),
             "image_size_px must be two positive integers (width height)");
    file->width = width, file->height = height;
  }
}

DetectionsFile readMireCsv(const std::filesystem::path& path, const Target& target) {
  const support::CsvTable table = support::readCsv(path);
  DetectionsFile file;
  readImageSize(path, &file);
  const std::size_t image = table.column("image"), id = table.column("feature_id"), u = table.column("u_px"),
                    v = table.column("v_px"), x = table.column("x_m"), y = table.column("y_m"), z = table.column("z_m");
  std::map<std::string, std::size_t> index;
  std::map<std::pair<std::string, int>, bool> seen;
  const int count = static_cast<int>(target.points().size());
  for (std::size_t row = 0; row < table.rows.size(); ++row) {
    const std::string& name = table.rows[row][image];
    if (name.empty()) failAt(table.where(row), "column 'image': empty");
    const double feature = table.number(row, id);
    if (feature != std::floor(feature) || feature < 0 || feature >= count)
      failAt(table.where(row), "column 'feature_id': " + table.rows[row][id] + " is not a feature of the target (0.." +
                                   std::to_string(count - 1) + ")");
    const int k = static_cast<int>(feature);
    const Eigen::Vector3d point(table.number(row, x), table.number(row, y), table.number(row, z));
    if ((point - target.points()[static_cast<std::size_t>(k)]).norm() > 1e-9)
      failAt(table.where(row), "feature " + std::to_string(k) + " is at (" + table.rows[row][x] + ", " +
                                   table.rows[row][y] + ", " + table.rows[row][z] +
                                   ") m in the file but not on this target (another target.yaml?)");
    if (!seen.emplace(std::make_pair(name, k), true).second)
      failAt(table.where(row), "feature " + std::to_string(k) + " of image '" + name + "' given twice");
    addFeature(&file, &index, name, k, Eigen::Vector2d(table.number(row, u), table.number(row, v)));
  }
  if (file.images.empty()) failAt(path.string(), "no detections");
  return file;
}

// mrcal's corners vnlog: "# filename x y level", then "name x y level" rows, each image's rows
// the board's corners in mrgingham's order (row-major from the board's first corner), which
// is a chessboard target's feature order; "-" marks a corner not seen (and a whole image
// without its board).
DetectionsFile readMrcalVnlog(const std::filesystem::path& path, const Target& target) {
  if (target.spec().type != TargetType::Chessboard)
    failAt(path.string(), "an mrcal corners vnlog needs a chessboard target (its corners in the board's order)");
  std::ifstream in(path);
  DetectionsFile file;
  std::map<std::string, std::size_t> index;
  std::map<std::string, int> rows_of_image;
  std::vector<std::string> order;
  const int count = static_cast<int>(target.points().size());
  std::string line;
  for (int number = 1; std::getline(in, line); ++number) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.empty() || line[0] == '#') continue;
    const std::string where = path.string() + ":" + std::to_string(number);
    std::istringstream fields(line);
    std::string name, x, y, level, extra;
    if (!(fields >> name >> x >> y >> level) || (fields >> extra))
      failAt(where, "expected 4 fields: filename x y level");
    if (rows_of_image.find(name) == rows_of_image.end()) order.push_back(name);
    const int k = rows_of_image[name]++;
    if (x == "-" && y == "-") continue;  // corner (or board) not seen
    if (level == "-") continue;          // mrcal: a point to ignore
    double u = 0, v = 0, l = 0;
    try {
      std::size_t end_u = 0, end_v = 0, end_l = 0;
      u = std::stod(x, &end_u), v = std::stod(y, &end_v), l = std::stod(level, &end_l);
      if (end_u != x.size() || end_v != y.size() || end_l != level.size()) throw std::invalid_argument(x);
    } catch (const std::exception&) {
      failAt(where, "x, y and level must be numbers (or '-')");
    }
    if (!std::isfinite(u) || !std::isfinite(v)) failAt(where, "x and y must be finite");
    if (l < 0) continue;  // mrcal: a negative level marks a point to ignore
    if (k >= count)
      failAt(where,
             "image '" + name + "' has more than " + std::to_string(count) + " corners (the target's cols x rows)");
    addFeature(&file, &index, name, k, Eigen::Vector2d(u, v));
  }
  for (const std::string& name : order)
    if (rows_of_image[name] != 1 && rows_of_image[name] != count)
      failAt(path.string(), "image '" + name + "' has " + std::to_string(rows_of_image[name]) +
                                " corner rows, the target " + std::to_string(count) + " (cols x rows)");
  if (file.images.empty()) failAt(path.string(), "no detections");
  return file;
}

}  // namespace

std::string detectionsCsv(const Target& target, const std::vector<ImageDetections>& images, int width, int height) {
  std::ostringstream out;
  out << "# mire detections: u, v in pixels (OpenCV's convention: integer coordinates at pixel centres); x, y, z: the\n"
         "# feature's point in the target's frame M (metres), feature_id its index (doc/targets.md)\n";
  if (width > 0 && height > 0) out << "# image_size_px: " << width << " " << height << "\n";
  out << kDetectionsCsvHeader << "\n";
  for (const ImageDetections& image : images) {
    if (image.image.find_first_of(",\"\n") != std::string::npos)
      throw std::runtime_error("image name '" + image.image +
                               "' contains ',', '\"' or a line break: cannot be written to CSV");
    for (std::size_t i = 0; i < image.ids.size(); ++i) {
      const Eigen::Vector3d& p = target.points()[static_cast<std::size_t>(image.ids[i])];
      out << image.image << "," << image.ids[i] << "," << support::formatNumber(image.pixels[i].x()) << ","
          << support::formatNumber(image.pixels[i].y()) << "," << support::formatNumber(p.x()) << ","
          << support::formatNumber(p.y()) << "," << support::formatNumber(p.z()) << "\n";
    }
  }
  return out.str();
}

DetectionsFile readDetectionsFile(const std::filesystem::path& path, const Target& target) {
  support::requireRegularFile(path);
  std::ifstream in(path);
  if (!in) throw std::runtime_error(path.string() + ": cannot open the detections file");
  std::string line;
  while (std::getline(in, line) && (line.empty() || line == "\r")) {
  }
  const bool vnlog = line.rfind("# filename", 0) == 0;
  return vnlog ? readMrcalVnlog(path, target) : readMireCsv(path, target);
}

}  // namespace mire::metrology
