// OpenCV ArUco dictionaries by name and the boards of charuco / aruco_grid targets.
#include "mire/metrology/aruco_boards.hpp"

#include <stdexcept>

namespace mire::metrology {
namespace {

struct DictionaryName {
  cv::aruco::PREDEFINED_DICTIONARY_NAME id;
  const char* name;
};
#define MIRE_DICTIONARY(name) \
  { cv::aruco::name, #name }
constexpr DictionaryName kDictionaries[] = {
    MIRE_DICTIONARY(DICT_4X4_50),        MIRE_DICTIONARY(DICT_4X4_100),        MIRE_DICTIONARY(DICT_4X4_250),
    MIRE_DICTIONARY(DICT_4X4_1000),      MIRE_DICTIONARY(DICT_5X5_50),         MIRE_DICTIONARY(DICT_5X5_100),
    MIRE_DICTIONARY(DICT_5X5_250),       MIRE_DICTIONARY(DICT_5X5_1000),       MIRE_DICTIONARY(DICT_6X6_50),
    MIRE_DICTIONARY(DICT_6X6_100),       MIRE_DICTIONARY(DICT_6X6_250),        MIRE_DICTIONARY(DICT_6X6_1000),
    MIRE_DICTIONARY(DICT_7X7_50),        MIRE_DICTIONARY(DICT_7X7_100),        MIRE_DICTIONARY(DICT_7X7_250),
    MIRE_DICTIONARY(DICT_7X7_1000),      MIRE_DICTIONARY(DICT_ARUCO_ORIGINAL), MIRE_DICTIONARY(DICT_APRILTAG_16h5),
    MIRE_DICTIONARY(DICT_APRILTAG_25h9), MIRE_DICTIONARY(DICT_APRILTAG_36h10), MIRE_DICTIONARY(DICT_APRILTAG_36h11)};
#undef MIRE_DICTIONARY

void requireType(const Target& target, TargetType type) {
  if (target.spec().type != type)
    throw std::invalid_argument("not a " + targetTypeName(type) + " target: " + targetTypeName(target.spec().type));
}

}  // namespace

cv::Ptr<cv::aruco::Dictionary> arucoDictionary(const std::string& name) {
  for (const DictionaryName& entry : kDictionaries)
    if (name == entry.name) return cv::aruco::getPredefinedDictionary(entry.id);
  return {};
}

std::vector<std::string> arucoDictionaryNames() {
  std::vector<std::string> names;
  for (const DictionaryName& entry : kDictionaries) names.emplace_back(entry.name);
  return names;
}

cv::Ptr<cv::aruco::CharucoBoard> charucoBoard(const Target& target) {
  requireType(target, TargetType::Charuco);
  const TargetSpec& spec = target.spec();
  return cv::aruco::CharucoBoard::create(spec.cols, spec.rows, static_cast<float>(spec.square_size_m),
                                         static_cast<float>(spec.marker_size_m), arucoDictionary(spec.dictionary));
}

cv::Ptr<cv::aruco::GridBoard> arucoGridBoard(const Target& target) {
  requireType(target, TargetType::ArucoGrid);
  const TargetSpec& spec = target.spec();
  return cv::aruco::GridBoard::create(spec.cols, spec.rows, static_cast<float>(spec.marker_size_m),
                                      static_cast<float>(spec.marker_spacing_m), arucoDictionary(spec.dictionary),
                                      spec.first_id);
}

}  // namespace mire::metrology
