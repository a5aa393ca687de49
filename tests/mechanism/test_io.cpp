// Identification files (doc/file-formats.md): poses.csv (+ covariance side file), joints.csv,
// lines.csv and the parameter YAML; every error names the file and line.
#include <gtest/gtest.h>

#include "mire/mechanism/h4.hpp"
#include "mire/mechanism/io.hpp"
#include "mire/support/side_files.hpp"
#include "test_support.hpp"

#include <fstream>

namespace mire::mechanism {
namespace {

namespace fs = std::filesystem;

const char* kHeader =
    "pose_id,images_used,images_total,tx_m,ty_m,tz_m,rx_rad,ry_rad,rz_rad,sigma_tx_mm,sigma_ty_mm,sigma_tz_mm,"
    "sigma_rx_deg,sigma_ry_deg,sigma_rz_deg,rms_px,extra\n";

TEST(PosesCsv, ReadsColumnsAndDiagonalCovariance) {
  test::TempDir dir;
  test::writeText(dir.path() / "poses.csv", std::string(kHeader) +
                                                "a,10,10,0.1,0.2,0.8,0.01,0.02,0.03,0.2,0.2,0.4,0.03,0.03,0.06,0.1,7\n"
                                                "b,10,10,0.1,0.2,0.8,0.01,0.02,0.03,0,0,0,0,0,0,0.1,7\n");
  const auto rows = readPosesCsv(dir.path() / "poses.csv");
  ASSERT_EQ(rows.size(), 2U);
  EXPECT_EQ(rows[0].observation.id, "a");
  EXPECT_EQ(rows[0].line, 2);
  EXPECT_DOUBLE_EQ(rows[0].observation.cTm[2], 0.8);
  ASSERT_TRUE(rows[0].observation.covariance.has_value());
  EXPECT_NEAR((*rows[0].observation.covariance)(2, 2), 0.4e-3 * 0.4e-3, 1e-18);
  EXPECT_NEAR((*rows[0].observation.covariance)(5, 5), std::pow(0.06 * M_PI / 180, 2), 1e-18);
  EXPECT_FALSE(rows[1].observation.covariance.has_value());  // zero σ: no covariance
}

TEST(PosesCsv, SideFileCovariance) {
  test::TempDir dir;
  test::writeText(dir.path() / "poses.csv",
                  std::string(kHeader) + "7,10,10,0.1,0.2,0.8,0.01,0.02,0.03,0.2,0.2,0.4,0.03,0.03,0.06,0.1,0\n");
  std::string side = "pose_id,part,row,tx,ty,tz,rx,ry,rz\n";
  const char* axes[6] = {"tx", "ty", "tz", "rx", "ry", "rz"};
  for (const char* part : {"noise", "total"})
    for (int r = 0; r < 6; ++r) {
      side += std::string("7,") + part + "," + axes[r];
      for (int c = 0; c < 6; ++c) side += r == c ? (part[0] == 't' ? ",2e-8" : ",1e-8") : (r + c == 5 ? ",1e-9" : ",0");
      side += "\n";
    }
  test::writeText(mire::support::covarianceSidePath(dir.path() / "poses.csv"), side);
  EXPECT_EQ(mire::support::covarianceSidePath(dir.path() / "poses.csv").filename(), "poses_covariance.csv");
  const auto rows = readPosesCsv(dir.path() / "poses.csv", mire::support::covarianceSidePath(dir.path() / "poses.csv"));
  ASSERT_TRUE(rows[0].observation.covariance.has_value());
  EXPECT_DOUBLE_EQ((*rows[0].observation.covariance)(0, 0), 2e-8);
  EXPECT_DOUBLE_EQ((*rows[0].observation.covariance)(0, 5), 1e-9);
}

TEST(PosesCsv, ErrorsNameFileAndLine) {
  test::TempDir dir;
  const auto p = dir.path() / "poses.csv";
  test::writeText(p, std::string(kHeader) +
                         "a,10,10,0.1,0.2,0.8,0.01,0.02,0.03,0.2,0.2,0.4,0.03,0.03,0.06,0.1,0\n"
                         "a,10,10,0.1,0.2,0.8,0.01,0.02,0.03,0.2,0.2,0.4,0.03,0.03,0.06,0.1,0\n");
  std::string e = test::errorOf([&] { readPosesCsv(p); });
  EXPECT_NE(e.find("poses.csv:3"), std::string::npos) << e;
  EXPECT_NE(e.find("duplicate pose_id 'a'"), std::string::npos) << e;
  test::writeText(p, std::string(kHeader) + "a,10,10,0.1,nan,0.8,0.01,0.02,0.03,0.2,0.2,0.4,0.03,0.03,0.06,0.1,0\n");
  e = test::errorOf([&] { readPosesCsv(p); });
  EXPECT_NE(e.find("poses.csv:2"), std::string::npos) << e;
  EXPECT_NE(e.find("ty_m"), std::string::npos) << e;
  test::writeText(p, "pose_id,tx_m\na,1\n");
  e = test::errorOf([&] { readPosesCsv(p); });
  EXPECT_NE(e.find("missing column"), std::string::npos) << e;
}

TEST(Observations, PoseWithoutJointsIsAnError) {
  test::TempDir dir;
  test::writeText(dir.path() / "poses.csv",
                  std::string(kHeader) +
                      "a,10,10,0.1,0.2,0.8,0.01,0.02,0.03,0.2,0.2,0.4,0.03,0.03,0.06,0.1,0\n"
                      "b,10,10,0.1,0.2,0.8,0.01,0.02,0.03,0.2,0.2,0.4,0.03,0.03,0.06,0.1,0\n");
  test::writeText(dir.path() / "joints.csv", "pose_id,q1_rad,q2_rad,q3_rad,q4_rad\na,0.1,0.2,0.3,0.4\nz,0,0,0,0\n");
  const std::string e = test::errorOf([&] { readObservations(dir.path() / "poses.csv", dir.path() / "joints.csv"); });
  EXPECT_NE(e.find("poses.csv:3"), std::string::npos) << e;
  EXPECT_NE(e.find("pose 'b' has no joints"), std::string::npos) << e;
  test::writeText(dir.path() / "joints.csv",
                  "pose_id,q1_rad,q2_rad,q3_rad,q4_rad\na,0.1,0.2,0.3,0.4\nb,0,0,0,0\nz,0,0,0,0\n");
  const auto set = readObservations(dir.path() / "poses.csv", dir.path() / "joints.csv");
  ASSERT_EQ(set.poses.size(), 2U);
  EXPECT_DOUBLE_EQ(set.poses[0].joints[3], 0.4);
  ASSERT_EQ(set.unused_joint_ids.size(), 1U);
  EXPECT_EQ(set.unused_joint_ids[0], "z");
}

// Joints listed in another order than the poses are paired by id, not by row; the same order
// (as mire writes them) is paired row by row. Both give each pose its own joints.
TEST(Observations, JointsArePairedByIdInAnyOrder) {
  test::TempDir dir;
  const std::string row = ",10,10,0.1,0.2,0.8,0.01,0.02,0.03,0.2,0.2,0.4,0.03,0.03,0.06,0.1,0\n";
  test::writeText(dir.path() / "poses.csv", std::string(kHeader) + "a" + row + "b" + row + "c" + row);
  for (const std::string joints : {"a,1,0,0,0\nb,2,0,0,0\nc,3,0,0,0\n", "c,3,0,0,0\na,1,0,0,0\nb,2,0,0,0\n"}) {
    test::writeText(dir.path() / "joints.csv", "pose_id,q1_rad,q2_rad,q3_rad,q4_rad\n" + joints);
    const auto set = readObservations(dir.path() / "poses.csv", dir.path() / "joints.csv");
    ASSERT_EQ(set.poses.size(), 3U);
    EXPECT_TRUE(set.unused_joint_ids.empty());
    for (std::size_t k = 0; k < 3; ++k) {
      EXPECT_EQ(set.poses[k].id, std::string(1, char('a' + k)));
      EXPECT_DOUBLE_EQ(set.poses[k].joints[0], double(k + 1)) << joints;
    }
  }
}

TEST(JointsAndLines, RoundTrip) {
  test::TempDir dir;
  const std::vector<Eigen::VectorXd> q{Eigen::Vector4d(0.1, -0.2, 1.0 / 3.0, 0.4), Eigen::Vector4d(1, 2, 3, 4)};
  writeJointsCsv(dir.path() / "joints.csv", {"p1", "p2"}, q);
  const auto rows = readJointsCsv(dir.path() / "joints.csv");
  ASSERT_EQ(rows.size(), 2U);
  EXPECT_EQ(rows[0].joints, q[0]);
  writeLinesCsv(dir.path() / "lines.csv", {{"1", {q[0], q[1], q[0]}}, {"2", {q[1], q[0], q[1]}}});
  const auto lines = readLinesCsv(dir.path() / "lines.csv");
  ASSERT_EQ(lines.size(), 2U);
  EXPECT_EQ(lines[1].joints[2], q[1]);
  test::writeText(dir.path() / "bad.csv", "line_id,q1_rad,q2_rad,q3_rad,q4_rad\n1,0,0,0,0\n1,0,0,0,0\n");
  EXPECT_NE(test::errorOf([&] { readLinesCsv(dir.path() / "bad.csv"); }).find("at least 3"), std::string::npos);
}

TEST(ParameterFile, WriteReadRoundTripAndErrors) {
  test::TempDir dir;
  ParameterSet parameters = h4Model12Parameters(H4Nominal{});
  parameters.setValue("L", 0.3012345678901234);
  Eigen::VectorXd sigma = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(parameters.size()));
  sigma[1] = 1e-4;
  const auto path = dir.path() / "p.yaml";
  writeParameterFile(path, parameters, sigma, {{"model", "h4-12"}}, "test");
  const ParameterFile file = readParameterFile(path);
  ASSERT_NE(file.find("sigma_L"), nullptr);
  EXPECT_EQ(file.find("sigma_R"), nullptr);  // σ = 0: not written
  EXPECT_EQ(file.find("model")->text, "h4-12");
  ParameterSet back = h4Model12Parameters(H4Nominal{});
  applyParameterFile(file, back);
  EXPECT_EQ(back.values(), parameters.values());

  test::writeText(path, "R: 0.22\nfoo: 1\n");
  std::string e = test::errorOf([&] {
    ParameterSet p = h4Model12Parameters(H4Nominal{});
    applyParameterFile(readParameterFile(path), p);
  });
  EXPECT_NE(e.find("p.yaml:2"), std::string::npos) << e;
  EXPECT_NE(e.find("unknown parameter name 'foo'"), std::string::npos) << e;
  test::writeText(path, "R: 0.22\nL: .nan\n");
  e = test::errorOf([&] {
    ParameterSet p = h4Model12Parameters(H4Nominal{});
    applyParameterFile(readParameterFile(path), p);
  });
  EXPECT_NE(e.find("p.yaml:2"), std::string::npos) << e;
  EXPECT_NE(e.find("not a finite number"), std::string::npos) << e;
  test::writeText(path, "R: 0.22\nR: 0.23\n");
  EXPECT_NE(test::errorOf([&] { readParameterFile(path); }).find("p.yaml:2: key 'R' appears twice"), std::string::npos);
  test::writeText(path, "just text\n");
  EXPECT_NE(test::errorOf([&] { readParameterFile(path); }).find("p.yaml:1"), std::string::npos);
}

TEST(ParameterFile, DefaultNominalFileHoldsTheBriefValues) {
  const auto file = readParameterFile(test::sourceDir() / "datasets/specs/h4_nominal.yaml");
  ParameterSet p = h4Model12Parameters(H4Nominal{});
  p.setValues(Eigen::VectorXd::Zero(static_cast<Eigen::Index>(p.size())));
  applyParameterFile(file, p);
  EXPECT_EQ(p.values(), h4Model12Parameters(H4Nominal{}).values());
}

}  // namespace
}  // namespace mire::mechanism
