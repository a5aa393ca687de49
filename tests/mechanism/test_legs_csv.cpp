// legs.csv (doc/file-formats.md): round trip, and errors naming the file and line.
#include <gtest/gtest.h>

#include <functional>

#include "mire/mechanism/legs_csv.hpp"
#include "test_support.hpp"

namespace mire::mechanism {
namespace {

const char* kHeader = "pose_id,leg,dx,dy,dz,mx_m,my_m,mz_m,c11,c12,c13,c14,c22,c23,c24,c33,c34,c44\n";

TEST(LegsCsv, RoundTripsLinesAndCovariances) {
  test::TempDir dir;
  LegObservation o;
  o.pose_id = "p7";
  o.leg = 4;
  o.line = support::Line3d::throughPoints(Eigen::Vector3d(0.1, -0.2, 1.1), Eigen::Vector3d(0.05, 0.1, 0.9));
  Eigen::Matrix4d A = Eigen::Matrix4d::Random();
  o.covariance = 1e-6 * (A * A.transpose() + Eigen::Matrix4d::Identity());
  writeLegsCsv(dir.path() / "legs.csv", {o});
  const std::vector<LegObservation> back = readLegsCsv(dir.path() / "legs.csv", 6);
  ASSERT_EQ(back.size(), 1u);
  EXPECT_EQ(back[0].pose_id, "p7");
  EXPECT_EQ(back[0].leg, 4);
  EXPECT_LT((back[0].line.direction - o.line.direction).norm(), 1e-15);
  EXPECT_LT((back[0].line.moment - o.line.moment).norm(), 1e-15);
  EXPECT_LT((back[0].covariance - o.covariance).norm(), 1e-20);
}

TEST(LegsCsv, ErrorsNameFileAndLine) {
  test::TempDir dir;
  const auto p = dir.path() / "legs.csv";
  const std::string row = ",0,0,1,0.1,0.2,0,1e-6,0,0,0,1e-6,0,0,1e-6,0,1e-6\n";
  test::writeText(p, std::string(kHeader) + "a,1" + row + "a,7" + row);
  std::string e = test::errorOf([&] { readLegsCsv(p, 6); });
  EXPECT_NE(e.find("legs.csv:3"), std::string::npos) << e;
  EXPECT_NE(e.find("not a leg number 1..6"), std::string::npos) << e;
  test::writeText(p, std::string(kHeader) + "a,1" + row + "a,1" + row);
  e = test::errorOf([&] { readLegsCsv(p, 6); });
  EXPECT_NE(e.find("legs.csv:3"), std::string::npos) << e;
  EXPECT_NE(e.find("appears twice"), std::string::npos) << e;
  test::writeText(p, std::string(kHeader) + "a,1,0,0,2,0.1,0.2,0,1e-6,0,0,0,1e-6,0,0,1e-6,0,1e-6\n");
  e = test::errorOf([&] { readLegsCsv(p, 6); });
  EXPECT_NE(e.find("legs.csv:2"), std::string::npos) << e;
  EXPECT_NE(e.find("length 2"), std::string::npos) << e;
  test::writeText(p, std::string(kHeader) + "a,1,0,0,1,0.1,0.2,0.3,1e-6,0,0,0,1e-6,0,0,1e-6,0,1e-6\n");
  e = test::errorOf([&] { readLegsCsv(p, 6); });
  EXPECT_NE(e.find("not perpendicular"), std::string::npos) << e;
  test::writeText(p, std::string(kHeader) + "a,1,0,0,1,0.1,0.2,0,1e-6,0,0,0,-1e-6,0,0,1e-6,0,1e-6\n");
  e = test::errorOf([&] { readLegsCsv(p, 6); });
  EXPECT_NE(e.find("not positive definite"), std::string::npos) << e;
  test::writeText(p, "pose_id,leg\na,1\n");
  e = test::errorOf([&] { readLegsCsv(p, 6); });
  EXPECT_NE(e.find("legs.csv"), std::string::npos) << e;
  EXPECT_NE(e.find("dx"), std::string::npos) << e;
}

}  // namespace
}  // namespace mire::mechanism
