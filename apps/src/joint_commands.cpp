// Joint commands for desired effector poses (joint_commands.hpp).
#include "joint_commands.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "mire/support/csv.hpp"
#include "mire/support/progress.hpp"

namespace mire::app {

namespace mech = mire::mechanism;

JointCommandTable jointCommandTable(const mech::PredictionModel& model, const std::vector<EffectorRow>& rows,
                                    const std::string& poses_name) {
  const mech::Mechanism& m = *model.mechanism;
  const auto columns = m.jointColumnNames();
  JointCommandTable table;
  std::ostringstream out;
  out << "pose_id";
  for (const auto& c : columns) out << ',' << c;
  for (const auto& c : columns) out << ",sigma_" << c;
  out << '\n';
  support::Progress progress("joint commands", rows.size());
  for (const auto& row : rows) {
    progress.advance();
    const mech::JointPrediction p = mech::predictJointCommands(model, m.poseToTransform(row.pose));
    const std::string where = poses_name + ":" + std::to_string(row.line) + ": pose '" + row.id + "'";
    if (!p.ikm.reachable()) {
      std::string legs;
      for (int j : p.ikm.unreachable_joints) legs += (legs.empty() ? "" : ", ") + std::to_string(j + 1);
      table.unreachable.push_back(where + " is unreachable (joint(s) " + legs + ")");
      continue;
    }
    if (!p.ikm.withinStroke()) {  // the command would drive a leg past its end stop
      std::string legs;
      for (int j : p.ikm.out_of_stroke_joints)
        legs += (legs.empty() ? "" : ", ") + std::to_string(j + 1) + " (" + support::formatNumber(p.ikm.joints[j]) +
                " " + mech::unitName(m.jointUnits()[static_cast<std::size_t>(j)]) + ")";
      table.unreachable.push_back(where + " is outside the stroke of joint(s) " + legs);
      continue;
    }
    out << row.id;
    for (Eigen::Index k = 0; k < p.ikm.joints.size(); ++k) out << ',' << support::formatNumber(p.ikm.joints[k]);
    for (Eigen::Index k = 0; k < p.ikm.joints.size(); ++k)
      out << ',' << support::formatNumber(std::sqrt(std::max(0.0, p.covariance(k, k))), 6);
    out << '\n';
    table.sigmas.push_back(p.covariance.diagonal().cwiseMax(0.0).cwiseSqrt());
    ++table.written;
  }
  progress.finish();
  table.csv = out.str();
  return table;
}

}  // namespace mire::app
