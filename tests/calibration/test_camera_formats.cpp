// Camera files both ways: OpenCV (and its key variants), ROS camera_info, ViSP XML, Kalibr,
// mrcal; real files of those tools (../shared/datasets/external/camera-files, values from its
// README); round trips; other readers (cv::FileStorage, PyYAML, mrcal) reading what mire writes.
#include "mire/calibration/camera_formats.hpp"
#include "mire/calibration/camera_io.hpp"
#include "mire/support/yaml.hpp"

#include "test_support.hpp"

#include <gtest/gtest.h>
#include <opencv2/core.hpp>

#include <cstdio>
#include <fstream>
#include <optional>
#include <sstream>

namespace mire::calibration {
namespace {

const std::filesystem::path kCameraFiles = "datasets/external/camera-files";
// Debian's interpreter: python3-yaml and python3-mrcal are installed for it (not for a
// user's pyenv that may come first on PATH).
const char* kPython = "/usr/bin/python3";

using test::writeText;

bool pythonHas(const std::string& module) {
  return test::runCommand(std::string(kPython) + " -c 'import " + module + "' >/dev/null 2>&1") == 0;
}

// Output of a shell command (stdout), for the Python checks.
std::string capture(const std::string& command) {
  std::string output;
  FILE* pipe = popen(command.c_str(), "r");
  if (!pipe) return output;
  char buffer[4096];
  while (const std::size_t n = std::fread(buffer, 1, sizeof buffer, pipe)) output.append(buffer, n);
  pclose(pipe);
  return output;
}

Camera openCvCamera(int count) {
  std::vector<double> d = {-0.3, 0.1, 1e-3, -1e-3, -0.02, 0.01, -0.005, 0.002, 1e-3, -5e-4, 8e-4, -3e-4};
  d.resize(static_cast<std::size_t>(count));
  return cameraFromOpenCV(1024, 768, 817.2043010752688, 816.5, 511.5, 383.25, d);
}

Camera fisheyeCamera() {
  Camera camera = openCvCamera(4);
  camera.lens = LensModel::Fisheye;
  camera.params = {277.95596230891084,    278.4167467580337,   315.5269754313737,     244.46893770533453,
                   -0.005908650672531068, 0.01587953759563821, -0.024196671184075886, 0.015501252412920248};
  camera.width = 640;
  camera.height = 480;
  return camera;
}

std::vector<Camera> everyKindOfCamera() {
  std::vector<Camera> cameras;
  for (const int count : {0, 4, 5, 8, 12}) cameras.push_back(openCvCamera(count));
  cameras.push_back(fisheyeCamera());
  return cameras;
}

void expectSameCamera(const Camera& a, const Camera& b, double tolerance) {
  EXPECT_EQ(a.width, b.width);
  EXPECT_EQ(a.height, b.height);
  EXPECT_EQ(a.lens, b.lens);
  ASSERT_EQ(a.params.size(), b.params.size());
  for (std::size_t i = 0; i < a.params.size(); ++i) EXPECT_NEAR(a.params[i], b.params[i], tolerance) << i;
}

// ---- real files of other tools --------------------------------------------------------------

TEST(CameraFormats, ReadsARealRosCameraInfo) {
  MIRE_REQUIRE_SHARED(kCameraFiles / "ros_camera_info.yaml");
  const auto path = test::sharedDir() / kCameraFiles / "ros_camera_info.yaml";
  EXPECT_EQ(detectCameraFormat(path), CameraFormat::Ros);
  const Camera camera = readCamera(path);
  EXPECT_EQ(camera.width, 320);
  EXPECT_EQ(camera.height, 240);
  EXPECT_EQ(camera.lens, LensModel::OpenCV);
  const std::vector<double> expected{376.711141, 376.065748, 159.282944, 119.710353, 0.128368,
                                     -0.726078,  0.006426,   -0.002841,  0.0};
  ASSERT_EQ(camera.params.size(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) EXPECT_DOUBLE_EQ(camera.params[i], expected[i]) << i;
}

TEST(CameraFormats, ReadsVispsOwnXml) {
  MIRE_REQUIRE_SHARED(kCameraFiles / "visp_camera.xml");
  const auto path = test::sharedDir() / kCameraFiles / "visp_camera.xml";
  EXPECT_EQ(detectCameraFormat(path), CameraFormat::Visp);
  const Camera camera = readCamera(path);
  EXPECT_EQ(camera.width, 640);
  EXPECT_EQ(camera.height, 480);
  EXPECT_NEAR(camera.fx(), 605.1467, 1e-4);
  EXPECT_NEAR(camera.fy(), 604.7915, 1e-4);
  EXPECT_NEAR(camera.cx(), 325.5325, 1e-4);
  EXPECT_NEAR(camera.cy(), 244.9508, 1e-4);
  ASSERT_EQ(camera.distortionCount(), 5);
  EXPECT_EQ(camera.params[4], 0.0);  // kud
}

TEST(CameraFormats, ReadsARealKalibrCamchain) {
  MIRE_REQUIRE_SHARED(kCameraFiles / "kalibr_camchain.yaml");
  const auto path = test::sharedDir() / kCameraFiles / "kalibr_camchain.yaml";
  EXPECT_EQ(detectCameraFormat(path), CameraFormat::Kalibr);
  const Camera camera = readCamera(path);
  expectSameCamera(camera, fisheyeCamera(), 1e-12);
  EXPECT_NEAR(camera.fx(), 277.956, 1e-3);
  EXPECT_NEAR(camera.fy(), 278.417, 1e-3);
  EXPECT_NEAR(camera.cx(), 315.527, 1e-3);
  EXPECT_NEAR(camera.cy(), 244.469, 1e-3);
}

// ---- round trips ---------------------------------------------------------------------------

TEST(CameraFormats, CameraYamlToRosAndBackIsExact) {
  const test::TempDir dir;
  for (const Camera& camera : everyKindOfCamera()) {
    writeText(dir.path() / "camera.yaml", cameraYamlString(camera));
    const Camera from_yaml = readCamera(dir.path() / "camera.yaml");
    writeText(dir.path() / "ros.yaml", cameraRosYamlString(from_yaml, "cam"));
    EXPECT_EQ(detectCameraFormat(dir.path() / "ros.yaml"), CameraFormat::Ros);
    const Camera back = readCamera(dir.path() / "ros.yaml");
    expectSameCamera(back, camera, 1e-9);
    EXPECT_EQ(back.params, camera.params);  // in fact bit-exact
  }
}

TEST(CameraFormats, CameraYamlToVispAndBackIsExactInVispsTerms) {
  const test::TempDir dir;
  // ViSP's model: px py u0 v0 and one radial term (kud = OpenCV's k1).
  Camera one_term = openCvCamera(5);
  one_term.params = {817.2043010752688, 816.5, 511.5, 383.25, -0.21, 0.0, 0.0, 0.0, 0.0};
  for (const Camera& camera : {one_term, openCvCamera(0)}) {
    writeText(dir.path() / "camera.yaml", cameraYamlString(camera));
    writeText(dir.path() / "camera.xml",
              cameraString(readCamera(dir.path() / "camera.yaml"), CameraFormat::Visp, "cam"));
    const Camera back = readCamera(dir.path() / "camera.xml");
    expectSameCamera(back, camera, 1e-9);
  }
  // A richer lens keeps px py u0 v0 exactly; its k1 becomes the fitted single term.
  writeText(dir.path() / "rich.xml", cameraVispXmlString(openCvCamera(5), "cam"));
  const Camera rich = readCamera(dir.path() / "rich.xml");
  for (int i = 0; i < 4; ++i)
    EXPECT_EQ(rich.params[static_cast<std::size_t>(i)], openCvCamera(5).params[static_cast<std::size_t>(i)]);
  EXPECT_LT(rich.params[4], 0.0);
}

TEST(CameraFormats, KalibrRoundTripAndRefusals) {
  const test::TempDir dir;
  for (const Camera& camera : {openCvCamera(4), openCvCamera(0), fisheyeCamera()}) {
    writeText(dir.path() / "camchain.yaml", cameraKalibrYamlString(camera));
    expectSameCamera(readCamera(dir.path() / "camchain.yaml"), camera, 0.0);
  }
  // Kalibr's radtan has k1 k2 p1 p2 only: a zero k3 is dropped, a non-zero one refused.
  Camera zero_k3 = openCvCamera(5);
  zero_k3.params[8] = 0.0;
  EXPECT_NO_THROW(cameraKalibrYamlString(zero_k3));
  EXPECT_THROW(cameraKalibrYamlString(openCvCamera(5)), std::invalid_argument);
  EXPECT_THROW(cameraMrcalString(fisheyeCamera()), std::invalid_argument);
  EXPECT_THROW(cameraVispXmlString(fisheyeCamera(), "cam"), std::invalid_argument);
}

// Every kind of camera through every format: where conversionLoss says the format holds the
// model, the file reads back bit for bit (parameters, lens, size); where it does not, the
// conversion is refused (no model for it at all) or named lossy with the terms it would drop.
TEST(CameraFormats, EveryFormatRoundTripIsExactOrRefused) {
  const test::TempDir dir;
  const CameraFormat formats[] = {CameraFormat::OpenCV, CameraFormat::Ros, CameraFormat::Visp, CameraFormat::Kalibr,
                                  CameraFormat::Mrcal};
  int exact = 0, lossy = 0, refused = 0;
  for (const Camera& camera : everyKindOfCamera()) {
    for (const CameraFormat format : formats) {
      const std::string what = camera.modelName() + " as " + cameraFormatName(format);
      std::optional<ConversionLoss> loss;
      try {
        loss = conversionLoss(camera, format);
      } catch (const std::invalid_argument&) {
        ++refused;
        EXPECT_THROW(cameraString(camera, format, "cam"), std::invalid_argument) << what;
        continue;
      }
      if (!loss->exact()) {
        ++lossy;
        EXPECT_GT(loss->max_px, 0.0) << what;
        continue;
      }
      ++exact;
      const auto path = dir.path() / (format == CameraFormat::Visp    ? "c.xml"
                                      : format == CameraFormat::Mrcal ? "c.cameramodel"
                                                                      : "c.yaml");
      writeText(path, cameraString(camera, format, "cam"));
      EXPECT_EQ(detectCameraFormat(path), format) << what;
      const Camera back = readCamera(path);
      EXPECT_EQ(back.lens, camera.lens) << what;
      EXPECT_EQ(back.params, camera.params) << what;
      EXPECT_EQ(back.width, camera.width) << what;
      EXPECT_EQ(back.height, camera.height) << what;
    }
  }
  std::printf("round trips: %d exact, %d lossy (refused without --lossy), %d refused (no such model)\n", exact, lossy,
              refused);
  EXPECT_GE(exact, 18);
  EXPECT_GT(lossy, 0);
  EXPECT_GT(refused, 0);
}

// ---- other tools read what mire writes -------------------------------------------------------

TEST(CameraFormats, OpenCvFileStorageReadsCameraYaml) {
  const test::TempDir dir;
  for (const Camera& camera : everyKindOfCamera()) {
    const auto path = dir.path() / "camera.yaml";
    writeText(path, cameraYamlString(camera));
    cv::FileStorage storage(path.string(), cv::FileStorage::READ);
    ASSERT_TRUE(storage.isOpened());
    EXPECT_EQ(static_cast<int>(storage["image_width"]), camera.width);
    EXPECT_EQ(static_cast<int>(storage["image_height"]), camera.height);
    cv::Mat k, d;
    storage["camera_matrix"] >> k;
    storage["distortion_coefficients"] >> d;
    ASSERT_EQ(k.rows, 3);
    EXPECT_EQ(k.at<double>(0, 0), camera.fx());
    EXPECT_EQ(k.at<double>(1, 1), camera.fy());
    EXPECT_EQ(k.at<double>(0, 2), camera.cx());
    EXPECT_EQ(k.at<double>(1, 2), camera.cy());
    const int count = camera.distortionCount() == 0 ? 5 : camera.distortionCount();  // pinhole: OpenCV's 5 zeros
    ASSERT_EQ(static_cast<int>(d.total()), count);
    for (int i = 0; i < camera.distortionCount(); ++i)
      EXPECT_EQ(d.at<double>(i), camera.params[static_cast<std::size_t>(kIntrinsicCount + i)]);
  }
}

TEST(CameraFormats, PyYamlReadsTheYamlFilesMireWrites) {
  if (!pythonHas("yaml")) GTEST_SKIP() << "needs python3-yaml (Debian), absent: skipped";
  const test::TempDir dir;
  Camera camera = openCvCamera(5);
  camera.covariance = Eigen::MatrixXd::Identity(9, 9) * 1e-6;
  writeText(dir.path() / "camera.yaml", cameraYamlString(camera));
  writeText(dir.path() / "ros.yaml", cameraRosYamlString(camera, "cam"));
  writeText(dir.path() / "kalibr.yaml", cameraKalibrYamlString(openCvCamera(4)));
  // ROS and Kalibr: plain YAML; every number is a float for PyYAML (YAML 1.1).
  for (const char* name : {"ros.yaml", "kalibr.yaml"}) {
    const std::string out = capture(std::string(kPython) +
                                    " -c \"import yaml,sys; d=yaml.safe_load(open(sys.argv[1])); "
                                    "print('ok', type(d).__name__)\" " +
                                    (dir.path() / name).string() + " 2>&1");
    EXPECT_EQ(out, "ok dict\n") << name;
  }
  const std::string fx = capture(std::string(kPython) +
                                 " -c \"import yaml,sys; d=yaml.safe_load(open(sys.argv[1])); "
                                 "print(d['camera_matrix']['data'][0] == 817.2043010752688)\" " +
                                 (dir.path() / "ros.yaml").string());
  EXPECT_EQ(fx, "True\n");
  // camera.yaml: PyYAML stops only at OpenCV's !!opencv-matrix tag; with a constructor for
  // that tag it reads the whole file.
  const std::string plain =
      capture(std::string(kPython) + " -c \"import yaml,sys; yaml.safe_load(open(sys.argv[1]))\" " +
              (dir.path() / "camera.yaml").string() + " 2>&1");
  EXPECT_NE(plain.find("opencv-matrix"), std::string::npos) << plain;
  const std::string tagged =
      capture(std::string(kPython) +
              " -c \"import yaml,sys; yaml.SafeLoader.add_constructor('tag:yaml.org,2002:opencv-matrix', "
              "lambda l, n: l.construct_mapping(n, deep=True)); d=yaml.safe_load(open(sys.argv[1])); "
              "print(d['model'], d['camera_matrix']['data'][0] == 817.2043010752688, len(d['sigma']), "
              "d['covariance']['rows'])\" " +
              (dir.path() / "camera.yaml").string() + " 2>&1");
  EXPECT_EQ(tagged, "opencv5 True 9 9\n");
}

TEST(CameraFormats, MrcalReadsTheCameramodelMireWrites) {
  if (!pythonHas("mrcal")) GTEST_SKIP() << "needs python3-mrcal (Debian), absent: skipped";
  const test::TempDir dir;
  const std::vector<int> counts{0, 4, 5, 8, 12};
  std::string paths;
  for (const int count : counts) {
    const auto path = dir.path() / ("camera" + std::to_string(count) + ".cameramodel");
    writeText(path, cameraMrcalString(openCvCamera(count)));
    paths += " " + path.string();
  }
  // One interpreter for all files (importing mrcal takes a second).
  const std::string out =
      capture(std::string(kPython) +
              " -c \"import mrcal,sys\nfor p in sys.argv[1:]:\n m=mrcal.cameramodel(p); l,i=m.intrinsics(); "
              "print(l, ' '.join(repr(float(x)) for x in i), *m.imagersize())\" " +
              paths + " 2>&1");
  std::istringstream in(out);
  for (const int count : counts) {
    const Camera camera = openCvCamera(count);
    std::string lensmodel;
    in >> lensmodel;
    EXPECT_EQ(lensmodel, count == 0 ? "LENSMODEL_PINHOLE" : "LENSMODEL_OPENCV" + std::to_string(count)) << out;
    for (const double expected : camera.params) {
      double value = 0.0;
      in >> value;
      EXPECT_EQ(value, expected) << out;
    }
    int width = 0, height = 0;
    in >> width >> height;
    EXPECT_EQ(width, 1024);
    EXPECT_EQ(height, 768);
  }
}

// ---- OpenCV's own key variants -----------------------------------------------------------------

// An mrcal-written model of every lens model mire shares with mrcal reads back as the equivalent
// camera.yaml: mrcal prints 10 significant digits, so the intrinsics agree to 1e-9 relative and
// the projections over the whole image to 1e-5 px (a pose from them: well below 1 µm).
TEST(CameraFormats, ReadsTheCameramodelMrcalWrites) {
  if (!pythonHas("mrcal")) GTEST_SKIP() << "needs python3-mrcal (Debian), absent: skipped";
  const test::TempDir dir;
  std::string script = "import mrcal, numpy as np\n";
  for (const int count : {0, 4, 5, 8, 12}) {
    const Camera camera = openCvCamera(count);
    std::string values;
    for (const double value : camera.params) values += support::formatYamlNumber(value) + ",";
    script += "mrcal.cameramodel(intrinsics=('" +
              std::string(count == 0 ? "LENSMODEL_PINHOLE" : "LENSMODEL_OPENCV" + std::to_string(count)) +
              "', np.array([" + values + "])), imagersize=(1024, 768)).write('" +
              (dir.path() / ("m" + std::to_string(count) + ".cameramodel")).string() + "')\n";
  }
  writeText(dir.path() / "write.py", script);
  ASSERT_EQ(capture(std::string(kPython) + " " + (dir.path() / "write.py").string() + " 2>&1"), "");
  for (const int count : {0, 4, 5, 8, 12}) {
    const auto path = dir.path() / ("m" + std::to_string(count) + ".cameramodel");
    EXPECT_EQ(detectCameraFormat(path), CameraFormat::Mrcal);
    const Camera read = readCamera(path);
    const Camera expected = openCvCamera(count);
    ASSERT_EQ(read.params.size(), expected.params.size());
    for (std::size_t i = 0; i < read.params.size(); ++i)
      EXPECT_NEAR(read.params[i], expected.params[i], 1e-9 * std::abs(expected.params[i])) << count << " " << i;
    EXPECT_EQ(read.width, 1024);
    EXPECT_EQ(read.height, 768);
    double worst = 0.0;
    for (int v = 0; v <= 768; v += 32)
      for (int u = 0; u <= 1024; u += 32) {
        Eigen::Vector2d ray, back;
        if (!expected.unproject({u - 0.5, v - 0.5}, &ray) || !read.project({ray.x(), ray.y(), 1.0}, &back)) continue;
        worst = std::max(worst, (back - Eigen::Vector2d(u - 0.5, v - 0.5)).norm());
      }
    EXPECT_LT(worst, 1e-5) << count;
  }
}

TEST(CameraFormats, MrcalRoundTripKeepsCovarianceAndName) {
  const test::TempDir dir;
  Camera camera = openCvCamera(12);
  camera.name = "left 'cam'";
  camera.rms_px = 0.042;
  const auto n = static_cast<Eigen::Index>(camera.params.size());
  const Eigen::MatrixXd a = Eigen::MatrixXd::Random(n, n);
  camera.covariance = 1e-3 * a * a.transpose();
  writeText(dir.path() / "c.cameramodel", cameraMrcalString(camera));
  const Camera back = readCamera(dir.path() / "c.cameramodel");
  EXPECT_EQ(back.params, camera.params);
  EXPECT_EQ(back.name, camera.name);
  EXPECT_EQ(back.rms_px, camera.rms_px);
  EXPECT_EQ(back.covariance, camera.covariance);
}

TEST(CameraFormats, MrcalModelsMireDoesNotHaveAreRefusedByName) {
  const test::TempDir dir;
  const auto error = [&](const std::string& text) {
    writeText(dir.path() / "m.cameramodel", text);
    try {
      readCamera(dir.path() / "m.cameramodel");
    } catch (const std::runtime_error& e) {
      return std::string(e.what()).substr((dir.path() / "m.cameramodel").string().size());
    }
    return std::string("no error");
  };
  EXPECT_EQ(error("# c\n{\n  'lensmodel': 'LENSMODEL_SPLINED_STEREOGRAPHIC_order=3_Nx=30_Ny=18_fov_x_deg=150',\n"
                  "  'intrinsics': [1, 2, 3, 4],\n  'imagersize': [640, 480],\n}\n"),
            ":3: lens model 'LENSMODEL_SPLINED_STEREOGRAPHIC_order=3_Nx=30_Ny=18_fov_x_deg=150' is not one mire has "
            "(it reads LENSMODEL_PINHOLE and LENSMODEL_OPENCV4, 5, 8, 12); convert it with mrcal-convert-lensmodel to "
            "one of those");
  EXPECT_EQ(error("{'lensmodel': 'LENSMODEL_CAHVOR', 'intrinsics': [], 'imagersize': [640, 480]}").substr(0, 36),
            ":1: lens model 'LENSMODEL_CAHVOR' is");
  EXPECT_EQ(error("{'lensmodel': 'LENSMODEL_OPENCV4',\n 'intrinsics': [500, 500, 320, 240, 0.1],\n"
                  " 'imagersize': [640, 480]}"),
            ":2: key 'intrinsics': 5 values, the lens model has 8 (fx fy cx cy and 4 coefficients)");
  EXPECT_EQ(error("{'lensmodel': 'LENSMODEL_PINHOLE',\n 'intrinsics': [500, 500, 320, 240],\n}"),
            ":1: missing key 'imagersize' (an mrcal .cameramodel has it)");
  EXPECT_EQ(error("{'lensmodel': 'LENSMODEL_PINHOLE', 'intrinsics': [500, 500, 320, x1]}"), ":1: 'x1' is not a number");
}

TEST(CameraFormats, ReadsOpenCvsKeyVariants) {
  const test::TempDir dir;
  const auto path = dir.path() / "c.yaml";
  const Camera expected = cameraFromOpenCV(640, 480, 500.0, 501.0, 320.0, 240.0, {-0.1, 0.01, 0.0, 0.0, 0.001});
  const std::string k = "[ 500., 0., 320., 0., 501., 240., 0., 0., 1. ]";
  const std::string d = "[ -0.1, 0.01, 0., 0., 0.001 ]";
  const std::string matrix_k = "!!opencv-matrix\n  rows: 3\n  cols: 3\n  dt: d\n  data: " + k + "\n";
  const std::string matrix_d = "!!opencv-matrix\n  rows: 1\n  cols: 5\n  dt: d\n  data: " + d + "\n";
  const std::vector<std::string> files{
      // OpenCV's interactive-calibration app
      "%YAML:1.0\n---\ncalibrationDate: \"Mon Nov 23\"\nframesCount: 20\ncameraResolution: [ 640, 480 ]\n"
      "cameraMatrix: " +
          matrix_k + "cameraMatrix_std_dev: " + matrix_d +
          "avg_reprojection_error: 0.2\n"
          "dist_coeffs: " +
          matrix_d,
      // OpenCV's tutorial camera_calibration
      "%YAML:1.0\n---\ncalibration_time: \"x\"\nnr_of_frames: 25\nimage_width: 640\nimage_height: 480\n"
      "board_width: 9\nboard_height: 6\nsquare_size: 50.\nflags: 0\ncamera_matrix: " +
          matrix_k + "distortion_coefficients: " + matrix_d + "avg_reprojection_error: 0.3\n",
      // short names, plain lists
      "width: 640\nheight: 480\nK: " + k + "\nD: " + d + "\n",
      "image_size: [640, 480]\ncamera_matrix: [[500, 0, 320], [0, 501, 240], [0, 0, 1]]\ndistCoeffs: " + d + "\n",
  };
  for (const std::string& text : files) {
    writeText(path, text);
    SCOPED_TRACE(text);
    expectSameCamera(readCamera(path), expected, 0.0);
  }
}

// ---- one camera.yaml in every YAML syntax: a test per variant ----------------------------------

const char* kPlainCamera =
    "image_width: 1024\nimage_height: 768\nmodel: opencv5\n"
    "camera_matrix: !!opencv-matrix\n  rows: 3\n  cols: 3\n  dt: d\n"
    "  data: [817.2043010752688, 0.0, 511.5, 0.0, 817.2043010752688, 383.5, 0.0, 0.0, 1.0]\n"
    "distortion_coefficients: !!opencv-matrix\n  rows: 5\n  cols: 1\n  dt: d\n  data: [-0.30, 0.10, 4.0e-4, -3.0e-4, "
    "-0.015]\n";

Camera referenceCamera() { return readCamera(test::sourceDir() / "datasets/specs/reference_camera.yaml"); }

void expectVariantLoads(const std::string& text) {
  const test::TempDir dir;
  writeText(dir.path() / "camera.yaml", text);
  const Camera camera = readCamera(dir.path() / "camera.yaml");
  expectSameCamera(camera, referenceCamera(), 0.0);
}

std::string withCrlf(std::string text) {
  std::string out;
  for (const char c : text) out += c == '\n' ? std::string("\r\n") : std::string(1, c);
  return out;
}

TEST(CameraYamlVariants, OpenCvHeader) { expectVariantLoads(std::string("%YAML:1.0\n---\n") + kPlainCamera); }
TEST(CameraYamlVariants, PlainYaml) { expectVariantLoads(kPlainCamera); }
TEST(CameraYamlVariants, DocumentMarkerOnly) { expectVariantLoads(std::string("---\n") + kPlainCamera); }
TEST(CameraYamlVariants, Yaml12Directive) {
  expectVariantLoads(std::string("%YAML 1.2\n---\n") + kPlainCamera + "...\n");
}
TEST(CameraYamlVariants, Crlf) { expectVariantLoads(withCrlf(std::string("%YAML:1.0\n---\n") + kPlainCamera)); }
TEST(CameraYamlVariants, Bom) { expectVariantLoads(std::string("\xEF\xBB\xBF") + kPlainCamera); }
TEST(CameraYamlVariants, FlowStyle) {
  expectVariantLoads(
      "{image_width: 1024, image_height: 768, model: opencv5, camera_matrix: {rows: 3, cols: 3, dt: d, data: "
      "[817.2043010752688, 0, 511.5, 0, 817.2043010752688, 383.5, 0, 0, 1]}, distortion_coefficients: "
      "[-0.30, 0.10, 4.0e-4, -3.0e-4, -0.015]}\n");
}
TEST(CameraYamlVariants, CommentsEverywhere) {
  expectVariantLoads(
      "# a camera\nimage_width: 1024   # px\nimage_height: 768 # px\n# the model\nmodel: opencv5 # five\n"
      "camera_matrix: # K\n  # rows first\n  rows: 3 # three\n  cols: 3\n  dt: d\n"
      "  data: [817.2043010752688, 0.0, 511.5,  # first row\n         0.0, 817.2043010752688, 383.5,\n"
      "         0.0, 0.0, 1.0]  # last\n"
      "distortion_coefficients:\n  - -0.30   # k1\n  - 0.10\n  - 4.0e-4\n  - -3.0e-4\n  - -0.015 # k3\n# end\n");
}

// ---- errors: file, line, key ---------------------------------------------------------------

std::string readError(const std::string& text) {
  const test::TempDir dir;
  writeText(dir.path() / "cam.yaml", text);
  try {
    readCamera(dir.path() / "cam.yaml");
  } catch (const std::runtime_error& e) {
    const std::string message = e.what();
    const std::string prefix = (dir.path() / "cam.yaml").string();
    return message.rfind(prefix, 0) == 0 ? "cam.yaml" + message.substr(prefix.size()) : message;
  }
  return "(no error)";
}

TEST(CameraFormats, ErrorsNameFileLineAndKey) {
  const std::string plain = kPlainCamera;
  EXPECT_EQ(readError(plain + "rms_pz: 0.1\n"), "cam.yaml:14: unknown key 'rms_pz' (did you mean 'rms_px'?)");
  EXPECT_EQ(readError(plain + "image_width: 640\n"), "cam.yaml:14: key 'image_width' appears twice (first at line 1)");
  EXPECT_EQ(readError("image_width: 3000000000\n" + plain.substr(plain.find('\n') + 1)),
            "cam.yaml:1: key 'image_width': 3000000000 is out of range (1..100000)");
  std::string k1 = plain;
  k1.replace(k1.find("-0.30"), 5, "1e6");
  EXPECT_EQ(readError(k1), "cam.yaml:13: key 'distortion_coefficients.data[0]': 1e+06 is out of range (-10000..10000)");
  std::string cx = plain;
  cx.replace(cx.find("511.5"), 5, "-5000");
  EXPECT_EQ(readError(cx),
            "cam.yaml:4: key 'camera_matrix': principal point (-5000, 383.5) px is far outside the 1024 x 768 image");
  EXPECT_EQ(readError(plain + "model: fisheye\n").substr(0, 9), "cam.yaml:");
  std::string fisheye = plain;
  fisheye.replace(fisheye.find("opencv5"), 7, "fisheye");
  EXPECT_EQ(readError(fisheye), "cam.yaml:3: key 'model': 'fisheye' needs 4 coefficients k1..k4, the file has 5");
  EXPECT_EQ(readError(plain + "distortion_model: plumb_bob\nD: [0, 0, 0, 0, 0]\n"),
            "cam.yaml:15: key 'D': given twice, as 'distortion_coefficients' and as 'D'");
  EXPECT_EQ(readError(""), "cam.yaml: empty file (expected a map of keys)");
  EXPECT_EQ(readError("{'lensmodel': 'LENSMODEL_OPENCV5'}\n"),
            "cam.yaml:1: missing key 'intrinsics' (an mrcal .cameramodel has it)");
}

}  // namespace
}  // namespace mire::calibration
