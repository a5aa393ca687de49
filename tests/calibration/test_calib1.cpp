// OpenCV's calib1.dat: 7 views of a 7×5 chessboard (2.54 cm squares, coordinates in cm) with
// the result of Bouguet's Camera Calibration Toolbox for MATLAB on the same points
// (../shared/datasets/external/README.md). No detector involved: the solver alone.
//
// Layout of the file (inspected): "640 480", "7 5", "7", then the 7 views' 35 object points
// (x y z, cm), then the 7 views' 35 image points (u v), then Bouguet's fc (2), cc (2),
// kc (4: k1 k2 p1 p2), the 7 rotation matrices (each 3×3 block as written is the TRANSPOSE of
// cRm: MATLAB's column order), the 7 translations (cTm, cm) and "pixel error" err = [0.10179 0.09492].
// What the file stores as the toolbox's "standard deviations": err is the toolbox's err_std =
// std(ex')', the one-sigma standard deviation of the reprojection residuals along x and y — a
// σ, not the 3σ "uncertainties" the toolbox prints beside fc/cc/kc (those are NOT in the
// file). So the σ check below compares our residual standard deviation per axis with err.
#include "mire/calibration/calibrate.hpp"

#include "sample_statistics.hpp"
#include "test_support.hpp"

#include <Eigen/Geometry>

#include <cmath>
#include <fstream>
#include <vector>

namespace {

struct Calib1 {
  int width = 0, height = 0;
  std::vector<std::vector<Eigen::Vector3d>> object_points;  // cm
  std::vector<std::vector<Eigen::Vector2d>> image_points;
  double fc[2], cc[2], kc[4];
  std::vector<Eigen::Matrix3d> rotations;
  std::vector<Eigen::Vector3d> translations;  // cm
  double err_std[2];
};

Calib1 readCalib1(const std::filesystem::path& path) {
  std::ifstream in(path);
  Calib1 data;
  int cols = 0, rows = 0, views = 0;
  in >> data.width >> data.height >> cols >> rows >> views;
  const int count = cols * rows;
  data.object_points.assign(views, std::vector<Eigen::Vector3d>(count));
  data.image_points.assign(views, std::vector<Eigen::Vector2d>(count));
  for (auto& view : data.object_points)
    for (auto& p : view) in >> p.x() >> p.y() >> p.z();
  for (auto& view : data.image_points)
    for (auto& p : view) in >> p.x() >> p.y();
  in >> data.fc[0] >> data.fc[1] >> data.cc[0] >> data.cc[1];
  for (double& k : data.kc) in >> k;
  data.rotations.resize(views);
  for (auto& r : data.rotations)
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) in >> r(i, j);
  data.translations.resize(views);
  for (auto& t : data.translations) in >> t.x() >> t.y() >> t.z();
  in >> data.err_std[0] >> data.err_std[1];
  if (!in) throw std::runtime_error("cannot parse " + path.string());
  return data;
}

}  // namespace

TEST(Calib1, MatchesBouguetToolbox) {
  MIRE_REQUIRE_SHARED("datasets/external/opencv-calib1/calib1.dat");
  const Calib1 data = readCalib1(mire::test::sharedDir() / "datasets/external/opencv-calib1/calib1.dat");
  ASSERT_EQ(data.object_points.size(), 7u);

  mire::calibration::CalibrationOptions options;
  options.model = mire::calibration::DistortionModel::OpenCV4;  // k1 k2 p1 p2, k3 = 0 as Bouguet
  const auto result =
      mire::calibration::calibrateCamera(data.object_points, data.image_points, data.width, data.height, options);
  const auto& p = result.camera.params;
  EXPECT_NEAR(p[0], data.fc[0], 0.1);
  EXPECT_NEAR(p[1], data.fc[1], 0.1);
  EXPECT_NEAR(p[2], data.cc[0], 0.1);
  EXPECT_NEAR(p[3], data.cc[1], 0.1);
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(p[4 + i], data.kc[i], 1e-3) << "kc" << i + 1;
  EXPECT_EQ(result.rejected_points, 0);
  EXPECT_EQ(result.used_views, 7);

  // Residual standard deviation per axis vs the toolbox's err_std (σ, see the file comment).
  std::vector<double> ex, ey;
  for (const auto& view : result.views)
    for (const auto& r : view.residuals) {
      ex.push_back(r.x());
      ey.push_back(r.y());
    }
  const double sx = mire::test::sampleStandardDeviation(ex), sy = mire::test::sampleStandardDeviation(ey);
  EXPECT_NEAR(sx / data.err_std[0], 1.0, 0.10) << sx;
  EXPECT_NEAR(sy / data.err_std[1], 1.0, 0.10) << sy;

  // Per-view poses (the file rounds to 4 decimals).
  for (std::size_t v = 0; v < 7; ++v) {
    const Eigen::Vector3d& r = result.views[v].rotation;
    const Eigen::Matrix3d rotation = Eigen::AngleAxisd(r.norm(), r.normalized()).toRotationMatrix();
    EXPECT_LT((rotation - data.rotations[v].transpose()).cwiseAbs().maxCoeff(), 2e-3) << "view " << v;
    EXPECT_LT((result.views[v].translation - data.translations[v]).cwiseAbs().maxCoeff(), 0.02) << "view " << v;
  }

  // σ of the parameters: Bouguet's formula is 3·std(all residual components)·sqrt(diag((JᵀJ)⁻¹))
  // printed as "uncertainty"; ours is σ·sqrt(diag((JᵀJ)⁻¹)) with σ² = SSR/(2N − n). The two σ
  // scales must agree within the (2N−1)/(2N−n) degrees-of-freedom factor (≈ 5 %).
  const double pooled = mire::test::sampleStandardDeviation([&] {
    std::vector<double> all = ex;
    all.insert(all.end(), ey.begin(), ey.end());
    return all;
  }());
  EXPECT_NEAR(result.sigma_px / pooled, 1.0, 0.10);
  const auto sigma = result.camera.sigmas();
  ASSERT_EQ(sigma.size(), 8u);
  for (double s : sigma) EXPECT_GT(s, 0.0);
  std::printf("calib1: fc %.5f %.5f (Bouguet %.5f %.5f) cc %.5f %.5f (%.5f %.5f)\n", p[0], p[1], data.fc[0], data.fc[1],
              p[2], p[3], data.cc[0], data.cc[1]);
  std::printf("calib1: kc %.5f %.5f %.5f %.5f; residual std %.5f %.5f (Bouguet %.5f %.5f); sigma_px %.5f\n", p[4], p[5],
              p[6], p[7], sx, sy, data.err_std[0], data.err_std[1], result.sigma_px);
  std::printf("calib1: 1-sigma fx %.3f fy %.3f cx %.3f cy %.3f k1 %.5f k2 %.5f p1 %.6f p2 %.6f\n", sigma[0], sigma[1],
              sigma[2], sigma[3], sigma[4], sigma[5], sigma[6], sigma[7]);
}
